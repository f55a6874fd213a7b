// Collision narrow-phase benchmark, in the steady_bench binary:
//   BM_PointPlaneSolve  SpanRoots::firstPointPlane() for one point and one plane, over 1024 random
//                       (point, plane) pairs on one random span (the span's solver prebuilt):
//                       points in [-2, 2]^3, unit normals, offsets uniform in [-6, 6], so that
//                       about one solve in nine finds a contact. One solve per iteration.
#include <steady/collide/span_roots.hpp>

#include "support/random_affine.hpp"

#include <benchmark/benchmark.h>

#include <optional>
#include <random>
#include <vector>

namespace {

void BM_PointPlaneSolve(benchmark::State& state) {
  using steady::testing::uniform;
  const steady::Span3 span(steady::testing::randomWellPosedSet<3>(31337, 1).front());
  const steady::SpanRoots solver(span);
  std::mt19937_64 rng(4242);
  std::vector<Eigen::Vector3d> points(1024), normals(1024);
  std::vector<double> offsets(1024);
  for (int i = 0; i < 1024; ++i) {
    points[i] = Eigen::Vector3d(uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2));
    normals[i] = Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)).normalized();
    offsets[i] = uniform(rng, -6, 6);
  }
  std::size_t i = 0, hits = 0, calls = 0;
  for (auto _ : state) {
    const std::optional<steady::ContactRoot> r = solver.firstPointPlane(points[i], normals[i], offsets[i]);
    hits += r.has_value() ? 1 : 0;
    ++calls;
    benchmark::DoNotOptimize(r);
    i = (i + 1) & 1023u;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["hit_fraction"] = calls ? static_cast<double>(hits) / static_cast<double>(calls) : 0.0;
}

}  // namespace

BENCHMARK(BM_PointPlaneSolve)->Unit(benchmark::kNanosecond);
