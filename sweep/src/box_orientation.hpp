#pragma once
// The orientation of three 2D points known only by boxes, decided in plain double arithmetic
// when the boxes decide it. Internal to steady::sweep (trim.cpp runs it before CGAL's interval
// filter; tests/sweep/test_box_orientation.cpp checks it against exact rationals).
#include <algorithm>
#include <cmath>

namespace steady::sweep::detail {

// A closed interval [lo, hi] of the reals (lo <= hi).
struct Range {
  double lo, hi;
};

// The sign of D = (bx - ax)(cy - ay) - (by - ay)(cx - ax) when it is the same for every choice
// of the six coordinates in their ranges: +1 or -1; 0 when the ranges do not decide it (or a
// bound is not finite). Never a wrong sign, under round-to-nearest or any directed rounding.
//
// Why. Each range is taken as centre m and radius r: the centre rounds to within 2^-52 of the
// larger end's magnitude (any rounding mode) and the half width to within 2^-52 of itself, and
// r = (half width)(1 + 2^-50) + 2^-52 max(|lo|, |hi|) covers both, so every point of the range
// lies within r of m (a range of one point: its value, r = 0). With u = b - a and v = c - a at
// the centres and su = ra + rb, sv = ra + rc per axis, D over the boxes differs from
// D0 = u1 v2 - u2 v1 by at most
//   E = |v2| su1 + |u1| sv2 + su1 sv2 + |v1| su2 + |u2| sv1 + su2 sv1,
// and D0 computed in doubles errs by at most (3 + 16 2^-53) 2^-53 (|u1 v2| + |u2 v1|)
// (Shewchuk's orient2d bound; twice that under directed rounding), below the
// 2^-49 ((|u1| + su1)(|v2| + sv2) + (|u2| + su2)(|v1| + sv1)) used here. E, a sum of
// positive products, is computed to within 1e-12 of itself. So D has the sign of the computed
// D0 when its magnitude exceeds both bounds (plus 1e-300 against underflow). Ranges of one
// point leave the rounding bound alone: a static filter like orient2d's, somewhat looser.
inline int orientationOfBoxes(Range ax, Range ay, Range bx, Range by, Range cx, Range cy) {
  auto centre = [](Range x) { return 0.5 * x.lo + 0.5 * x.hi; };
  auto radius = [](Range x) {
    if (x.lo == x.hi) return 0.0;
    return 0.5 * (x.hi - x.lo) * (1 + 0x1.0p-50) + 0x1.0p-52 * std::max(std::abs(x.lo), std::abs(x.hi));
  };
  const double max = centre(ax), may = centre(ay), mbx = centre(bx), mby = centre(by);
  const double mcx = centre(cx), mcy = centre(cy);
  const double rax = radius(ax), ray = radius(ay), rbx = radius(bx), rby = radius(by);
  const double rcx = radius(cx), rcy = radius(cy);
  if (!std::isfinite(max + may + mbx + mby + mcx + mcy + rax + ray + rbx + rby + rcx + rcy)) return 0;
  const double u1 = mbx - max, u2 = mby - may, v1 = mcx - max, v2 = mcy - may;
  const double su1 = rax + rbx, su2 = ray + rby, sv1 = rax + rcx, sv2 = ray + rcy;
  const double d = u1 * v2 - u2 * v1;
  const double spread =
      std::abs(v2) * su1 + std::abs(u1) * sv2 + su1 * sv2 + std::abs(v1) * su2 + std::abs(u2) * sv1 + su2 * sv1;
  const double size = (std::abs(u1) + su1) * (std::abs(v2) + sv2) + (std::abs(u2) + su2) * (std::abs(v1) + sv1);
  const double bound = spread * (1 + 1e-12) + 0x1.0p-49 * size + 1e-300;
  if (d > bound) return 1;
  if (d < -bound) return -1;
  return 0;
}

}  // namespace steady::sweep::detail
