// steady_bench: what one call of the EAR costs, next to what users would call instead (Eigen's
// unsupported MatrixFunctions module).
//
// Every benchmark walks the same fixed set: the 1024 affinities of
// steady::testing::randomWellPosedSet<D>(kSetSeed, 1024) and 1024 exponents t uniform in [-2, 2].
// Iteration k handles item k mod 1024, so one iteration is one call and the reported time per
// iteration is the time per call (items_per_second says the same thing). All inputs are built
// before the timed loops, in the form each library takes natively: steady::Affine for steady,
// Eigen matrices (linear part, or the homogeneous matrix [L t; 0 1]) for Eigen.
//
// Peers of each steady call:
//   BM_EarLog2      steady::log(Affine2)            BM_EigenLog2 (2x2 L.log());
//                                                   BM_EigenLog2Hom (3x3 homogeneous, extra)
//   BM_EarLog3      steady::log(Affine3)            BM_EigenLog4 (4x4 homogeneous .log()),
//                                                   BM_EigenLog3 (3x3 linear part .log())
//   BM_EarPow3      steady::pow(A, t)               BM_EigenPow4 (4x4 homogeneous .pow(t))
//   BM_EarSpanEval3 Span3::power(t), span prebuilt  BM_EigenExp4 ((t X).exp(), X = the 4x4
//                                                   homogeneous log, precomputed)
//   BM_EarSpanBuild3 (extra) the one-off cost of building a Span3.
//
// Before running, main() checks the measured steady calls against Eigen on the whole set and
// stores the largest relative differences in the benchmark context (visible in the console
// header and in the JSON output), so a fast but wrong kernel cannot go unnoticed.
//
// Suggested run (medians over repetitions):
//   steady_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// or scripts/bench-table.sh, which builds, runs and prints the Markdown table.

#include <steady/core/affine.hpp>
#include <steady/core/ear.hpp>

#include "support/random_affine.hpp"

#include <benchmark/benchmark.h>

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr std::uint64_t kSetSeed = 20240611;   // the affinities
constexpr std::uint64_t kTimeSeed = 97531;     // the exponents t
constexpr int kCount = 1024;                   // a power of two: the index wraps with a mask
constexpr std::size_t kMask = static_cast<std::size_t>(kCount) - 1;
static_assert((kCount & (kCount - 1)) == 0, "kCount must be a power of two");

std::vector<double> makeExponents() {
  std::mt19937_64 rng(kTimeSeed);
  std::vector<double> ts(static_cast<std::size_t>(kCount));
  for (double& t : ts) t = steady::testing::uniform(rng, -2.0, 2.0);
  return ts;
}

const std::vector<double>& exponents() {
  static const std::vector<double> ts = makeExponents();
  return ts;
}

// ---- 2D data --------------------------------------------------------------------------------

struct Data2 {
  std::vector<steady::Affine2> A;
  std::vector<Eigen::Matrix2d> L;  // linear parts
  std::vector<Eigen::Matrix3d> H;  // homogeneous matrices
  std::string error;               // first failure of a steady call, if any
};

Data2 makeData2() {
  Data2 d;
  d.A = steady::testing::randomWellPosedSet<2>(kSetSeed, kCount);
  for (const auto& a : d.A) {
    d.L.push_back(a.linear());
    d.H.push_back(a.homogeneous());
  }
  return d;
}

const Data2& data2() {
  static const Data2 d = makeData2();
  return d;
}

// ---- 3D data --------------------------------------------------------------------------------

struct Data3 {
  std::vector<steady::Affine3> A;
  std::vector<Eigen::Matrix3d> L;  // linear parts
  std::vector<Eigen::Matrix4d> H;  // homogeneous matrices
  std::vector<Eigen::Matrix4d> X;  // homogeneous logs (steady's; Eigen's where steady failed)
  std::vector<steady::Span3> spans;
  std::string error;  // first failure of a steady call, if any
};

Data3 makeData3() {
  Data3 d;
  d.A = steady::testing::randomWellPosedSet<3>(kSetSeed, kCount);
  d.spans.reserve(d.A.size());
  for (std::size_t i = 0; i < d.A.size(); ++i) {
    const auto& a = d.A[i];
    d.L.push_back(a.linear());
    d.H.push_back(a.homogeneous());
    try {
      d.X.push_back(steady::log(a).homogeneous());
      d.spans.emplace_back(a);
    } catch (const std::exception& e) {
      if (d.error.empty()) d.error = "item " + std::to_string(i) + ": " + e.what();
      if (d.X.size() == i) d.X.push_back(d.H.back().log());
    }
  }
  return d;
}

const Data3& data3() {
  static const Data3 d = makeData3();
  return d;
}

// Runs op(i) for i = 0, 1, 2, ... (mod kCount), one call per iteration, keeping each result
// alive; an exception skips the benchmark with its message.
template <class Op>
void cycle(benchmark::State& state, Op op) {
  std::size_t i = 0;
  try {
    for (auto _ : state) {
      auto r = op(i);
      benchmark::DoNotOptimize(r);
      i = (i + 1) & kMask;
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  state.SetItemsProcessed(state.iterations());
}

// ---- steady ---------------------------------------------------------------------------------

void BM_EarLog2(benchmark::State& state) {
  const auto& A = data2().A;
  cycle(state, [&](std::size_t i) { return steady::log(A[i]); });
}

void BM_EarLog3(benchmark::State& state) {
  const auto& A = data3().A;
  cycle(state, [&](std::size_t i) { return steady::log(A[i]); });
}

void BM_EarPow3(benchmark::State& state) {
  const auto& A = data3().A;
  const auto& ts = exponents();
  cycle(state, [&](std::size_t i) { return steady::pow(A[i], ts[i]); });
}

void BM_EarSpanEval3(benchmark::State& state) {
  const auto& d = data3();
  if (!d.error.empty() || d.spans.size() != static_cast<std::size_t>(kCount)) {
    state.SkipWithError(("could not build every Span3: " + d.error).c_str());
    return;
  }
  const auto& ts = exponents();
  cycle(state, [&](std::size_t i) { return d.spans[i].power(ts[i]); });
}

// Extra: the one-off cost that BM_EarSpanEval3 leaves out (log + spectral form).
void BM_EarSpanBuild3(benchmark::State& state) {
  const auto& A = data3().A;
  cycle(state, [&](std::size_t i) { return steady::Span3(A[i]); });
}

// ---- Eigen MatrixFunctions peers ------------------------------------------------------------

void BM_EigenLog2(benchmark::State& state) {
  const auto& L = data2().L;
  cycle(state, [&](std::size_t i) { return Eigen::Matrix2d(L[i].log()); });
}

// Extra: the 2D affinity as Eigen users would pass it (3x3 homogeneous).
void BM_EigenLog2Hom(benchmark::State& state) {
  const auto& H = data2().H;
  cycle(state, [&](std::size_t i) { return Eigen::Matrix3d(H[i].log()); });
}

void BM_EigenLog3(benchmark::State& state) {
  const auto& L = data3().L;
  cycle(state, [&](std::size_t i) { return Eigen::Matrix3d(L[i].log()); });
}

void BM_EigenLog4(benchmark::State& state) {
  const auto& H = data3().H;
  cycle(state, [&](std::size_t i) { return Eigen::Matrix4d(H[i].log()); });
}

// exp(t X) with X the precomputed homogeneous log: what Span3::power(t) computes.
void BM_EigenExp4(benchmark::State& state) {
  const auto& X = data3().X;
  const auto& ts = exponents();
  cycle(state, [&](std::size_t i) { return Eigen::Matrix4d((ts[i] * X[i]).exp()); });
}

void BM_EigenPow4(benchmark::State& state) {
  const auto& H = data3().H;
  const auto& ts = exponents();
  cycle(state, [&](std::size_t i) { return Eigen::Matrix4d(H[i].pow(ts[i])); });
}

BENCHMARK(BM_EarLog2)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EarLog3)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EarPow3)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EarSpanEval3)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EarSpanBuild3)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EigenLog2)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EigenLog2Hom)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EigenLog3)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EigenLog4)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EigenExp4)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EigenPow4)->Unit(benchmark::kNanosecond);

// ---- correctness check recorded in the context ----------------------------------------------

// Largest absolute entry difference, relative to max(1, largest entry of the reference).
template <typename M1, typename M2>
double relDiff(const M1& a, const M2& ref) {
  return (a - ref).cwiseAbs().maxCoeff() / std::max(1.0, ref.cwiseAbs().maxCoeff());
}

std::string sci(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2e", x);
  return buf;
}

void recordChecks() {
  benchmark::AddCustomContext("bench_set", "randomWellPosedSet<D>(" + std::to_string(kSetSeed) +
                                               ", " + std::to_string(kCount) +
                                               "), t uniform in [-2,2] (seed " +
                                               std::to_string(kTimeSeed) + ")");
  const auto& ts = exponents();
  std::string error;
  double log2 = 0, log3 = 0, pow3 = 0, round3 = 0;
  try {
    const auto& d2 = data2();
    for (std::size_t i = 0; i < d2.A.size(); ++i) {
      const Eigen::Matrix3d ref = d2.H[i].log();
      log2 = std::max(log2, relDiff(steady::log(d2.A[i]).homogeneous(), ref));
    }
    const auto& d3 = data3();
    if (!d3.error.empty()) error = d3.error;
    for (std::size_t i = 0; i < d3.A.size(); ++i) {
      const Eigen::Matrix4d refLog = d3.H[i].log();
      log3 = std::max(log3, relDiff(steady::log(d3.A[i]).homogeneous(), refLog));
      const Eigen::Matrix4d refPow = d3.H[i].pow(ts[i]);
      const Eigen::Matrix4d p = steady::pow(d3.A[i], ts[i]).homogeneous();
      pow3 = std::max(pow3, relDiff(p, refPow));
      // Round trip through Eigen's exponential: independent of Eigen's own logarithm.
      round3 = std::max(round3, relDiff(d3.X[i].exp().eval(), d3.H[i]));
    }
  } catch (const std::exception& e) {
    if (error.empty()) error = e.what();
  }
  benchmark::AddCustomContext("check_log2_vs_eigen", sci(log2));
  benchmark::AddCustomContext("check_log3_vs_eigen", sci(log3));
  benchmark::AddCustomContext("check_pow3_vs_eigen", sci(pow3));
  benchmark::AddCustomContext("check_exp_of_log3_vs_input", sci(round3));
  if (!error.empty()) benchmark::AddCustomContext("check_error", error);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  recordChecks();  // also builds the data sets, outside every timed region
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
