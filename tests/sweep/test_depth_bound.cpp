// The certified depth bound of a point from the inside test alone (sweep/src/depth_bound.hpp),
// which the envelope reports for the walls it keeps at mouths it could not close
// (Envelope::kept_wall_depth_bound). Checked here against solids whose boundary distance is
// known: half-spaces (tilted the worst way for the 26 probe directions), balls, and thin layers
// of the other side at a surface vertex that only the surface's own probes find.
#include "depth_bound.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

namespace {

using steady::sweep::detail::cubeDirections;
using steady::sweep::detail::depthBound;
using steady::sweep::detail::kDepthClaims;
using V = Eigen::Vector3d;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = 1e-3;
constexpr double kDelta = 1e-12;

// The half-space {x : n . x <= 0} (n a unit vector), exactly.
struct HalfSpace {
  V n;
  bool operator()(const V& x) const { return n.dot(x) <= 0; }
};

// The ball of radius r about the origin, exactly.
struct Ball {
  double r;
  bool operator()(const V& x) const { return x.norm() <= r; }
};

// The angle from unit direction d to the nearest of the 26 probe directions.
double nearestAngle(const V& d) {
  double nearest = -1;
  for (const V& p : cubeDirections()) nearest = std::max(nearest, d.dot(p));
  return std::acos(std::min(1.0, nearest));
}

// The unit direction farthest from the 26 probe directions, and its angle to the nearest: by
// symmetry the cone 0 <= y <= x <= z holds one; a grid over it, then a shrinking local search.
V farthestDirection(double* angle) {
  auto dir = [](double x, double y) { return V(x, y, 1.0).normalized(); };
  double bx = 0, by = 0, worst = 0;
  for (int i = 0; i <= 400; ++i)
    for (int j = 0; j <= i; ++j) {
      const double a = nearestAngle(dir(i / 400.0, j / 400.0));
      if (a > worst) worst = a, bx = i / 400.0, by = j / 400.0;
    }
  for (double h = 1.0 / 400; h > 1e-12; h *= 0.7)
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        const double a = nearestAngle(dir(bx + dx * h, by + dy * h));
        if (a > worst) worst = a, bx += dx * h, by += dy * h;
      }
  *angle = worst;
  return dir(bx, by);
}

TEST(DepthBound, DirectionsAreTheCubesTwentySix) {
  ASSERT_EQ(cubeDirections().size(), 26u);
  for (const V& d : cubeDirections()) EXPECT_NEAR(d.norm(), 1.0, 1e-15);
  double angle = 0;
  farthestDirection(&angle);
  // The documented covering: every direction within about 27.6 degrees of a probe direction
  // (27.569 degrees, at (sqrt 2 - 1, 0.318, 1) and its images).
  EXPECT_NEAR(angle * 180 / M_PI, 27.569, 0.001);
}

// Below a flat boundary along a probe direction: the first claim whose radius reaches it.
TEST(DepthBound, DepthBelowAFlatBoundaryAlongAProbeDirection) {
  const HalfSpace s{V(0, 0, 1)};
  EXPECT_EQ(depthBound(V(0, 0, -0.3 * kEps), kEps, kDelta, s), kEps);
  EXPECT_EQ(depthBound(V(0, 0, -0.99 * kEps), kEps, kDelta, s), kEps);
  EXPECT_EQ(depthBound(V(0, 0, -1.1 * kEps), kEps, kDelta, s), 1.25 * kEps);
  EXPECT_EQ(depthBound(V(0, 0, -1.4 * kEps), kEps, kDelta, s), 1.5 * kEps);
  EXPECT_EQ(depthBound(V(0, 0, -3 * kEps), kEps, kDelta, s), 4 * kEps);
  EXPECT_EQ(depthBound(V(0, 0, -7.9 * kEps), kEps, kDelta, s), 8 * kEps);
  EXPECT_EQ(depthBound(V(0, 0, -9 * kEps), kEps, kDelta, s), kInf);
  // A point outside looks for a point inside.
  EXPECT_EQ(depthBound(V(0, 0, 0.5 * kEps), kEps, kDelta, s), kEps);
  EXPECT_EQ(depthBound(V(0, 0, 1.2 * kEps), kEps, kDelta, s), 1.25 * kEps);
  // The radius leaves four inside-test tolerances: a boundary just inside the claim but beyond
  // that radius is not claimed.
  const double r = kEps - 4 * kDelta;
  EXPECT_EQ(depthBound(V(0, 0, -(r - 1e-6 * kEps)), kEps, kDelta, s), kEps);
  EXPECT_EQ(depthBound(V(0, 0, -(r + 1e-6 * kEps)), kEps, kDelta, s), 1.25 * kEps);
}

// Below a flat boundary whose normal is the direction farthest from every probe: a point at
// depth d is claimed at the first radius at least d / cos(angle).
TEST(DepthBound, DepthBelowAFlatBoundaryTiltedTheWorstWay) {
  double angle = 0;
  const V n = farthestDirection(&angle);
  const HalfSpace s{n};
  const double stretch = 1 / std::cos(angle);  // about 1.13
  const double r = kEps - 4 * kDelta;
  EXPECT_EQ(depthBound(V(-0.98 * r / stretch * n), kEps, kDelta, s), kEps);
  EXPECT_EQ(depthBound(V(-1.02 * r / stretch * n), kEps, kDelta, s), 1.25 * kEps);
}

TEST(DepthBound, CentresOfBalls) {
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, Ball{0.5 * kEps}), kEps);
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, Ball{1.7 * kEps}), 2 * kEps);
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, Ball{5 * kEps}), 8 * kEps);
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, Ball{20 * kEps}), kInf);
}

// A tolerance not far above the inside test's: claims whose radius would not be positive are
// skipped (here all but 8 eps, whose radius is 8 eps - 4 delta = 4e-9).
TEST(DepthBound, ClaimsWithoutARadiusAreSkipped) {
  const double eps = 1e-9, delta = 1e-9;
  const HalfSpace s{V(0, 0, 1)};
  EXPECT_EQ(depthBound(V(0, 0, -1e-12), eps, delta, s), 8 * eps);
  EXPECT_EQ(depthBound(V(0, 0, -4.5e-9), eps, delta, s), kInf);
}

// Thin layers of the other side at a surface vertex, which every cube direction misses: each is
// found by the surface probes made for it, and only with them. x is the origin, the surface's
// normal m is a direction near none of the cube's, and u lies in the surface.
struct ThinLayers : ::testing::Test {
  const V m = V(3, 7, 15).normalized();  // (at least 0.168 from every cube direction's plane)
  const V u = m.unitOrthogonal();
  void SetUp() override {
    // (no cube direction lies within 1e-2 rad of the surface's plane, so none enters a layer of
    // half width 1e-4 eps at radius eps, nor one 1e-3 eps off the surface)
    for (const V& d : cubeDirections()) ASSERT_GT(std::abs(m.dot(d)), 1e-2);
  }
};

// A crack of the outside, 2e-4 eps wide, along the surface from x: found along the surface.
TEST_F(ThinLayers, CrackAlongTheSurfaceIsFoundAlongIt) {
  const auto inside = [&](const V& q) { return !(std::abs(m.dot(q)) < 1e-4 * kEps && u.dot(q) > 0); };
  steady::sweep::detail::SurfaceProbes probes;
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, probes), kInf);
  probes.tangents = {-u, u};
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, probes), kEps);
}

// A wedge of the outside between two faces that meet at x (half angle 1e-2 rad, opening along
// u): found just off a face, a little way into it, not along the face's normal from x.
TEST_F(ThinLayers, WedgeEndingAtTheVertexIsFoundJustOffItsFace) {
  const auto inside = [&](const V& q) { return !(u.dot(q) > 0 && std::abs(m.dot(q)) < 1e-2 * u.dot(q)); };
  steady::sweep::detail::SurfaceProbes probes;
  probes.normals = {m, -m};
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, probes), kInf);
  const V w = m.cross(u);  // (the face's edges at x lie 30 degrees either side of u)
  probes.faces = {{u, std::cos(0.5236) * u + std::sin(0.5236) * w, std::cos(0.5236) * u - std::sin(0.5236) * w, m}};
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, probes), kEps);
}

// A layer of the outside over part of a face's angle at x (44 to 56 degrees from one edge of a
// face whose angle is 80 degrees, its centroid 10 degrees from that edge), from 0.7 eps out,
// between 0.011 and 0.014 of the distance above the face's plane (like the thin cracks beside
// the kept walls of campaign cases 604 and 4214): found just off the face in a direction
// between its edges, nearly at the full radius, with offsets at half octaves (without any one
// of the three it is missed); not towards the centroid.
TEST_F(ThinLayers, LayerOverPartOfAFaceIsFoundBetweenItsEdges) {
  const V w = m.cross(u);
  auto at = [&](double degrees) { return V(std::cos(degrees * M_PI / 180) * u + std::sin(degrees * M_PI / 180) * w); };
  const auto inside = [&](const V& q) {
    const double r = q.norm(), angle = std::atan2(w.dot(q), u.dot(q)) * 180 / M_PI, rise = m.dot(q) / r;
    return !(r > 0.7 * kEps && angle > 44 && angle < 56 && rise > 0.011 && rise < 0.014);
  };
  steady::sweep::detail::SurfaceProbes probes;
  probes.normals = {m, -m};
  probes.faces = {{at(10), at(10), at(10), m}};  // (towards the centroid only)
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, probes), kInf);
  probes.faces = {{at(10), at(0), at(80), m}};
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, probes), kEps);
}

// A layer of the outside tilted 11 to 20 degrees off a face at x, over 20 to 60 degrees of its
// angle there, from 0.6 eps out (like the outside beside a fin of three faces of campaign case
// 8054, a star polySAM): found just off the face at offsets up to half the radius, which the
// probes along the surface's normals, its tangents and the cube's directions all miss.
TEST_F(ThinLayers, LayerTiltedOffAFaceIsFoundAtLargeOffsets) {
  const V w = m.cross(u);
  auto at = [&](double degrees) { return V(std::cos(degrees * M_PI / 180) * u + std::sin(degrees * M_PI / 180) * w); };
  const auto inside = [&](const V& q) {
    const double r = q.norm(), angle = std::atan2(w.dot(q), u.dot(q)) * 180 / M_PI;
    const double tilt = std::asin(std::clamp(m.dot(q) / r, -1.0, 1.0)) * 180 / M_PI;
    return !(r > 0.6 * kEps && angle > 20 && angle < 60 && tilt > 11 && tilt < 20);
  };
  steady::sweep::detail::SurfaceProbes probes;
  probes.normals = {m, -m};
  probes.tangents = {at(0), at(80)};
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, probes), kInf);
  probes.faces = {{at(10), at(0), at(80), m}};
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, probes), kEps);
}

// A layer of the outside 1e-3 eps beside the surface and 1e-3 eps thick: crossed along the
// normal at a radius halved 9 times, skipped at the claims' own radii.
TEST_F(ThinLayers, LayerBesideTheSurfaceIsCrossedAtFineRadii) {
  const auto inside = [&](const V& q) { return !(m.dot(q) > 1e-3 * kEps && m.dot(q) < 2e-3 * kEps); };
  steady::sweep::detail::SurfaceProbes probes;
  probes.normals = {-m, m};
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, probes), kEps);
  probes.normals = {};
  EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, probes), kInf);
}

// Seeded property: for random half-spaces and balls, and random points near their boundary,
// the bound is never below the true distance to the boundary (it is certified), and it is the
// first claim at or above 1.13 times that distance (the probes are not needlessly coarse).
TEST(DepthBound, NeverBelowTheTrueDistanceAndNotLoose) {
  std::mt19937_64 rng(20261127);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> depth(-9 * kEps, 9 * kEps);
  int checked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const V n = V(g(rng), g(rng), g(rng)).normalized();
    const double d = depth(rng);
    const V along = V(g(rng), g(rng), g(rng)).cross(n);  // (any point of the plane, offset)
    const V x = along + d * n;                            // signed distance d to the plane
    const HalfSpace s{n};
    const double b = depthBound(x, kEps, kDelta, s);
    const double dist = std::abs(d);
    ASSERT_GE(b, dist) << "trial " << trial;
    // The first claim whose radius reaches 1.13 times the distance (the covering angle's factor
    // 1 / cos 27.6 deg is 1.1280) is never exceeded.
    double loose = kInf;
    for (const double c : kDepthClaims)
      if (c * kEps - 4 * kDelta >= 1.1281 * dist) {
        loose = c * kEps;
        break;
      }
    EXPECT_LE(b, loose) << "trial " << trial << ", depth " << d / kEps << " eps";
    ++checked;
  }
  for (int trial = 0; trial < 500; ++trial) {
    const double radius = std::abs(depth(rng)) + 0.1 * kEps;
    const V x = V(g(rng), g(rng), g(rng)).normalized() * (radius * std::uniform_real_distribution<double>(0, 1.5)(rng));
    const double b = depthBound(x, kEps, kDelta, Ball{radius});
    ASSERT_GE(b, std::abs(radius - x.norm())) << "ball trial " << trial;
    ++checked;
  }
  EXPECT_EQ(checked, 2500);
}

// The pair of the first two normals (here n and -n, no witness asked): when x + r n and
// x - r n get different answers, x itself is never tested, and the bound is what the search
// without the pair gives (a witness asked for turns the pair off).
TEST(DepthBound, AntipodalNormalsSettleWithoutTestingThePoint) {
  using steady::sweep::detail::SurfaceProbes;
  const V n = V(1, 2, 2) / 3.0;
  SurfaceProbes p;
  p.normals = {n, -n};
  V witness;
  // A flat boundary 0.3 eps from x: the two probes straddle it, so two inside tests.
  {
    int calls = 0;
    const V x = -0.3 * kEps * n;
    const auto inside = [&](const V& q) { return ++calls, n.dot(q) <= 0; };
    EXPECT_EQ(depthBound(x, kEps, kDelta, inside, p), kEps);
    EXPECT_EQ(calls, 2);
    EXPECT_EQ(depthBound(x, kEps, kDelta, inside, p, &witness), kEps);
    EXPECT_EQ(calls, 2 + 2);  // x, then x + r n (outside): the first probe that differs
  }
  // x in a slab of the outside 0.2 eps thick, both probes inside: x is tested, once per probe.
  {
    int calls = 0;
    const auto inside = [&](const V& q) { return ++calls, std::abs(n.dot(q)) > 0.1 * kEps; };
    EXPECT_EQ(depthBound(V::Zero(), kEps, kDelta, inside, p), kEps);
    EXPECT_EQ(calls, 3);  // the two probes (known), then x
  }
}

// Seeded property: for random half-spaces, balls and slabs, and random points near their
// boundaries, the bound with the pair equals the bound of the search without it (a witness
// asked for), for antipodal normals and, in one trial of four, any two.
TEST(DepthBound, AntipodalPairGivesTheSameBound) {
  using steady::sweep::detail::SurfaceProbes;
  std::mt19937_64 rng(20261201);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> offset(-3 * kEps, 3 * kEps), width(0.01 * kEps, 2 * kEps);
  int differ = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const V n = V(g(rng), g(rng), g(rng)).normalized();
    const V m = trial % 2 ? n : V(V(g(rng), g(rng), g(rng)).normalized());  // (the probes' normal)
    const V x = V(g(rng), g(rng), g(rng)).cross(n) + offset(rng) * n;
    const double w = width(rng), r = std::abs(offset(rng)) + 0.05 * kEps;
    std::function<bool(const V&)> inside;
    switch (trial % 3) {
      case 0: inside = [n](const V& q) { return n.dot(q) <= 0; }; break;
      case 1: inside = [n, w](const V& q) { return std::abs(n.dot(q)) > w; }; break;
      default: inside = [c = V(x + offset(rng) * n), r](const V& q) { return (q - c).norm() <= r; };
    }
    SurfaceProbes p;
    p.normals = {m, trial % 4 == 3 ? V(V(g(rng), g(rng), g(rng)).normalized()) : V(-m)};
    V witness;
    const double with_pair = depthBound(x, kEps, kDelta, inside, p);
    const double without = depthBound(x, kEps, kDelta, inside, p, &witness);
    ASSERT_EQ(with_pair, without) << "trial " << trial;
    differ += inside(x + (kEps - 4 * kDelta) * p.normals[0]) != inside(x + (kEps - 4 * kDelta) * p.normals[1]);
  }
  // (both ways of the pair are met)
  EXPECT_GT(differ, 300);
  EXPECT_LT(differ, 2700);
}

}  // namespace
