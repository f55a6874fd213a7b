// The certified separating planes of sweep/src/separation.hpp (internal), against exact rational
// arithmetic: every plane or axis they report must separate the true points strictly, as
// claimed, including when the doubles given are the true points moved by up to their pads. And
// they must find the plane where the triangles are well apart: fans of a cap face (triangles
// from one corner to consecutive points of a side), the case they were written for.
#include "separation.hpp"

// (g++ 12 warns that Boost's cpp_int may use an uninitialized limb when its code is inlined
// here: a false positive inside Boost, silenced for this file only.)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/multiprecision/cpp_int.hpp>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace {

using steady::sweep::detail::certainlyDisjoint;
using steady::sweep::detail::meetAtSharedCornerOnly;
using steady::sweep::detail::PadPoint;
using Rational = boost::multiprecision::cpp_rational;
using Vec = Eigen::Vector3d;

// The exact sign of m . (x - o) for doubles m, x, o.
int exactSide(const Vec& m, const Vec& o, const Vec& x) {
  Rational s = 0;
  for (int k = 0; k < 3; ++k) s += Rational(m[k]) * (Rational(x[k]) - Rational(o[k]));
  return s.sign();
}

// The exact value of m . x.
Rational exactDot(const Vec& m, const Vec& x) {
  Rational s = 0;
  for (int k = 0; k < 3; ++k) s += Rational(m[k]) * Rational(x[k]);
  return s;
}

Vec randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  Vec v(n(rng), n(rng), n(rng));
  return v.normalized();
}

// x moved by up to `pad` per coordinate.
Vec moved(const Vec& x, double pad, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-pad, pad);
  return x + Vec(u(rng), u(rng), u(rng));
}

struct Fan {
  Vec apex;
  std::vector<Vec> side;  // consecutive points of the side
};

// A fan in a random plane: an apex and n points along a segment, in doubles (so not exactly
// coplanar), at a random scale and place.
Fan randomFan(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> u(-1, 1);
  const Vec e1 = randomUnit(rng);
  const Vec e2 = e1.unitOrthogonal();
  const double scale = std::pow(10.0, 4 * u(rng)), far = 100 * u(rng) * scale;
  const Vec origin = Vec(u(rng), u(rng), u(rng)) * far;
  Fan f;
  f.apex = origin + scale * (0.3 * u(rng) * e1 + (0.5 + 0.5 * (u(rng) + 1)) * e2);
  for (int i = 0; i < n; ++i) f.side.push_back(origin + scale * (2.0 * i / (n - 1) - 1.0) * e1);
  return f;
}

TEST(Separation, FanTrianglesMeetAtTheirApexOnly) {
  std::mt19937_64 rng(60);
  long found = 0, pairs = 0, adjacent_claims = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 40;
    const Fan f = randomFan(rng, n);
    // (pads: none, or a tenth of the spacing's ten-thousandth; the doubles are moved by up to it)
    const double spacing = (f.side[1] - f.side[0]).norm();
    const double pad = trial % 2 ? 1e-5 * spacing : 0.0;
    std::vector<Vec> given(f.side.size());
    for (std::size_t i = 0; i < f.side.size(); ++i) given[i] = pad > 0 ? moved(f.side[i], pad, rng) : f.side[i];
    const Vec apex = pad > 0 ? moved(f.apex, pad, rng) : f.apex;
    for (int i = 0; i + 1 < n; ++i)
      for (int j = i + 1; j + 1 < n; ++j) {
        Vec m;
        const bool apart = meetAtSharedCornerOnly({apex, pad}, {given[i], pad}, {given[i + 1], pad}, {given[j], pad},
                                                  {given[j + 1], pad}, &m);
        if (j == i + 1) {  // (they share an edge, not only the apex: the wedges touch)
          adjacent_claims += apart;
          continue;
        }
        ++pairs;
        if (!apart) continue;
        ++found;
        // the true points, strictly on the sides claimed
        const int s = exactSide(m, f.apex, f.side[i]);
        ASSERT_NE(s, 0);
        EXPECT_EQ(exactSide(m, f.apex, f.side[i + 1]), s) << trial << " " << i << " " << j;
        EXPECT_EQ(exactSide(m, f.apex, f.side[j]), -s) << trial << " " << i << " " << j;
        EXPECT_EQ(exactSide(m, f.apex, f.side[j + 1]), -s) << trial << " " << i << " " << j;
      }
  }
  // Adjacent triangles share the ray to their common point: no plane through the apex parts
  // them strictly, and none may be claimed.
  EXPECT_EQ(adjacent_claims, 0);
  std::printf("[ info     ] fan pairs: %ld of %ld parted in doubles\n", found, pairs);
  EXPECT_GE(found, pairs * 99 / 100);
}

// Wedges that overlap, or touch within rounding (a gap of at most 1e-17 of their size), must
// never be claimed apart.
TEST(Separation, OverlappingOrTouchingWedgesAreNotParted) {
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<double> u(0, 1);
  long claims = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec e1 = randomUnit(rng), e2 = e1.unitOrthogonal(), v = Vec(u(rng), u(rng), u(rng));
    const auto at = [&](double angle) { return Vec(v + std::cos(angle) * e1 + std::sin(angle) * e2); };
    const double a0 = 3 * u(rng), a1 = a0 + 0.1 + u(rng);
    // the second wedge starts inside the first, or just past its end
    const double gap = trial % 2 ? -0.05 * u(rng) : 1e-17 * u(rng);
    const double b0 = a1 + gap, b1 = b0 + 0.1 + u(rng);
    claims += meetAtSharedCornerOnly({v, 0}, {at(a0), 0}, {at(a1), 0}, {at(b0), 0}, {at(b1), 0});
  }
  EXPECT_EQ(claims, 0);
}

// Two fan triangles that share a side point in truth, each given its own copy of it moved by up
// to the pad: the copies may part the doubles, but not the true triangles, and no claim may be
// made (the pads are what keeps it from being made).
TEST(Separation, PointsEqualInTruthAreNotPartedByTheirPads) {
  std::mt19937_64 rng(64);
  long claims = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Fan f = randomFan(rng, 8);
    const double pad = 1e-3 * (f.side[1] - f.side[0]).norm();
    const int i = trial % 6;
    claims += meetAtSharedCornerOnly({f.apex, 0}, {moved(f.side[i], pad, rng), pad}, {moved(f.side[i + 1], pad, rng), pad},
                                     {moved(f.side[i + 1], pad, rng), pad}, {moved(f.side[i + 2], pad, rng), pad});
  }
  EXPECT_EQ(claims, 0);
}

TEST(Separation, DisjointTrianglesGetACertifiedAxis) {
  std::mt19937_64 rng(62);
  std::uniform_real_distribution<double> u(-1, 1);
  long found = 0, trials = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    // two triangles in a plane (in doubles) or across it, some far apart, some nearly touching
    const Vec e1 = randomUnit(rng), e2 = e1.unitOrthogonal(), n = e1.cross(e2);
    const double gap = trial % 3 == 0 ? 1e-14 : trial % 3 == 1 ? 1e-3 : 0.5;
    const double tilt = trial % 4 == 0 ? 0.3 : 0.0;
    std::array<Vec, 3> s, t;
    for (int k = 0; k < 3; ++k) {
      const double lean = k == 0 ? 0.0 : std::abs(u(rng));  // (corner 0 of each at the gap)
      s[static_cast<std::size_t>(k)] = -(gap / 2 + lean) * e1 + u(rng) * e2 + (k == 1 ? tilt : 0.0) * n;
      t[static_cast<std::size_t>(k)] = (gap / 2 + std::abs(u(rng)) * (k != 0)) * e1 + u(rng) * e2 - (k == 2 ? tilt : 0.0) * n;
    }
    // (every corner of s has e1 . x <= -gap/2 and of t >= gap/2, up to rounding: disjoint)
    const double pad = trial % 2 ? 1e-4 * gap : 0.0;
    std::array<PadPoint, 3> ps, pt;
    for (int k = 0; k < 3; ++k) {
      ps[static_cast<std::size_t>(k)] = {pad > 0 ? moved(s[static_cast<std::size_t>(k)], pad, rng) : s[static_cast<std::size_t>(k)], pad};
      pt[static_cast<std::size_t>(k)] = {pad > 0 ? moved(t[static_cast<std::size_t>(k)], pad, rng) : t[static_cast<std::size_t>(k)], pad};
    }
    ++trials;
    Vec m;
    if (!certainlyDisjoint(ps, pt, &m)) continue;
    ++found;
    // the true points' projections, strictly apart along m
    Rational s_lo = exactDot(m, s[0]), s_hi = s_lo, t_lo = exactDot(m, t[0]), t_hi = t_lo;
    for (int k = 1; k < 3; ++k) {
      const Rational a = exactDot(m, s[static_cast<std::size_t>(k)]), b = exactDot(m, t[static_cast<std::size_t>(k)]);
      s_lo = a < s_lo ? a : s_lo, s_hi = a > s_hi ? a : s_hi;
      t_lo = b < t_lo ? b : t_lo, t_hi = b > t_hi ? b : t_hi;
    }
    EXPECT_TRUE(s_hi < t_lo || t_hi < s_lo) << trial;
  }
  std::printf("[ info     ] disjoint pairs: %ld of %ld parted in doubles\n", found, trials);
  EXPECT_GE(found, trials * 3 / 5);  // (a third of them are 1e-14 apart)
}

// Two thin triangles that cross like an X seen along their nearly common normal, one passing
// just above the other where they cross, each straddling the other's plane: neither normal
// parts them, nor any edge normal within their planes (their shadows overlap), only the cross
// product of their long edges. Some pairs are tilted by 1e-4 (normals 0.008 degrees apart,
// which certainlyDisjoint treats as coplanar and tries its in-plane axes first) and some by
// 0.1, each in a random frame; every pair must be parted, along an axis that parts the exact
// points.
TEST(Separation, CrossedTrianglesOneAboveTheOtherArePartedByTheirEdges) {
  std::mt19937_64 rng(72);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 400; ++trial) {
    const double tilt = trial % 2 ? 1e-4 : 0.1;
    // s in z = 0 along x; t along y in z = tilt (x + y + 0.03), which is above z = 0 by at
    // least tilt * 0.01 wherever the shadows overlap (|x|, |y| <= 0.01), and below it at t's far
    // end (y = -1); s's corner at x = -1 is above t's plane, its corner at x = 1 below.
    const auto zt = [&](double x, double y) { return tilt * (x + y + 0.03); };
    const std::array<Vec, 3> s0{{Vec(-1, -0.01, 0), Vec(1, -0.01, 0), Vec(0, 0.01, 0)}};
    const std::array<Vec, 3> t0{{Vec(-0.01, -1, zt(-0.01, -1)), Vec(0.01, -1, zt(0.01, -1)), Vec(0, 1, zt(0, 1))}};
    const Eigen::Matrix3d R = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    const Vec shift(u(rng), u(rng), u(rng));
    std::array<PadPoint, 3> s, t;
    for (std::size_t k = 0; k < 3; ++k) s[k] = {R * s0[k] + shift, 0}, t[k] = {R * t0[k] + shift, 0};
    Vec m;
    ASSERT_TRUE(certainlyDisjoint(s, t, &m)) << trial;
    Rational s_lo = exactDot(m, s[0].x), s_hi = s_lo, t_lo = exactDot(m, t[0].x), t_hi = t_lo;
    for (std::size_t k = 1; k < 3; ++k) {
      const Rational a = exactDot(m, s[k].x), b = exactDot(m, t[k].x);
      s_lo = a < s_lo ? a : s_lo, s_hi = a > s_hi ? a : s_hi;
      t_lo = b < t_lo ? b : t_lo, t_hi = b > t_hi ? b : t_hi;
    }
    EXPECT_TRUE(s_hi < t_lo || t_hi < s_lo) << trial;
    // (the pair is the case meant: each straddles the other's plane, so neither normal parts it)
    const Vec ns = (s[1].x - s[0].x).cross(s[2].x - s[0].x), nt = (t[1].x - t[0].x).cross(t[2].x - t[0].x);
    EXPECT_EQ(exactSide(ns, s[0].x, t[0].x) * exactSide(ns, s[0].x, t[2].x), -1) << trial;
    EXPECT_EQ(exactSide(nt, t[0].x, s[0].x) * exactSide(nt, t[0].x, s[1].x), -1) << trial;
  }
}

// Triangles that cross, or share a point without sharing a corner, are never parted.
TEST(Separation, CrossingTrianglesAreNotParted) {
  std::mt19937_64 rng(63);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 4000; ++trial) {
    const Vec c(u(rng), u(rng), u(rng));  // a point of both
    std::array<PadPoint, 3> s, t;
    // s and t each hold c as a convex combination of their corners
    for (auto* tri : {&s, &t}) {
      const Vec a = c + randomUnit(rng), b = c + randomUnit(rng);
      (*tri)[0] = {a, 0}, (*tri)[1] = {b, 0}, (*tri)[2] = {Vec(3 * c - a - b), 0};  // c is their centroid
    }
    EXPECT_FALSE(certainlyDisjoint(s, t)) << trial;
  }
}

}  // namespace
