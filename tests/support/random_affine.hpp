#pragma once
// Seeded generators of "well-posed" random affinities, shared by the tests and the benchmarks so
// that both speak about the same set.
//
// The random set: L = exp(X) with the entries of X uniform in [-1, 1] (so a real logarithm
// exists and the rotation angle of any complex pair is below about 1.8 rad), rejected unless
// the 2-norm condition number of L is at most 1e3; translation uniform in [-5, 5]^D.

#include <steady/core/affine.hpp>

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include <cstdint>
#include <random>
#include <vector>

namespace steady::testing {

/// A deterministic uniform double in [lo, hi) (independent of the standard library's
/// distribution implementations).
inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return lo + (hi - lo) * u;
}

template <int D>
Affine<D> randomWellPosedAffine(std::mt19937_64& rng) {
  using Linear = typename Affine<D>::Linear;
  using Vector = typename Affine<D>::Vector;
  for (;;) {
    Linear X;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) X(i, j) = uniform(rng, -1.0, 1.0);
    const Linear L = X.exp();
    Eigen::JacobiSVD<Linear> svd(L);
    const auto s = svd.singularValues();
    if (s(D - 1) <= 0 || s(0) / s(D - 1) > 1e3) continue;
    Vector t;
    for (int i = 0; i < D; ++i) t(i) = uniform(rng, -5.0, 5.0);
    return Affine<D>(L, t);
  }
}

/// `count` affinities of the random set from `seed`.
template <int D>
std::vector<Affine<D>> randomWellPosedSet(std::uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  std::vector<Affine<D>> out;
  out.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) out.push_back(randomWellPosedAffine<D>(rng));
  return out;
}

}  // namespace steady::testing
