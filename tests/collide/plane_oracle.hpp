#pragma once
// An independent oracle shared by the collide tests: the first time a point set moving along a
// motion reaches the plane z = 0 from above, by dense sampling of the motion (N steps) and
// bisection (60 halvings) of the first sign change of each point's height. Returns 2 when no
// point reaches the plane.
#include <steady/core/motion.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <vector>

namespace steady_test {

inline double firstPlaneCrossing(const steady::Motion3& motion, const std::vector<Eigen::Vector3d>& points,
                                 int N = 4000) {
  double first = 2;
  for (const Eigen::Vector3d& p : points) {
    auto z = [&](double t) { return motion.pose(t).applyPoint(p).z(); };
    double prev = z(0);
    for (int i = 1; i <= N && static_cast<double>(i - 1) / N < first; ++i) {
      const double t = static_cast<double>(i) / N, cur = z(t);
      if (prev > 0 && cur <= 0) {
        double lo = static_cast<double>(i - 1) / N, hi = t;
        for (int it = 0; it < 60; ++it) (z(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
        first = std::min(first, hi);
        break;
      }
      prev = cur;
    }
  }
  return first;
}

}  // namespace steady_test
