// The double-precision orientation filter on boxes (sweep/src/box_orientation.hpp, internal),
// against exact rational arithmetic: a sign it gives must hold for every point of the boxes.
// The determinant is affine in each coordinate, so its extremes over the boxes are at their 64
// corners, which are checked exactly.
#include "box_orientation.hpp"

// (g++ 12 warns that Boost's cpp_int may use an uninitialized limb when its code is inlined
// here: a false positive inside Boost, silenced for this file only.)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/multiprecision/cpp_int.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>

namespace {

using steady::sweep::detail::orientationOfBoxes;
using steady::sweep::detail::Range;
using Rational = boost::multiprecision::cpp_rational;

int exactSign(const std::array<double, 6>& q) {
  auto r = [&](int k) { return Rational(q[static_cast<std::size_t>(k)]); };
  const Rational d = (r(2) - r(0)) * (r(5) - r(1)) - (r(3) - r(1)) * (r(4) - r(0));
  return d.sign();
}

struct Case {
  std::array<Range, 6> box;  // ax, ay, bx, by, cx, cy
  std::array<double, 6> point;  // a point in the boxes
};

// Nearly collinear triples at scales 2^-20 .. 2^19, some far from the origin, with a random
// perturbation off the line down to 2^-60 of the scale; each coordinate a point (exact double)
// or a range of random width around it, down to a few ulps (in a quarter of the cases every
// coordinate is a point).
Case nearlyCollinear(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double scale = std::ldexp(1.0, static_cast<int>(rng() % 40) - 20);
  const double offset = rng() % 2 ? 1000 * u(rng) : 0.0;
  const double ax = offset + scale * u(rng), ay = offset + scale * u(rng), dx = scale * u(rng), dy = scale * u(rng);
  const double s = u(rng), t = u(rng), off = std::ldexp(scale, -static_cast<int>(rng() % 60));
  const bool exact = rng() % 4 == 0;  // every coordinate a point
  Case c;
  c.point = {ax, ay, ax + s * dx, ay + s * dy, ax + t * dx + off * u(rng), ay + t * dy + off * u(rng)};
  for (std::size_t k = 0; k < 6; ++k) {
    const double x = c.point[k];
    if (exact || rng() % 3 == 0) {
      c.box[k] = {x, x};
    } else {
      const double w = std::ldexp(std::abs(x) + scale, -static_cast<int>(rng() % 55) - 1);
      c.box[k] = {x - w * std::abs(u(rng)), x + w * std::abs(u(rng))};
    }
  }
  return c;
}

int filter(const Case& c) { return orientationOfBoxes(c.box[0], c.box[1], c.box[2], c.box[3], c.box[4], c.box[5]); }

TEST(BoxOrientation, NeverContradictsExactArithmeticAtAnyCornerOfTheBoxes) {
  std::mt19937_64 rng(20261126);
  int decided = 0, undecided_points = 0;
  for (int i = 0; i < 40000; ++i) {
    const Case c = nearlyCollinear(rng);
    const int o = filter(c);
    if (o == 0) {
      bool points = true;
      for (const Range& r : c.box) points = points && r.lo == r.hi;
      undecided_points += points;
      continue;
    }
    ++decided;
    ASSERT_EQ(o, exactSign(c.point)) << "case " << i;
    for (int corner = 0; corner < 64; ++corner) {
      std::array<double, 6> q{};
      for (std::size_t k = 0; k < 6; ++k) q[k] = (corner >> k) & 1 ? c.box[k].hi : c.box[k].lo;
      ASSERT_EQ(o, exactSign(q)) << "case " << i << ", corner " << corner;
    }
  }
  // The generator reaches both sides of the filter's bound: cases it decides, and cases of
  // exact points it leaves undecided (off the line by less than its rounding bound).
  EXPECT_GT(decided, 4000);
  EXPECT_GT(undecided_points, 100);
}

TEST(BoxOrientation, DecidesClearTurnsAndLeavesDegenerateOnesUndecided) {
  const Range zero{0, 0}, one{1, 1};
  EXPECT_EQ(orientationOfBoxes(zero, zero, one, zero, zero, one), 1);   // (0,0) (1,0) (0,1): left turn
  EXPECT_EQ(orientationOfBoxes(zero, zero, zero, one, one, zero), -1);  // (0,0) (0,1) (1,0): right turn
  const Range two{2, 2};
  EXPECT_EQ(orientationOfBoxes(zero, zero, one, one, two, two), 0);     // collinear
  // A box that straddles the line through the other two points: undecided.
  EXPECT_EQ(orientationOfBoxes(zero, zero, two, zero, one, Range{-1e-9, 1e-9}), 0);
  // The same box just above the line: decided.
  EXPECT_EQ(orientationOfBoxes(zero, zero, two, zero, one, Range{1e-9, 2e-9}), 1);
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(orientationOfBoxes(zero, zero, one, zero, zero, Range{1, inf}), 0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(orientationOfBoxes(zero, zero, one, zero, Range{nan, nan}, one), 0);
}

}  // namespace
