#pragma once
// Shared meshes and checkers of the sweep tests, generated in code.
#include <steady/core/affine.hpp>
#include <steady/core/error.hpp>

#include "support/meshes.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <regex>
#include <string>
#include <vector>

namespace steady_sweep_test {

using steady_test::box;
using steady_test::Faces;
using steady_test::Mesh;
using steady_test::uvSphere;
using steady_test::V;

// Reverses every face.
inline Mesh flipped(Mesh m) {
  for (auto& t : m.f) std::swap(t[1], t[2]);
  return m;
}

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
}

inline V randomUnit(std::mt19937_64& rng) {
  for (;;) {
    const V p(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const double n = p.norm();
    if (n > 0.1 && n <= 1) return p / n;
  }
}

// The convex hull of n random points on an ellipsoid (random axes 0.5..1.5 about c), by brute
// force over point triples (points in general position: no four coplanar).
inline Mesh randomConvex(std::mt19937_64& rng, int n, const V& c = V::Zero()) {
  const V axes(uniform(rng, 0.5, 1.5), uniform(rng, 0.5, 1.5), uniform(rng, 0.5, 1.5));
  Mesh m;
  for (int i = 0; i < n; ++i) m.v.push_back(c + randomUnit(rng).cwiseProduct(axes));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        const V nrm = (m.v[j] - m.v[i]).cross(m.v[k] - m.v[i]);
        int pos = 0, neg = 0;
        for (int l = 0; l < n; ++l) {
          if (l == i || l == j || l == k) continue;
          const double d = nrm.dot(m.v[l] - m.v[i]);
          pos += d > 0;
          neg += d < 0;
        }
        if (pos == 0) m.f.push_back({i, j, k});        // all others below: outward already
        else if (neg == 0) m.f.push_back({i, k, j});   // all above: flip
      }
  return m;
}

// Closest distance from p to triangle (a, b, c) (Ericson, Real-Time Collision Detection 5.1.5).
inline double pointTriangleDistance(const V& p, const V& a, const V& b, const V& c) {
  const V ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const V bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const V cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

// Runs f, expecting steady::Error with `code` and a message matching `pattern` (ECMAScript).
inline ::testing::AssertionResult throwsError(const std::function<void()>& f, steady::ErrorCode code,
                                              const std::string& pattern) {
  try {
    f();
  } catch (const steady::Error& e) {
    if (e.code() != code)
      return ::testing::AssertionFailure() << "code " << steady::to_string(e.code()) << " instead of "
                                           << steady::to_string(code) << ": " << e.what();
    if (!std::regex_search(e.what(), std::regex(pattern)))
      return ::testing::AssertionFailure() << "message \"" << e.what() << "\" does not match /" << pattern << "/";
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "no steady::Error thrown (expected " << steady::to_string(code) << ")";
}

}  // namespace steady_sweep_test
