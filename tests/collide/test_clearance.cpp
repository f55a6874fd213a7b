// Clearance (minimum distance over a motion): the bracket [lower, upper] must contain the true
// minimum, upper must be a distance actually attained, and the bracket must be as narrow as
// asked. Oracles: closed forms (a box gliding above a slab, axis-aligned boxes in translation)
// and, for a convex body above a flat plate, the lowest vertex height minimised over time.
#include <steady/collide/collide.hpp>
#include <steady/core/error.hpp>

#include "support/meshes.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <vector>

namespace {

using steady::Affine3;
using steady::Clearance;
using steady::ClearanceOptions;
using steady::Motion3;
using steady::StaticScene;
using steady_test::box;
using steady_test::grid;
using steady_test::Mesh;
using steady_test::uvSphere;
using steady_test::V;

// The bracket is valid for the true minimum `truth` (known to within `truth_tol`) and as narrow
// as the options ask.
void expectBracket(const Clearance& c, double truth, double truth_tol, double diag, const ClearanceOptions& o = {}) {
  EXPECT_LE(c.lower, truth + truth_tol);
  EXPECT_GE(c.upper, truth - truth_tol);
  EXPECT_LE(c.lower, c.upper);
  EXPECT_LT(c.evaluations, o.max_evaluations);  // converged, not stopped by the cap
  EXPECT_LE(c.upper - c.lower, std::max(o.absolute_gap * diag, o.relative_gap * c.upper) * (1 + 1e-12));
  EXPECT_NEAR((c.point_a - c.point_b).norm(), c.upper, 1e-12 * (1 + c.upper));
}

TEST(Clearance, BoxGlidingAboveASlabKeepsItsHeight) {
  const Mesh slab = box(V(-10, -10, -2), V(10, 10, -1));
  const StaticScene scene(slab.v, slab.f);
  const Mesh cube = box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5));
  // Bottom face at z = -0.75 the whole time: 0.25 above the slab; a quarter turn about z.
  const Motion3 m = Motion3::polySam(std::vector<Affine3>{
      Affine3::translation(V(-3, 0, -0.25)), Affine3::translation(V(3, 1, -0.25)) * Affine3::rotation(V(0, 0, 1), M_PI / 2)});
  const Clearance c = scene.clearance(cube.v, cube.f, m);
  expectBracket(c, 0.25, 1e-12, std::sqrt(1200.0 + 1));
  EXPECT_NEAR(c.upper, 0.25, 1e-12);
  EXPECT_NEAR(c.point_b.z(), -1.0, 1e-12);
  EXPECT_GE(c.t, 0.0);
  EXPECT_LE(c.t, 1.0);
}

TEST(Clearance, TouchingMeshesHaveZeroLowerBound) {
  const Mesh slab = box(V(-10, -10, -11), V(10, 10, -1.2));
  const StaticScene scene(slab.v, slab.f);
  const Mesh cube = box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5));
  const Motion3 m = Motion3::polySam(std::vector<Affine3>{Affine3::translation(V(0, 0, 2)), Affine3::translation(V(0, 0, -2))});
  const Clearance c = scene.clearance(cube.v, cube.f, m);
  EXPECT_EQ(c.lower, 0.0);
  EXPECT_LE(c.upper, 1e-9 * 30);  // within the contact tolerance
  EXPECT_NEAR(c.t, 2.7 / 4, 1e-12);
}

// Persistent crossing with no contact event: a thin box stuck through the slab's top face,
// sliding along it (away from the diagonal of the slab's top face). The distance is 0 all the
// time, with no feature contact event: no vertex meets a plane, no edge meets an edge.
TEST(Clearance, PersistentCrossingIsZero) {
  const Mesh slab = box(V(-10, -10, -2), V(10, 10, -1));
  const StaticScene scene(slab.v, slab.f);
  const Mesh rod = box(V(-0.1, -0.1, -1.5), V(0.1, 0.1, -0.5));
  const Motion3 m = Motion3::polySam(std::vector<Affine3>{Affine3::translation(V(1, 2, 0)), Affine3::translation(V(3, 1, 0))});
  ASSERT_FALSE(scene.touches(rod.v, rod.f, m));
  const Clearance c = scene.clearance(rod.v, rod.f, m);
  EXPECT_EQ(c.lower, 0.0);
  EXPECT_EQ(c.upper, 0.0);
}

// A convex body above a flat plate that extends beyond it: the distance at each time is the
// lowest vertex height. Seeded screw and general affine motions that pass close to the plate.
TEST(Clearance, ConvexBodyAboveAPlateMatchesTheLowestVertex) {
  const Mesh plate = grid(40, 4.0);
  const StaticScene scene(plate.v, plate.f);
  const Mesh ball = uvSphere(12, 24, 0.5);
  std::mt19937_64 rng(5551212);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 8; ++k) {
    const Affine3 B = Affine3::translation(V(0.3 * u(rng), 0.3 * u(rng), 1.2)) * Affine3::rotation(V(u(rng), u(rng), 1), u(rng));
    Affine3 L = Affine3::rotation(V(u(rng), u(rng), u(rng)), 1.5 + u(rng));
    if (k % 2 == 1) L = L * Affine3::scaling(V(1.1 + 0.1 * u(rng), 0.9 + 0.05 * u(rng), 1.0));
    // End higher than the start: the lowest height is in the middle, between 0.05 and 0.6.
    const Affine3 C = Affine3::translation(V(0.5 * u(rng), 0.5 * u(rng), 0.3 * u(rng))) * L * B;
    const Motion3 m = Motion3::polySam(std::vector<Affine3>{B, C});
    auto low = [&](double t) {
      const Affine3 P = m.pose(t);
      double z = 1e300;
      for (const V& p : ball.v) z = std::min(z, P.applyPoint(p).z());
      return z;
    };
    // Dense samples, then golden-section refinement around the best (the lowest height is a
    // minimum of smooth curves: refine each neighbourhood of a sample minimum).
    const int N = 2000;
    double best = 1e300, tb = 0;
    for (int i = 0; i <= N; ++i) {
      const double z = low(static_cast<double>(i) / N);
      if (z < best) best = z, tb = static_cast<double>(i) / N;
    }
    double a = std::max(0.0, tb - 1.0 / N), b = std::min(1.0, tb + 1.0 / N);
    for (int it = 0; it < 100; ++it) {
      const double x1 = b - 0.618033988749895 * (b - a), x2 = a + 0.618033988749895 * (b - a);
      (low(x1) < low(x2) ? b : a) = low(x1) < low(x2) ? x2 : x1;
    }
    const double truth = std::min(best, low(0.5 * (a + b)));
    if (truth <= 0.01) continue;  // touching: covered elsewhere
    const ClearanceOptions o;
    const Clearance c = scene.clearance(ball.v, ball.f, m, o);
    SCOPED_TRACE("motion " + std::to_string(k) + " truth " + std::to_string(truth));
    expectBracket(c, truth, 1e-12, std::sqrt(2 * 64.0), o);
    EXPECT_NEAR(c.point_b.z(), 0.0, 1e-12);
    EXPECT_NEAR(low(c.t), c.upper, 1e-12);  // upper is the distance at t
    // A tighter request gives a tighter, still valid bracket.
    ClearanceOptions tight;
    tight.relative_gap = 1e-6;
    const Clearance d = scene.clearance(ball.v, ball.f, m, tight);
    expectBracket(d, truth, 1e-12, std::sqrt(2 * 64.0), tight);
  }
}

// Two axis-aligned boxes in translation: the distance is the norm of the per-axis gaps, a
// convex function of time, minimised by ternary search.
TEST(Clearance, TwoTranslatingBoxesMatchTheClosedForm) {
  const Mesh unit = box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5));
  std::mt19937_64 rng(424242);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 10; ++k) {
    const V a0(-3, u(rng), u(rng)), a1(3, u(rng), 1.5 + u(rng));
    const V b0(3, 1.4 + u(rng), u(rng)), b1(-3, 1.4 + u(rng), u(rng));
    const Motion3 ma = Motion3::polySam(std::vector<Affine3>{Affine3::translation(a0), Affine3::translation(a1)});
    const Motion3 mb = Motion3::polySam(std::vector<Affine3>{Affine3::translation(b0), Affine3::translation(b1)});
    auto dist = [&](double t) {
      const V d = ((1 - t) * a0 + t * a1 - (1 - t) * b0 - t * b1).cwiseAbs() - V::Ones();
      return d.cwiseMax(0.0).norm();
    };
    double lo = 0, hi = 1;
    for (int it = 0; it < 200; ++it) {
      const double x1 = lo + (hi - lo) / 3, x2 = hi - (hi - lo) / 3;
      (dist(x1) <= dist(x2) ? hi : lo) = dist(x1) <= dist(x2) ? x2 : x1;
    }
    const double truth = dist(0.5 * (lo + hi));
    const Clearance c = steady::clearance({unit.v, unit.f, ma}, {unit.v, unit.f, mb});
    SCOPED_TRACE("pair " + std::to_string(k) + " truth " + std::to_string(truth));
    expectBracket(c, truth, 1e-12, std::sqrt(3.0));
    EXPECT_NEAR(dist(c.t), c.upper, 1e-12);
  }
}

TEST(Clearance, BadOptionsAreTypedErrors) {
  const Mesh slab = box(V(-10, -10, -2), V(10, 10, -1));
  const StaticScene scene(slab.v, slab.f);
  const Mesh cube = box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5));
  const Motion3 m = Motion3::polySam(std::vector<Affine3>{Affine3::translation(V(0, 0, 1)), Affine3::translation(V(1, 0, 1))});
  ClearanceOptions o;
  o.relative_gap = 0;
  o.absolute_gap = 0;
  EXPECT_THROW(scene.clearance(cube.v, cube.f, m, o), steady::Error);
  o = {};
  o.relative_gap = std::nan("");
  EXPECT_THROW(scene.clearance(cube.v, cube.f, m, o), steady::Error);
  o = {};
  o.max_evaluations = 0;
  EXPECT_THROW(scene.clearance(cube.v, cube.f, m, o), steady::Error);
}

}  // namespace
