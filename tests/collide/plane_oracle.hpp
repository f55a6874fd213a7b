#pragma once
// Shared by the collide tests: an independent plane-crossing oracle and the random approach
// poses and two-body scenes of the seeded scene tests.
#include <steady/core/motion.hpp>

#include "support/meshes.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <optional>
#include <random>
#include <utility>
#include <vector>

namespace steady_test {

// Random poses of a body approaching the origin: B starts 2.5 away in a random direction with a
// random turn; C ends near the other side with another turn, under a random shear/scale
// L = I + 0.25 U (U uniform in [-1, 1] per entry) unless `rigid` (L = I, a screw, and no draws
// for it). Returns false when L does not keep orientation or no SAM joins B and C.
template <class Rng>
bool randomApproach(Rng& rng, bool rigid, steady::Affine3& B, steady::Affine3& C) {
  using steady::Affine3;
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const V dir = V(U(rng), U(rng), U(rng)).normalized();
  B = Affine3::translation(2.5 * dir) * Affine3::rotation(V(U(rng), U(rng), U(rng)), 3 * U(rng));
  Eigen::Matrix3d L = Eigen::Matrix3d::Identity();
  if (!rigid)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) L(i, j) += 0.25 * U(rng);
  C = Affine3(L, -1.5 * dir + 0.8 * V(U(rng), U(rng), U(rng))) * Affine3::rotation(V(U(rng), U(rng), U(rng)), 3 * U(rng));
  return L.determinant() > 0 && steady::samExists(B, C);
}

// A seeded two-body scene, number `trial`: an octahedron or a box (by trial) approaching along
// randomApproach's poses (with a middle key, a 2-span polySAM, on every fourth trial) a static
// octahedron or box (by trial), which, when `partner_moves`, wanders about the origin on its own
// polySAM with other key times. None (and no more draws) when randomApproach finds no motion.
struct TwoBodyScene {
  Mesh moving, fixed;
  steady::Motion3 motion, partner;
};
template <class Rng>
std::optional<TwoBodyScene> twoBodyScene(Rng& rng, int trial, bool partner_moves) {
  using steady::Affine3;
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const steady::MotionOptions split{{}, steady::NoSamPolicy::Split, 12};
  Mesh fixed = trial % 2 ? octahedron(V(0, 0, 0), 1.0) : box(V(-0.8, -0.6, -0.7), V(0.7, 0.9, 0.6));
  Mesh moving = trial % 3 ? octahedron(V(0, 0, 0), 0.6) : box(V(-0.5, -0.3, -0.4), V(0.4, 0.5, 0.3));
  Affine3 B, C;
  if (!randomApproach(rng, false, B, C)) return std::nullopt;
  std::vector<Affine3> keys{B, C};
  if (trial % 4 == 0) keys.insert(keys.begin() + 1, steady::sam(B, 0.5, C) * Affine3::rotation(V(0, 0, 1), 0.5));
  std::vector<steady::Keyframe<3>> fk{{0.0, Affine3()}, {1.0, Affine3()}};
  if (partner_moves) {
    fk = {{0.0, Affine3::rotation(V(U(rng), U(rng), U(rng)), U(rng))},
          {0.37, Affine3::translation(0.3 * V(U(rng), U(rng), U(rng))) * Affine3::rotation(V(U(rng), U(rng), U(rng)), U(rng))},
          {1.0, Affine3::translation(0.3 * V(U(rng), U(rng), U(rng)))}};
  }
  return TwoBodyScene{std::move(moving), std::move(fixed), steady::Motion3::polySam(keys, split),
                      steady::Motion3::polySam(fk, split)};
}

// Random poses of a ball sinking onto the plane z = 0: B above it (height 0.9, small offset and
// tilt), C = T L B with L a turn of 1 to 3 radians about a random axis and, when `deform`, a
// shear and an anisotropic scaling, and T sinking by 0.4 to 0.7.
template <class Rng>
std::pair<steady::Affine3, steady::Affine3> randomSinking(Rng& rng, bool deform) {
  using steady::Affine3;
  std::uniform_real_distribution<double> u(-1, 1);
  const Affine3 B = Affine3::translation(V(0.3 * u(rng), 0.3 * u(rng), 0.9)) * Affine3::rotation(V(u(rng), u(rng), 1), u(rng));
  Affine3 L = Affine3::rotation(V(u(rng), u(rng), u(rng)), 2 + u(rng));
  if (deform) {
    Eigen::Matrix3d shear = Eigen::Matrix3d::Identity();
    shear(0, 2) = 0.3 * u(rng);
    L = L * Affine3(shear, V::Zero()) * Affine3::scaling(V(1.2 + 0.2 * u(rng), 0.8 + 0.1 * u(rng), 1 + 0.2 * u(rng)));
  }
  return {B, Affine3::translation(V(0.5 * u(rng), 0.5 * u(rng), -0.55 + 0.15 * u(rng))) * L * B};
}

// The first time a point set moving along a motion reaches the plane z = 0 from above, by dense
// sampling of the motion (N steps) and bisection (60 halvings) of the first sign change of each
// point's height. Returns 2 when no point reaches the plane.
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
