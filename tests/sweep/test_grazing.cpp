// Grazing sets: known answers (translated cube and sphere, rotating cube, scalings), a seeded
// property test on random convex bodies and random SAMs, and bad input.
#include <steady/sweep/grazing.hpp>

#include "support/random_affine.hpp"
#include "sweep/sweep_test.hpp"

#include <steady/core/ear.hpp>

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace {

using steady::Affine3;
using steady::ErrorCode;
using steady::Span3;
using steady::sweep::Body;
using steady::sweep::FaceClass;
using steady::sweep::GrazingSet;
using steady::sweep::grazingSet;
using steady::sweep::SegmentKind;
using namespace steady_sweep_test;

std::map<SegmentKind, int> kinds(const GrazingSet& gs) {
  std::map<SegmentKind, int> k;
  for (const auto& s : gs.segments) ++k[s.kind];
  return k;
}

// The two vertices of an edge differ in exactly one coordinate (an edge of a box, not a diagonal).
bool axisEdge(const Body& b, int e) {
  const V d = b.vertices()[b.edges()[e].vertices[1]] - b.vertices()[b.edges()[e].vertices[0]];
  return (d.array() != 0).count() == 1;
}

// Checks the chaining: every segment in exactly one loop, loops are connected chains.
void expectLoopsConsistent(const GrazingSet& gs) {
  std::vector<int> seen(gs.segments.size(), 0);
  for (const auto& loop : gs.loops) {
    ASSERT_EQ(loop.points.size(), loop.segments.size() + 1);
    ASSERT_EQ(loop.polyline.size(), loop.points.size());
    for (std::size_t i = 0; i < loop.segments.size(); ++i) {
      const auto& sp = gs.segments[loop.segments[i]].points;
      ++seen[loop.segments[i]];
      EXPECT_TRUE((sp[0] == loop.points[i] && sp[1] == loop.points[i + 1]) ||
                  (sp[1] == loop.points[i] && sp[0] == loop.points[i + 1]));
    }
    EXPECT_EQ(loop.closed, loop.points.front() == loop.points.back());
  }
  for (int c : seen) EXPECT_EQ(c, 1);
}

TEST(Grazing, CubeTranslatedAlongX) {
  const Body body(box(V(-1, -1, -1), V(1, 1, 1)).v, box(V(-1, -1, -1), V(1, 1, 1)).f);
  const Affine3 B = Affine3::translation(V(1, 2, 3)) * Affine3::rotation(V(1, 1, 0), 0.7);
  const Affine3 C = Affine3::translation(B.linear() * V(2, 0, 0)) * B;  // +x in body coordinates
  const GrazingSet gs = grazingSet(body, Span3::between(B, C));
  EXPECT_FALSE(gs.stationary);
  for (std::size_t f = 0; f < body.faces().size(); ++f) {
    const V n = body.faceNormals()[f];
    const FaceClass want = n.x() > 0.5 ? FaceClass::Front : n.x() < -0.5 ? FaceClass::Back : FaceClass::Grazing;
    EXPECT_EQ(gs.faces[f], want) << "face " << f << " normal " << n.transpose();
  }
  // Only whole-face boundaries: the 12 edges of the cube, none of the 6 diagonals.
  auto k = kinds(gs);
  EXPECT_EQ(k[SegmentKind::Face], 0);
  EXPECT_EQ(k[SegmentKind::Silhouette], 0);
  EXPECT_EQ(k[SegmentKind::GrazingBoundary], 12);
  std::set<int> edges;
  for (const auto& s : gs.segments) {
    EXPECT_TRUE(axisEdge(body, s.edge));
    edges.insert(s.edge);
    EXPECT_EQ(gs.faces[s.face], FaceClass::Grazing);
    // Runs along its grazing face's winding.
    const auto& E = body.edges()[s.edge];
    const int from = gs.points[s.points[0]].vertex;
    EXPECT_EQ(from, E.faces[0] == s.face ? E.vertices[0] : E.vertices[1]);
  }
  EXPECT_EQ(edges.size(), 12u);
  EXPECT_FALSE(gs.generic);  // three segments meet at every corner
  expectLoopsConsistent(gs);
  // The world positions are the body posed at span time 0.
  for (const auto& p : gs.points) EXPECT_LT((p.world - B(p.body)).norm(), 1e-14);
}

TEST(Grazing, UvSphereTranslatedAlongD) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 3; ++trial) {
    const V c(0.3, -0.2, 0.1);
    const Mesh s = uvSphere(16, 32, 1.5, c);
    const Body body(s.v, s.f);
    const V d = randomUnit(rng);
    const Affine3 B = Affine3::rotation(randomUnit(rng), 0.4);
    const Affine3 C = Affine3::translation(3.0 * d) * B;
    const V d_body = B.linear().transpose() * d;  // B is a rotation
    const GrazingSet gs = grazingSet(body, Span3::between(B, C));
    // g is constant on each face for a translation: only silhouettes, one closed loop around d.
    auto k = kinds(gs);
    EXPECT_EQ(k[SegmentKind::Face], 0);
    EXPECT_EQ(k[SegmentKind::GrazingBoundary], 0);
    EXPECT_GT(k[SegmentKind::Silhouette], 32);
    EXPECT_TRUE(gs.generic);
    ASSERT_EQ(gs.loops.size(), 1u);
    EXPECT_TRUE(gs.loops[0].closed);
    expectLoopsConsistent(gs);
    // Every grazing point is near the great circle orthogonal to d: |n . d| is at most about
    // the angular size of a face (pi / 16).
    for (const auto& p : gs.points) {
      const V n = (p.body - c).normalized();
      EXPECT_LT(std::abs(n.dot(d_body)), 0.21) << p.body.transpose();
    }
    // The loop winds once around d.
    const V e1 = d_body.unitOrthogonal(), e2 = d_body.cross(e1);
    double turn = 0.0;
    const auto& poly = gs.loops[0].polyline;
    for (std::size_t i = 0; i + 1 < poly.size(); ++i) {
      const V a = poly[i] - c, b = poly[i + 1] - c;
      turn += std::atan2(a.dot(e1) * b.dot(e2) - a.dot(e2) * b.dot(e1), a.dot(e1) * b.dot(e1) + a.dot(e2) * b.dot(e2));
    }
    EXPECT_NEAR(std::abs(turn), 2 * M_PI, 1e-9);
    // Front faces are those facing d.
    for (std::size_t f = 0; f < body.faces().size(); ++f)
      EXPECT_EQ(gs.faces[f], body.faceNormals()[f].dot(d_body) > 0 ? FaceClass::Front : FaceClass::Back);
  }
}

TEST(Grazing, CubeRotatedAboutZThroughItsCentre) {
  const Mesh m = box(V(-1, -1, -1), V(1, 1, 1));
  const Body body(m.v, m.f);
  const V c(2, -1, 0.5);
  const Affine3 B = Affine3::translation(c);
  const Affine3 C = Affine3::translation(c) * Affine3::rotation(V(0, 0, 1), 1.0);
  const GrazingSet gs = grazingSet(body, Span3::between(B, C));
  // Top and bottom slide in their planes; every side face is split by the vertical line through
  // its middle (where the velocity is tangent to the face).
  for (std::size_t f = 0; f < body.faces().size(); ++f)
    EXPECT_EQ(gs.faces[f], std::abs(body.faceNormals()[f].z()) > 0.5 ? FaceClass::Grazing : FaceClass::Split) << f;
  auto k = kinds(gs);
  EXPECT_EQ(k[SegmentKind::Silhouette], 4);        // the four vertical edges, whole
  EXPECT_EQ(k[SegmentKind::GrazingBoundary], 8);   // the squares of the top and bottom
  EXPECT_EQ(k[SegmentKind::Face], 8);              // two per side face (it has two triangles)
  std::map<int, double> face_length;               // per side plane (by normal)
  for (const auto& s : gs.segments) {
    const auto& p = gs.points[s.points[0]];
    const auto& q = gs.points[s.points[1]];
    if (s.kind == SegmentKind::Silhouette) {
      EXPECT_GE(p.vertex, 0);
      EXPECT_GE(q.vertex, 0);
      const V d = q.body - p.body;
      EXPECT_EQ(d.x(), 0);
      EXPECT_EQ(d.y(), 0);
      EXPECT_EQ(std::abs(d.z()), 2);
      // Counter-clockwise rotation: at a vertical edge, the face whose normal is the rotation
      // direction (z x corner) is in front, and the segment runs with the front face on its left.
      const auto& E = body.edges()[s.edge];
      const bool f0_front = body.faceNormals()[E.faces[0]].dot(V(0, 0, 1).cross(p.body)) > 0;
      EXPECT_EQ(p.vertex, f0_front ? E.vertices[0] : E.vertices[1]);
    } else if (s.kind == SegmentKind::GrazingBoundary) {
      EXPECT_TRUE(axisEdge(body, s.edge));
      EXPECT_EQ(std::abs(p.body.z()), 1);
      EXPECT_EQ(std::abs(q.body.z()), 1);
    } else {
      const V n = body.faceNormals()[s.face];
      // On the face x = +-1 the segment is y = 0, on y = +-1 it is x = 0.
      for (const auto* pt : {&p, &q}) {
        if (std::abs(n.x()) > 0.5) EXPECT_NEAR(pt->body.y(), 0.0, 1e-12);
        else EXPECT_NEAR(pt->body.x(), 0.0, 1e-12);
      }
      face_length[static_cast<int>(std::lround(n.x() * 2 + n.y() * 3))] += (q.body - p.body).norm();
    }
  }
  ASSERT_EQ(face_length.size(), 4u);
  for (const auto& [key, len] : face_length) EXPECT_NEAR(len, 2.0, 1e-12) << key;
  expectLoopsConsistent(gs);
}

TEST(Grazing, ScalingAboutCentre) {
  const Mesh m = box(V(0, 0, 0), V(2, 2, 2));
  const Body body(m.v, m.f);
  auto scaling = [](const V& centre, double k) {
    return Affine3::translation(centre) * Affine3::scaling(k) * Affine3::translation(-centre);
  };
  // About the centre: every face moves outward (growth) or inward (shrinking), nothing grazes.
  for (double k : {2.0, 0.5}) {
    const GrazingSet gs = grazingSet(body, Span3(scaling(V(1, 1, 1), k)));
    for (FaceClass c : gs.faces) EXPECT_EQ(c, k > 1 ? FaceClass::Front : FaceClass::Back);
    EXPECT_TRUE(gs.segments.empty());
    EXPECT_TRUE(gs.loops.empty());
  }
  // About a point of the bottom plane: the bottom (n . (x - centre) = 0) slides in its plane.
  const GrazingSet gs = grazingSet(body, Span3(scaling(V(1, 1, 0), 2.0)));
  for (std::size_t f = 0; f < body.faces().size(); ++f)
    EXPECT_EQ(gs.faces[f], body.faceNormals()[f].z() < -0.5 ? FaceClass::Grazing : FaceClass::Front);
  auto k = kinds(gs);
  EXPECT_EQ(k[SegmentKind::GrazingBoundary], 4);
  EXPECT_EQ(gs.segments.size(), 4u);
  for (const auto& s : gs.segments) EXPECT_TRUE(axisEdge(body, s.edge));
  ASSERT_EQ(gs.loops.size(), 1u);  // the bottom square
  EXPECT_TRUE(gs.loops[0].closed);
  EXPECT_TRUE(gs.generic);
}

TEST(Grazing, StationarySpan) {
  const Mesh m = box(V(0, 0, 0), V(1, 1, 1));
  const Body body(m.v, m.f);
  const Affine3 B = Affine3::translation(V(1, 2, 3)) * Affine3::rotation(V(0, 1, 1), 0.3);
  const GrazingSet gs = grazingSet(body, Span3::between(B, B));
  EXPECT_TRUE(gs.stationary);
  EXPECT_TRUE(gs.segments.empty());
  for (FaceClass c : gs.faces) EXPECT_EQ(c, FaceClass::Grazing);
}

// A face segment that approaches an edge merges into it continuously: when the corner values
// fall below eps_g the segment is gone, and it was already within about eps_g / |g| of the edge.
TEST(Grazing, SnappingIsContinuousAtTheThreshold) {
  const Mesh m = box(V(-1, -1, -1), V(1, 1, 1));
  const Body body(m.v, m.f);
  for (double delta : {1e-6, 1e-8, 1e-10, 1e-13}) {
    // Rotation about the vertical line x = 0, y = 1 - delta: on the faces x = +-1 the velocity
    // is tangent along y = 1 - delta, just inside the edges at y = 1.
    const V a(0, 1 - delta, 0);
    const Affine3 C = Affine3::translation(a) * Affine3::rotation(V(0, 0, 1), 0.8) * Affine3::translation(-a);
    const GrazingSet gs = grazingSet(body, Span3(C));
    int near_edge = 0;
    for (const auto& s : gs.segments) {
      if (s.kind != SegmentKind::Face || std::abs(body.faceNormals()[s.face].x()) < 0.5) continue;
      ++near_edge;
      for (int q : s.points) EXPECT_LE(std::abs(gs.points[q].body.y() - (1 - delta)), 1e-15) << delta;
    }
    // Above the threshold (eps_g is about 2.2e-9 times the rotation speed): two segments per
    // face x = +-1; below it the corners snap to zero and the faces are Back/Front entirely.
    EXPECT_EQ(near_edge, delta > 1e-9 ? 4 : 0) << delta;
    // Above the threshold the faces x = +-1 have a back strip of width delta along their edges
    // y = 1, bounded by the face segment and a silhouette on that edge (a thin closed loop);
    // below it the strip and both sides of the loop vanish together.
    int vertical = 0;
    for (const auto& s : gs.segments)
      if (s.kind == SegmentKind::Silhouette) {
        const V p = gs.points[s.points[0]].body, q = gs.points[s.points[1]].body;
        vertical += p.y() == 1 && q.y() == 1 && std::abs(p.x()) == 1 && std::abs(q.z() - p.z()) == 2;
      }
    EXPECT_EQ(vertical, delta > 1e-9 ? 2 : 0) << delta;
    expectLoopsConsistent(gs);
  }
}

TEST(Grazing, NearlyStationarySpan) {
  const Mesh m = box(V(0, 0, 0), V(1, 1, 1));
  const Body body(m.v, m.f);
  // A motion of 1e-14 of the body size is rounding: stationary; 1e-9 is a motion.
  EXPECT_TRUE(grazingSet(body, Span3(Affine3::translation(V(1e-14, 0, 0)))).stationary);
  const GrazingSet gs = grazingSet(body, Span3(Affine3::translation(V(1e-9, 0, 0))));
  EXPECT_FALSE(gs.stationary);
  EXPECT_EQ(gs.segments.size(), 12u);
}

// Random convex polyhedra on random SAMs: grazing points satisfy n_f . v = 0 (at every span
// time), silhouettes separate front from back, the curves are closed loops.
TEST(Grazing, RandomSamOnRandomConvexBody) {
  std::mt19937_64 rng(20240611);
  int face_segments = 0, silhouettes = 0, loops = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const V c(uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2));
    const Mesh m = randomConvex(rng, 24, c);
    const Body body(m.v, m.f);
    const Affine3 B = steady::testing::randomWellPosedAffine<3>(rng);
    const Affine3 A = steady::testing::randomWellPosedAffine<3>(rng);
    const Span3 span = Span3::between(B, A * B);
    const GrazingSet gs = grazingSet(body, span);
    const auto& M = span.log().M;
    const auto& u = span.log().u;
    auto vel = [&](const V& x) { return V(M * x + u); };
    double scale = 0.0;
    std::vector<V> W;
    for (const V& p : body.vertices()) {
      W.push_back(B(p));
      scale = std::max(scale, M.norm() * W.back().norm() + u.norm());
    }
    auto worldNormal = [&](int f, const Affine3& pose) {
      const auto& t = body.faces()[f];
      const V a = pose(body.vertices()[t[0]]), b = pose(body.vertices()[t[1]]), cc = pose(body.vertices()[t[2]]);
      return V((b - a).cross(cc - a).normalized());
    };
    // Face classes agree with the signs of g at the corners.
    for (std::size_t f = 0; f < body.faces().size(); ++f) {
      int pos = 0, neg = 0;
      for (int v : body.faces()[f]) {
        const double g = worldNormal(static_cast<int>(f), B).dot(vel(W[v]));
        pos += g > 1e-9 * gs.speed;
        neg += g < -1e-9 * gs.speed;
      }
      const FaceClass want = pos && neg ? FaceClass::Split : pos ? FaceClass::Front : neg ? FaceClass::Back : FaceClass::Grazing;
      EXPECT_EQ(gs.faces[f], want);
    }
    std::vector<int> degree(gs.points.size(), 0);
    for (const auto& s : gs.segments) {
      for (int q : s.points) ++degree[q];
      const auto& p = gs.points[s.points[0]];
      const auto& q = gs.points[s.points[1]];
      if (s.kind == SegmentKind::Face) {
        ++face_segments;
        for (const auto* pt : {&p, &q}) {
          EXPECT_LE(std::abs(worldNormal(s.face, B).dot(vel(pt->world))), 1e-12 * scale);
          // Independent of time: n_τ . v(A^τ B p) = 0 at other span times too.
          for (double tau : {0.3, 1.0}) {
            const Affine3 pose = span.pose(tau);
            EXPECT_LE(std::abs(worldNormal(s.face, pose).dot(vel(pose(pt->body)))), 1e-9 * scale) << tau;
          }
        }
        // Oriented with the front corner on the left, seen from outside.
        const auto& t = body.faces()[s.face];
        for (int v : t) {
          const double g = worldNormal(s.face, B).dot(vel(W[v]));
          if (std::abs(g) < 1e-6 * gs.speed) continue;
          const double side = worldNormal(s.face, B).cross(q.world - p.world).dot(W[v] - p.world);
          EXPECT_EQ(g > 0, side > 0);
        }
      } else if (s.kind == SegmentKind::Silhouette) {
        ++silhouettes;
        // The two faces have g of opposite signs at the middle, the left one (faces[0] when
        // the segment runs v0 -> v1) in front.
        const V mid = 0.5 * (p.world + q.world);
        const auto& E = body.edges()[s.edge];
        const double g0 = worldNormal(E.faces[0], B).dot(vel(mid));
        const double g1 = worldNormal(E.faces[1], B).dot(vel(mid));
        EXPECT_LT(g0 * g1, 0.0);
        const V dir = body.vertices()[E.vertices[1]] - body.vertices()[E.vertices[0]];
        EXPECT_EQ(g0 > 0, (q.body - p.body).dot(dir) > 0);
      } else {
        ADD_FAILURE() << "no face of a generic random body grazes entirely";
      }
    }
    for (int d : degree) EXPECT_EQ(d, 2);
    EXPECT_TRUE(gs.generic);
    for (const auto& loop : gs.loops) EXPECT_TRUE(loop.closed);
    expectLoopsConsistent(gs);
    loops += static_cast<int>(gs.loops.size());
  }
  // The property test reached both kinds of segments.
  EXPECT_GT(face_segments, 20);
  EXPECT_GT(silhouettes, 20);
  EXPECT_GE(loops, 20);
}

TEST(Grazing, BadOptions) {
  const Mesh m = box(V(0, 0, 0), V(1, 1, 1));
  const Body body(m.v, m.f);
  const Span3 span(Affine3::translation(V(1, 0, 0)));
  for (double t : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    steady::sweep::GrazingOptions o;
    o.tolerance = t;
    EXPECT_TRUE(throwsError([&] { grazingSet(body, span, o); }, ErrorCode::InvalidArgument, "GrazingOptions::tolerance"));
    steady::sweep::GrazingOptions r;
    r.stationary_tolerance = t;
    EXPECT_TRUE(throwsError([&] { grazingSet(body, span, r); }, ErrorCode::InvalidArgument,
                            "GrazingOptions::stationary_tolerance"));
  }
}

}  // namespace
