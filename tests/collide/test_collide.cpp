// Mesh contact queries: the cube-on-slab answers, translations, each feature type, bad input,
// and a seeded property test against an independent oracle (dense sampling of the motion with an
// exact triangle/triangle intersection test, then bisection).
#include <steady/collide/collide.hpp>

#include "collide/plane_oracle.hpp"
#include "support/meshes.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

namespace {

using steady::Affine3;
using steady::Contact;
using steady::ContactType;
using steady::Motion3;
using steady::StaticScene;
using steady_test::box;
using steady_test::Faces;
using steady_test::grid;
using steady_test::Mesh;
using steady_test::octahedron;
using steady_test::uvSphere;
using steady_test::V;

double cubeFirstContact(double theta) {  // see test_span_roots.cpp
  double best = 2;
  for (double y : {1.5, 2.5})
    for (double z : {-0.5, 0.5}) {
      const double R = std::hypot(y, z), a = std::atan2(y, z), base = std::acos(-1.2 / R);
      for (int k = -2; k <= 2; ++k)
        for (double sg : {1.0, -1.0}) {
          const double s = (sg * base + 2 * M_PI * k - a) / theta;
          if (s >= 0 && s <= 1) best = std::min(best, s);
        }
    }
  return best;
}

TEST(Collide, CubeOnSlabFirstContact) {
  const Mesh slab = box(V(-10, -10, -11), V(10, 10, -1.2));
  const StaticScene scene(slab.v, slab.f);
  const Mesh cube = box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5));
  for (double theta : {1.0, 2.0, 3.0}) {
    const Affine3 B = Affine3::translation(V(0, 2, 0));
    const Affine3 C = Affine3::translation(V(0.7, 0, 0)) * Affine3::rotation(V(1, 0, 0), -theta) * B;
    const Motion3 motion = Motion3::polySam(std::vector<Affine3>{B, C});
    steady::CollideStats stats;
    const auto c = scene.firstContact(cube.v, cube.f, motion, {}, &stats);
    ASSERT_TRUE(c.has_value()) << "theta " << theta;
    EXPECT_NEAR(c->t, cubeFirstContact(theta), 1e-11) << "theta " << theta;
    EXPECT_LE(c->t, cubeFirstContact(theta) + 1e-12);  // never late
    EXPECT_NEAR(c->point.z(), -1.2, 1e-9);
    EXPECT_NEAR(std::abs(c->normal.z()), 1.0, 1e-12);
    EXPECT_TRUE(c->certain);
    EXPECT_GT(stats.candidate_pairs, 0u);
    EXPECT_TRUE(scene.touches(cube.v, cube.f, motion));
  }
}



// Fine meshes on long motions: the swept boxes of a whole slice are many triangles wide, so the
// broad phase halves intervals before and after its Embree queries. The body is convex and the
// grid flat, so the first contact is the first time a vertex reaches z = 0: the oracle samples
// each vertex's height densely and bisects its first sign change.
TEST(Collide, FineMeshesOnLongMotionsKeepTheExactFirstContact) {
  const Mesh plate = grid(120, 3.0);  // 28,800 triangles of side 0.05
  const StaticScene scene(plate.v, plate.f);
  const Mesh ball = uvSphere(24, 48, 0.5);  // 2,208 triangles
  // Seeded motions: turns of 1 to 3 radians about random axes while sinking by 0.4 to 0.7; every
  // other one adds a shear and an anisotropic scaling.
  std::mt19937_64 rng(8675309);
  std::vector<std::pair<Affine3, Affine3>> motions;
  for (int k = 0; k < 12; ++k) motions.push_back(steady_test::randomSinking(rng, k % 2 == 1));
  for (std::size_t k = 0; k < motions.size(); ++k) {
    const Motion3 motion = Motion3::polySam(std::vector<Affine3>{motions[k].first, motions[k].second});
    const double oracle = steady_test::firstPlaneCrossing(motion, ball.v);
    ASSERT_LT(oracle, 1.0) << "motion " << k << " must reach the plate";
    const auto c = scene.firstContact(ball.v, ball.f, motion);
    ASSERT_TRUE(c.has_value()) << "motion " << k;
    EXPECT_NEAR(c->t, oracle, 1e-9) << "motion " << k;
    EXPECT_LE(c->t, oracle + 1e-12) << "motion " << k;
    EXPECT_NEAR(c->point.z(), 0.0, 1e-9);
  }
}

TEST(Collide, TranslationOntoAFaceEdgeAndVertex) {
  // A cube centred at z = 2 falling by 4 onto the slab: its bottom face (at 1.5 - 4 s) reaches
  // z = -1.2 at s = 2.7 / 4.
  const Mesh slab = box(V(-10, -10, -11), V(10, 10, -1.2));
  const StaticScene scene(slab.v, slab.f);
  const Mesh cube = box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5));
  const Affine3 B = Affine3::translation(V(0, 0, 2)), C = Affine3::translation(V(0, 0, -2));
  const Motion3 motion = Motion3::polySam(std::vector<Affine3>{B, C});
  const auto c = scene.firstContact(cube.v, cube.f, motion);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->t, (2 - 0.5 + 1.2) / 4, 1e-12);
  // Moving the other way: never touches.
  EXPECT_FALSE(scene.touches(cube.v, cube.f, Motion3::polySam(std::vector<Affine3>{B, Affine3::translation(V(0, 0, 6))})));

  // Edge/edge only: a cube turned 45 degrees about x (an edge lowest) moving along x across a
  // static cube turned 45 degrees about y (an edge highest): the edges cross without any vertex
  // touching a face first. Lowest moving edge at z = 3 - sqrt(0.5) - 4 s; highest static edge at
  // z = sqrt(0.5): contact at s = (3 - 2 sqrt(0.5)) / 4.
  const Affine3 down45 = Affine3::rotation(V(1, 0, 0), M_PI / 4);
  const Mesh mover = cube;
  Mesh fixed = cube;
  for (V& p : fixed.v) p = Affine3::rotation(V(0, 1, 0), M_PI / 4).applyPoint(p);
  const StaticScene scene2(fixed.v, fixed.f);
  const Motion3 fall = Motion3::polySam(std::vector<Affine3>{Affine3::translation(V(0, 0, 3)) * down45,
                                                              Affine3::translation(V(0, 0, -1)) * down45});
  const auto e = scene2.firstContact(mover.v, mover.f, fall);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->type, ContactType::EdgeEdge);
  EXPECT_NEAR(e->t, (3 - 2 * std::sqrt(0.5)) / 4, 1e-12);
  EXPECT_NEAR(e->point.z(), std::sqrt(0.5), 1e-9);
}

TEST(Collide, FaceVertexWhenAStaticTipMeetsAMovingFace) {
  // A static upward tip (octahedron top vertex at z = 1) and a large plate falling onto it: the
  // plate's lower face reaches the tip first; only a face/vertex feature can see it (no moving
  // vertex or edge is near the tip).
  const Mesh tip = octahedron(V(0, 0, 0), 1.0);
  const StaticScene scene(tip.v, tip.f);
  const Mesh plate = box(V(-5, -4, -0.1), V(5, 6, 0.1));  // diagonals miss the tip
  const Affine3 B = Affine3::translation(V(0, 0, 3));
  const Motion3 drop = Motion3::polySam(std::vector<Affine3>{B, Affine3::translation(V(0, 0, -1))});
  const auto c = scene.firstContact(plate.v, plate.f, drop);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->type, ContactType::FaceVertex);
  EXPECT_EQ(c->b[0], 4);  // the top vertex
  EXPECT_NEAR(c->t, (3 - 0.1 - 1) / 4, 1e-12);
}

TEST(Collide, FaceVertexOnAnExactHalfTurn) {
  // A plate (x in [-5, 5], y in [1, 3], z in [-0.1, 0.1]) turns an exact half turn about the
  // x axis and sweeps its face over a tiny static octahedron (radius r, lowest vertex at distance
  // 2 from the axis) on the side the span actually turns through. Only a static vertex against
  // the moving face sees the contact. The first one is the octahedron vertex at (0, r, 2 + r) in
  // the turning plane: (2 + r) cos(th) - r sin(th) = 0.1, th = acos(0.1 / R) - atan2(r, 2 + r).
  // Regression: the static-vertex trajectories came from the EAR log of A^-1, which at an exact
  // half turn turns the same way as the span (a mirrored path that never meets the tip).
  const double r = 0.05;
  const Mesh plate = box(V(-5, 1, -0.1), V(5, 3, 0.1));
  const Motion3 turn = Motion3::polySam(std::vector<Affine3>{Affine3(), Affine3::rotation(V(1, 0, 0), M_PI)});
  const double side = turn.span(0).pose(0.5).applyPoint(V(0, 1, 0)).z() > 0 ? 1.0 : -1.0;
  Mesh tip = octahedron(V(0, 0, 2 + r), r);
  for (V& p : tip.v) p.z() *= side;
  if (side < 0)
    for (auto& f : tip.f) std::swap(f[1], f[2]);
  const StaticScene scene(tip.v, tip.f);
  const auto c = scene.firstContact(plate.v, plate.f, turn);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->type, ContactType::FaceVertex);
  const double R = std::hypot(2 + r, r);
  EXPECT_NEAR(c->t, (std::acos(0.1 / R) - std::atan2(r, 2 + r)) / M_PI, 1e-9);
}

TEST(Collide, AllContactsAreOrderedAndMerged) {
  const Mesh slab = box(V(-10, -10, -11), V(10, 10, -1.2));
  const StaticScene scene(slab.v, slab.f);
  const Mesh cube = box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5));
  const Affine3 B = Affine3::translation(V(0, 2, 0));
  const Affine3 C = Affine3::translation(V(0.7, 0, 0)) * Affine3::rotation(V(1, 0, 0), -1.0) * B;
  const auto all = scene.contacts(cube.v, cube.f, Motion3::polySam(std::vector<Affine3>{B, C}));
  ASSERT_FALSE(all.empty());
  EXPECT_NEAR(all.front().t, cubeFirstContact(1.0), 1e-11);
  for (std::size_t i = 1; i < all.size(); ++i) EXPECT_LE(all[i - 1].t, all[i].t);
  for (std::size_t i = 1; i < all.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_FALSE(all[i].type == all[j].type && all[i].a == all[j].a && all[i].b == all[j].b &&
                   std::abs(all[i].t - all[j].t) < 1e-9)
          << "duplicate event " << i << " and " << j;
}

TEST(Collide, BadInputGivesTypedErrors) {
  const Mesh slab = box(V(-1, -1, -1), V(1, 1, 0));
  auto code = [](auto f) {
    try {
      f();
    } catch (const steady::Error& e) {
      return e.code();
    }
    return steady::ErrorCode::InvalidFile;  // "no error"
  };
  EXPECT_EQ(code([&] { StaticScene s({}, {}); }), steady::ErrorCode::DegenerateInput);
  EXPECT_EQ(code([&] { StaticScene s(slab.v, {{0, 1, 99}}); }), steady::ErrorCode::InvalidArgument);
  EXPECT_EQ(code([&] { StaticScene s(slab.v, {{0, 1, 1}}); }), steady::ErrorCode::DegenerateInput);
  std::vector<V> bad = slab.v;
  bad[3].x() = NAN;
  EXPECT_EQ(code([&] { StaticScene s(bad, slab.f); }), steady::ErrorCode::NonFinite);
  const StaticScene scene(slab.v, slab.f);
  const Motion3 m = Motion3::polySam(std::vector<Affine3>{Affine3(), Affine3::translation(V(1, 0, 0))});
  EXPECT_EQ(code([&] { scene.firstContact(bad, slab.f, m); }), steady::ErrorCode::NonFinite);
  steady::CollideOptions o;
  o.slices = 0;
  EXPECT_EQ(code([&] { scene.firstContact(slab.v, slab.f, m, o); }), steady::ErrorCode::InvalidArgument);
}

TEST(CollideTwoMoving, StaticPartnerGivesTheStaticAnswer) {
  const Mesh slab = box(V(-10, -10, -11), V(10, 10, -1.2));
  const Mesh cube = box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5));
  const Affine3 B = Affine3::translation(V(0, 2, 0));
  const Affine3 C = Affine3::translation(V(0.7, 0, 0)) * Affine3::rotation(V(1, 0, 0), -1.0) * B;
  const Motion3 motion = Motion3::polySam(std::vector<Affine3>{B, C});
  const Motion3 still = Motion3::polySam(std::vector<Affine3>{Affine3(), Affine3()});
  const auto c = steady::firstContact({cube.v, cube.f, motion}, {slab.v, slab.f, still});
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->t, cubeFirstContact(1.0), 1e-11);
  EXPECT_TRUE(c->certain);
}

TEST(CollideTwoMoving, HeadOnTranslations) {
  // Faces at -2.5 + 4t and 2.5 - 4t meet at t = 5/8; the key times of the two motions differ.
  const Mesh cube = box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5));
  const Motion3 ma = Motion3::polySam(std::vector<steady::Keyframe<3>>{
      {0.0, Affine3::translation(V(-3, 0, 0))}, {0.3, Affine3::translation(V(-1.8, 0, 0))}, {1.0, Affine3::translation(V(1, 0, 0))}});
  const Motion3 mb = Motion3::polySam(std::vector<steady::Keyframe<3>>{
      {0.0, Affine3::translation(V(3, 0.2, 0))}, {0.5, Affine3::translation(V(1, 0.2, 0))}, {1.0, Affine3::translation(V(-1, 0.2, 0))}});
  const auto c = steady::firstContact({cube.v, cube.f, ma}, {cube.v, cube.f, mb});
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->t, 0.625, 1e-12);
  EXPECT_NEAR(c->point.x(), 0.0, 1e-9);
  EXPECT_EQ(c->span, 1u);  // a's second span (0.3 .. 1)
}

TEST(CollideTwoMoving, CarriedTogetherNeverTouch) {
  // Both bodies carried by the same screw G^t (A_t = G^t X, B_t = G^t Y): the relative pose never
  // changes, so separated bodies never touch, however far the screw turns.
  const Mesh cube = box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5));
  const Affine3 G = Affine3::translation(V(0.3, -0.2, 1.0)) * Affine3::rotation(V(1, 2, 3), 2.5);
  const Affine3 X = Affine3::translation(V(0, 0, 0)), Y = Affine3::translation(V(1.2, 0.1, 0)) * Affine3::rotation(V(0, 0, 1), 0.3);
  const Motion3 ma = Motion3::polySam(std::vector<Affine3>{X, G * X});
  const Motion3 mb = Motion3::polySam(std::vector<Affine3>{Y, G * Y});
  EXPECT_FALSE(steady::firstContact({cube.v, cube.f, ma}, {cube.v, cube.f, mb}).has_value());
  // Closer, their top faces are coplanar and overlap: they touch from the start and throughout.
  const Affine3 Z = Affine3::translation(V(0.9, 0, 0));
  const auto c = steady::firstContact({cube.v, cube.f, ma}, {cube.v, cube.f, Motion3::polySam(std::vector<Affine3>{Z, G * Z})});
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->t, 0.0);
  EXPECT_EQ(c->crossing, 0);
}

// ---- independent oracle ------------------------------------------------------------------------

// Whether segment [p, q] meets triangle (a, b, c) (generic position: no coplanarity handling).
bool segmentHitsTriangle(const V& p, const V& q, const V& a, const V& b, const V& c) {
  const V d = q - p, e1 = b - a, e2 = c - a;
  const V h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-300) return false;
  const double inv = 1.0 / det;
  const V s = p - a;
  const double u = s.dot(h) * inv;
  if (u < 0 || u > 1) return false;
  const V qv = s.cross(e1);
  const double v = d.dot(qv) * inv;
  if (v < 0 || u + v > 1) return false;
  const double t = e2.dot(qv) * inv;
  return t >= 0 && t <= 1;
}

bool trianglesIntersect(const std::array<V, 3>& A, const std::array<V, 3>& B) {
  for (int i = 0; i < 3; ++i) {
    if (segmentHitsTriangle(A[i], A[(i + 1) % 3], B[0], B[1], B[2])) return true;
    if (segmentHitsTriangle(B[i], B[(i + 1) % 3], A[0], A[1], A[2])) return true;
  }
  return false;
}

bool meshesIntersect(const Mesh& moving, const Affine3& pose, const Mesh& fixed) {
  std::vector<V> w(moving.v.size());
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = pose.applyPoint(moving.v[i]);
  for (const auto& f : moving.f)
    for (const auto& g : fixed.f)
      if (trianglesIntersect({w[f[0]], w[f[1]], w[f[2]]}, {fixed.v[g[0]], fixed.v[g[1]], fixed.v[g[2]]})) return true;
  return false;
}

// Seeded random scenes: an octahedron or a box on a random SAM (or 2-span polySAM) near a
// static octahedron or box (or, with both_moving, a box moving on its own polySAM with other key
// times). The oracle samples 1000 times per unit time, then bisects the first sample interval
// where the surfaces intersect. steady must never be later than the oracle (1e-9), agree with it
// (1e-9) unless it found a contact the sampling stepped over, and such an earlier contact must be
// real: the surfaces intersect within one sample step after it, or it is a touch (crossing 0).
void randomScenes(bool both_moving, int trials, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  int contacts = 0, none = 0, earlier = 0;
  double worst = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const auto scene = steady_test::twoBodyScene(rng, trial, both_moving);
    if (!scene) continue;
    const Mesh &fixed = scene->fixed, &moving = scene->moving;
    const Motion3 &motion = scene->motion, &partner = scene->partner;
    const auto got = steady::firstContact({moving.v, moving.f, motion}, {fixed.v, fixed.f, partner});
    auto intersect = [&](double t) {
      Mesh posed = fixed;
      const Affine3 P = partner.pose(t);
      for (V& p : posed.v) p = P.applyPoint(p);
      return meshesIntersect(moving, motion.pose(t), posed);
    };
    const int N = 2000;
    double t_oracle = -1;
    for (int k = 0; k <= N; ++k) {
      const double t = static_cast<double>(k) / N;
      if (!intersect(t)) continue;
      if (k == 0) {
        t_oracle = 0;
        break;
      }
      double lo = static_cast<double>(k - 1) / N, hi = t;
      while (hi - lo > 1e-13) {
        const double mid = 0.5 * (lo + hi);
        (intersect(mid) ? hi : lo) = mid;
      }
      t_oracle = hi;
      break;
    }
    auto realContact = [&](const Contact& c) {
      if (c.crossing == 0) return true;
      for (int k = 1; k <= 200; ++k)
        if (intersect(c.t + k * 1e-2 / N)) return true;
      return false;
    };
    if (t_oracle < 0) {
      ++none;
      if (got) {
        ++earlier;
        EXPECT_TRUE(realContact(*got)) << "trial " << trial << ": contact at " << got->t << " but the oracle sees none";
      }
      continue;
    }
    ++contacts;
    ASSERT_TRUE(got.has_value()) << "trial " << trial << ": missed the contact at " << t_oracle;
    EXPECT_LE(got->t, t_oracle + 1e-9) << "trial " << trial << ": late";
    EXPECT_TRUE(got->certain) << "trial " << trial;
    if (got->t < t_oracle - 1e-9) {
      ++earlier;
      EXPECT_TRUE(realContact(*got)) << "trial " << trial << ": contact at " << got->t << " before the oracle's "
                                     << t_oracle << " is not followed by an intersection";
    } else {
      worst = std::max(worst, std::abs(got->t - t_oracle));
    }
  }
  EXPECT_GT(contacts, trials / 2);
  std::printf("contacts %d, no contact %d, earlier than sampling %d, worst time difference %.3g\n", contacts, none,
              earlier, worst);
}

TEST(CollideOracle, StaticSceneFirstContactAgreesWithSampling) {
  std::mt19937_64 rng(2718281828);
  int contacts = 0, none = 0, earlier = 0;
  double worst = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Mesh fixed = trial % 2 ? octahedron(V(0, 0, 0), 1.0) : box(V(-0.8, -0.6, -0.7), V(0.7, 0.9, 0.6));
    const Mesh moving = trial % 3 ? octahedron(V(0, 0, 0), 0.6) : box(V(-0.5, -0.3, -0.4), V(0.4, 0.5, 0.3));
    const StaticScene scene(fixed.v, fixed.f);
    Affine3 B, C;
    if (!steady_test::randomApproach(rng, false, B, C)) continue;
    const Motion3 motion = Motion3::polySam(std::vector<Affine3>{B, C});
    const auto got = scene.firstContact(moving.v, moving.f, motion);
    const int N = 1000;
    double t_oracle = -1;
    for (int k = 0; k <= N && t_oracle < 0; ++k) {
      const double t = static_cast<double>(k) / N;
      if (!meshesIntersect(moving, motion.pose(t), fixed)) continue;
      double lo = k == 0 ? 0 : static_cast<double>(k - 1) / N, hi = t;
      while (k > 0 && hi - lo > 1e-13) {
        const double mid = 0.5 * (lo + hi);
        (meshesIntersect(moving, motion.pose(mid), fixed) ? hi : lo) = mid;
      }
      t_oracle = hi;
    }
    if (t_oracle < 0) {
      ++none;
      continue;  // a contact the sampling stepped over is checked in the two-body test below
    }
    ++contacts;
    ASSERT_TRUE(got.has_value()) << "trial " << trial << ": missed the contact at " << t_oracle;
    EXPECT_LE(got->t, t_oracle + 1e-9) << "trial " << trial << ": late";
    if (got->t < t_oracle - 1e-9) ++earlier; else worst = std::max(worst, std::abs(got->t - t_oracle));
  }
  EXPECT_GT(contacts, 300);
  EXPECT_EQ(earlier, 0);
  std::printf("contacts %d, no contact %d, earlier %d, worst time difference %.3g\n", contacts, none, earlier, worst);
}

TEST(CollideOracle, StillPartnerAgreesWithSampling) { randomScenes(false, 150, 31415926); }
TEST(CollideOracle, BothMovingAgreesWithSampling) { randomScenes(true, 250, 27182818); }

}  // namespace
