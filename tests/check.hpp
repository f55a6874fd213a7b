#pragma once
// Shared checkers of the test suite.

#include <steady/core/affine.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace steady::testing {

/// Relative Frobenius distance of two affinities, over the D x (D+1) matrices [L | t].
template <int D>
double relativeDistance(const Affine<D>& a, const Affine<D>& b) {
  const double n = std::max(b.matrix().norm(), 1e-300);
  return (a.matrix() - b.matrix()).norm() / n;
}

/// Asserts `|a - b|_F <= tol * |b|_F` and prints both on failure.
template <int D>
::testing::AssertionResult near(const Affine<D>& a, const Affine<D>& b, double tol) {
  const double e = relativeDistance(a, b);
  if (e <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "relative error " << e << " > " << tol << "\n got:\n"
                                       << a.matrix() << "\n expected:\n"
                                       << b.matrix();
}

/// Asserts that two matrices agree entrywise within `tol` (absolute), printing both.
template <class A, class B>
::testing::AssertionResult matNear(const A& a, const B& b, double tol) {
  const double e = (a - b).cwiseAbs().maxCoeff();
  if (e <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "max abs error " << e << " > " << tol << "\n got:\n"
                                       << a << "\n expected:\n"
                                       << b;
}

}  // namespace steady::testing
