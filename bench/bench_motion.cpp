// Motion benchmarks (issue 3), in the same steady_bench binary as the EAR benchmarks:
//   BM_MotionPose   Motion3::pose(t) along a 100-span polySAM, at 1024 random times in [0, 1]
//                   (one call per iteration: span lookup by binary search, then A^s B);
//   BM_Subdivide4   four rounds of four-point subdivision of 10 key poses (10 -> 145 poses),
//                   one whole subdivision per iteration.
// The key poses are those of chainedPoses() below.
#include <steady/core/motion.hpp>

#include "support/random_affine.hpp"

#include <benchmark/benchmark.h>

#include <Eigen/Dense>

#include <cstdint>
#include <random>
#include <vector>

namespace {

// Key poses of a tumbling body: each key turns the previous orientation by at most 90 degrees
// about a random axis, rescales each axis by a factor in [0.8, 1.25] and moves by up to 2
// units, so every pair of consecutive keys has a SAM and conditioning does not drift.
std::vector<steady::Affine3> chainedPoses(std::uint64_t seed, int count) {
  using steady::testing::uniform;
  std::mt19937_64 rng(seed);
  std::vector<steady::Affine3> poses;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d axis(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    R = steady::Affine3::rotation(axis, uniform(rng, 0, 1.5)).linear() * R;
    const Eigen::Vector3d scale(uniform(rng, 0.8, 1.25), uniform(rng, 0.8, 1.25), uniform(rng, 0.8, 1.25));
    x += Eigen::Vector3d(uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2));
    poses.emplace_back(R * scale.asDiagonal(), x);
  }
  return poses;
}

void BM_MotionPose(benchmark::State& state) {
  const steady::Motion3 motion = steady::Motion3::polySam(chainedPoses(424242, 101));
  std::mt19937_64 rng(777);
  std::vector<double> ts(1024);
  for (double& t : ts) t = steady::testing::uniform(rng, 0.0, 1.0);
  std::size_t i = 0;
  for (auto _ : state) {
    steady::Affine3 p = motion.pose(ts[i]);
    benchmark::DoNotOptimize(p);
    i = (i + 1) & 1023u;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["spans"] = static_cast<double>(motion.spanCount());
}

void BM_Subdivide4(benchmark::State& state) {
  const std::vector<steady::Affine3> keys = chainedPoses(171717, 10);
  std::size_t out = 0;
  for (auto _ : state) {
    std::vector<steady::Affine3> q = steady::subdivide(keys, 4);
    out = q.size();
    benchmark::DoNotOptimize(q.data());
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["poses_out"] = static_cast<double>(out);
}

}  // namespace

BENCHMARK(BM_MotionPose)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_Subdivide4)->Unit(benchmark::kMicrosecond);
