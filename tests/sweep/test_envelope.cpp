// Independent verification of the swept envelope (envelope.hpp). The oracles are not the
// pipeline's: closed-form volumes, our own directed-edge count and divergence-theorem measures,
// a generalized winding number on the output mesh, point/triangle distances, and the signed
// distance of a point to the body posed at a time, minimised over the motion by a certified
// Lipschitz branch and bound (envelope_check.hpp). Cross-checked with the inside test
// (inside.hpp), which never builds an envelope.
//
// Volume bound. The envelope's only approximation is the tessellation, within ε of the true
// boundary (envelope.hpp). The true and the computed volumes then differ by the region between
// the two surfaces, at most ε thick over the boundary's area A: |V_env - V_true| <= ε A (to
// first order in ε; curvature terms are O(ε^2) times the boundary's total curvature, far below
// it for ε = 1e-3 of the body size). Where every trajectory of a grazing point is a straight
// line traversed once (pure translations, and a scaling of a box from a corner), the
// tessellation is exact and the volume is exact up to rounding (1e-9 relative here).
#include <steady/io/mesh.hpp>
#include <steady/io/motion_file.hpp>
#include <steady/sweep/envelope.hpp>
#include <steady/sweep/inside.hpp>

#include "sweep/envelope_check.hpp"
#include "sweep/envelope_oracle.hpp"
#include "sweep/sweep_test.hpp"

#include "coincident.hpp"  // (internal: detail::MergeEveryFace)
#include "refill_memory.hpp"  // (internal: detail::RefillMemoryProbe)
#include "cycle.hpp"  // (internal: a span's cycle, detail::planSpan)
#include "doubt.hpp"  // (internal: detail::sweptEnvelope with another cap)

#include <steady/core/ear.hpp>
#include <steady/core/motion.hpp>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <optional>
#include <string>

namespace {

using steady::Affine3;
using steady::ErrorCode;
using steady::Motion3;
using steady::Span3;
using steady::sweep::Body;
using steady::sweep::Envelope;
using steady::sweep::inspectMesh;
using steady::sweep::MeshCheck;
using steady::sweep::SweepOptions;
using steady::sweep::sweptEnvelope;
using steady::sweep::SweptVolume;
using namespace steady_sweep_test;

// A bundled mesh (data/meshes/NAME.off), and a bundled motion (data/motions/NAME.json) fitted to
// a mesh's box, as the CLI fits it.
Mesh bundledMesh(const char* name) {
  const steady::io::TriangleMesh t = steady::io::readMesh(std::string(STEADY_DATA_DIR "/meshes/") + name + ".off");
  return Mesh{t.vertices, t.faces};
}
Motion3 bundledMotion(const char* name, const Mesh& m) {
  return steady::io::readMotionFile(std::string(STEADY_DATA_DIR "/motions/") + name + ".json").motion().toMotion(makeBody(m).box());
}

// ---- analytic volumes --------------------------------------------------------------------------

TEST(Envelope, BoxTranslatedIsTheMinkowskiSum) {
  // Cavalieri: every line parallel to d meets the sum of a convex K and the segment [0, d] in its
  // chord through K lengthened by |d|, so vol = vol K + |d| area(projection of K along d). For a
  // box the projection's area is sum_i |d_i / |d|| A_i (A_i the area of the faces normal to
  // axis i), so vol = 1 + |d_x| + |d_y| + |d_z| = 3.8 for the unit box and d = (2, 0.5, 0.3).
  // Its boundary: the two caps' back and front halves and six parallelograms swept by the
  // silhouette edges: every envelope vertex must have Minkowski depth 0 (rounding only).
  const Mesh m = box(V(0, 0, 0), V(1, 1, 1));
  const V d(2, 0.5, 0.3);
  const Span3 span = Span3::between(Affine3(), Affine3::translation(d));
  const Envelope env = sweptEnvelope(makeBody(m), span);
  std::mt19937_64 rng(21);
  checkEnvelope(m, single(Affine3(), Affine3::translation(d)), env, epsOf(m), rng, "box translated");
  const double want = 1 + 2 + 0.5 + 0.3;
  EXPECT_NEAR(env.volume, want, env.tolerance * env.area) << "the epsilon A bound";
  EXPECT_NEAR(env.volume, want, 1e-9 * want) << "straight trajectories: exact";
  // Every vertex on the boundary of the Minkowski sum (depth 0 up to rounding).
  double worst = 0;
  for (const V& x : env.vertices) worst = std::max(worst, std::abs(minkowskiDepth(x, V(0, 0, 0), V(1, 1, 1), d)));
  EXPECT_LE(worst, 1e-12);
}

TEST(Envelope, BoxAlongAnAxisHasGrazingFaces) {
  // The unit box translated by (2, 0, 0): four faces slide in their planes (Grazing). The union
  // is the box [0, 3] x [0, 1]^2: volume 3, area 14, every vertex on its boundary.
  const Mesh m = box(V(0, 0, 0), V(1, 1, 1));
  const Motion3 motion = single(Affine3(), Affine3::translation(V(2, 0, 0)));
  const Envelope env = sweep(m, motion);
  std::mt19937_64 rng(22);
  checkEnvelope(m, motion, env, epsOf(m), rng, "box along x (grazing)");
  EXPECT_NEAR(env.volume, 3.0, 1e-9 * 3);
  EXPECT_NEAR(env.area, 14.0, 1e-9 * 14);
  for (const V& x : env.vertices) {
    const double depth = std::min({x.x(), x.y(), x.z(), 3 - x.x(), 1 - x.y(), 1 - x.z()});
    EXPECT_NEAR(depth, 0.0, 1e-12) << x.transpose();
  }
}

TEST(Envelope, BoxScaledFromItsCorner) {
  // diag(2, 1, 1)^tau maps [0, 1]^3 to [0, 2^tau] x [0, 1]^2: the union is [0, 2] x [0, 1]^2
  // (volume 2, area 10). Four faces are Grazing (invariant planes), the face x = 0 does not
  // move; every trajectory is a straight segment along x traversed once.
  const Mesh m = box(V(0, 0, 0), V(1, 1, 1));
  const Motion3 motion = single(Affine3(), Affine3::scaling(V(2, 1, 1)));
  const Envelope env = sweep(m, motion);
  std::mt19937_64 rng(23);
  checkEnvelope(m, motion, env, epsOf(m), rng, "box scaled from corner");
  EXPECT_NEAR(env.volume, 2.0, env.tolerance * 10) << "the epsilon A bound";
  EXPECT_NEAR(env.volume, 2.0, 1e-9 * 2) << "straight trajectories: exact";
  EXPECT_NEAR(env.area, 10.0, 1e-9 * 10);
  for (const V& x : env.vertices) {
    const double depth = std::min({x.x(), x.y(), x.z(), 2 - x.x(), 1 - x.y(), 1 - x.z()});
    EXPECT_NEAR(depth, 0.0, 1e-12) << x.transpose();
  }
}

TEST(Envelope, BoxTurningAboutItsAxis) {
  // The box [-a, a]^2 x [0, h] turned about the z axis by theta < pi/2. The cross-section is
  // the union of the squares turned by [0, theta]: star-shaped about the axis, with radius
  // r(alpha) = a sqrt 2 when the window [alpha - theta, alpha] holds a corner direction (an arc
  // of angle theta per corner), else the larger end value of a / cos (alpha measured from a side's
  // normal). Per quarter: a^2 theta (the arc sector) + 2 * 1/2 int_{theta/2}^{pi/4} a^2 / cos^2 u du
  // = a^2 theta + a^2 (1 - tan(theta / 2)). Area: 4 a^2 (1 + theta - tan(theta / 2)) (4 a^2 at
  // theta = 0; the disc 2 pi a^2 at theta = pi/2). Perimeter: 4 (a sqrt2 theta + 2 a (1 - tan(theta/2))).
  const double a = 0.5, h = 0.7, theta = 1.1;
  const Mesh m = box(V(-a, -a, 0), V(a, a, h));
  const Span3 span = Span3::between(Affine3(), Affine3::rotation(V(0, 0, 1), theta));
  const Envelope env = sweptEnvelope(makeBody(m), span);
  std::mt19937_64 rng(24);
  checkEnvelope(m, single(Affine3(), Affine3::rotation(V(0, 0, 1), theta)), env, epsOf(m), rng, "box turning");
  const double section = 4 * a * a * (1 + theta - std::tan(theta / 2));
  const double perimeter = 4 * (a * std::sqrt(2.0) * theta + 2 * a * (1 - std::tan(theta / 2)));
  const double want = h * section, area = 2 * section + h * perimeter;
  std::printf("[ info     ] box turning: volume %.6f, closed form %.6f, bound %.2e\n", env.volume, want,
              env.tolerance * std::max(area, env.area));
  EXPECT_NEAR(env.volume, want, env.tolerance * std::max(area, env.area));
  EXPECT_NEAR(env.area, area, 0.01 * area);
}

TEST(Envelope, SphereOnAScrewBetweenTubes) {
  // A ball of radius r on a rigid motion sweeps the union of balls about its centre's path: for
  // a path of length L whose curvature radius exceeds r and that does not come back near itself,
  // a tube (pi r^2 L, Pappus) plus two half-balls: pi r^2 L + 4/3 pi r^3. The polyhedral sphere
  // holds its inscribed ball (radius: the smallest distance from the centre to a face plane) and
  // lies in its circumscribed ball (radius 1), so its swept volume is between the two.
  // Helix: centre at distance R = 3 from the axis, turn theta = 2, rise 2: L = sqrt((R theta)^2 +
  // 2^2), curvature radius (R^2 + c^2) / R with c = rise / theta = 1: 3.33 > 1.
  const Mesh m = uvSphere(10, 20, 1.0, V(3, 0, 0));
  double r_in = 1;
  for (const auto& f : m.f) {
    const V n = (m.v[f[1]] - m.v[f[0]]).cross(m.v[f[2]] - m.v[f[0]]).normalized();
    r_in = std::min(r_in, n.dot(m.v[f[0]] - V(3, 0, 0)));
  }
  const double theta = 2.0, rise = 2.0, R = 3.0;
  const Motion3 motion = single(Affine3(), Affine3::translation(V(0, 0, rise)) * Affine3::rotation(V(0, 0, 1), theta));
  const Envelope env = sweep(m, motion);
  std::mt19937_64 rng(25);
  checkEnvelope(m, motion, env, epsOf(m), rng, "sphere on screw");
  const double L = std::hypot(R * theta, rise);
  auto tube = [&](double r) { return M_PI * r * r * L + 4.0 / 3.0 * M_PI * r * r * r; };
  const double lo = tube(r_in), hi = tube(1.0), slack = env.tolerance * env.area;
  std::printf("[ info     ] sphere on screw: volume %.5f in [%.5f, %.5f] (+- %.2e)\n", env.volume, lo, hi, slack);
  EXPECT_GE(env.volume, lo - slack);
  EXPECT_LE(env.volume, hi + slack);
}

// ---- cases that break naive methods ------------------------------------------------------------

TEST(Envelope, NonConvexLOnAScrew) {
  const Mesh m = lShape(0.5);
  const Motion3 motion = single(Affine3::translation(V(-1, -1, 0)),
                                Affine3::translation(V(0.5, 0, 1.2)) * Affine3::rotation(V(0.2, 0.1, 1), 2.4) *
                                    Affine3::translation(V(-1, -1, 0)));
  const Envelope env = sweep(m, motion, 2e-3);
  std::mt19937_64 rng(31);
  checkEnvelope(m, motion, env, epsOf(m, 2e-3), rng, "L on screw");
}

TEST(Envelope, PolySamBeyondAHalfTurnPassesTwice) {
  // Four spans of 100 degrees about a vertical axis through the L's corner region, rising 0.1 per
  // span: 400 degrees, so the body sweeps over its own earlier path.
  const Mesh m = lShape(0.5);
  std::vector<Affine3> poses{Affine3()};
  const Affine3 step = Affine3::translation(V(0, 0, 0.1)) * Affine3::translation(V(1.5, 0.5, 0)) *
                       Affine3::rotation(V(0, 0, 1), 100 * M_PI / 180) * Affine3::translation(V(-1.5, -0.5, 0));
  for (int i = 0; i < 4; ++i) poses.push_back(step * poses.back());
  const Motion3 motion = Motion3::polySam(poses);
  const Envelope env = sweep(m, motion, 5e-3);  // a coarse tolerance keeps the run short
  std::mt19937_64 rng(32);
  CheckOptions co;
  co.expected_euler = 99;  // the region around the axis may be enclosed or not: not asserted
  checkEnvelope(m, motion, env, epsOf(m, 5e-3), rng, "L 400 degrees", co);
}

TEST(Envelope, PolySamJointsLeaveNoWholeBody) {
  // One screw SAM cut into four spans at equal steps (the same velocity field in every span):
  // the same swept volume. At each joint the end cap of one span and the start cap of the next,
  // reversed, cancel wherever both spans move a face outward, so the cycle is smaller than the
  // four spans' own cycles together (each with Back at its start and Front at its end, which
  // would leave a whole posed body at each of the three joints). The spans meet in the same
  // chord ends, and their chord points lie exactly on the chords. Before they did, the chord
  // points of two spans lay a few ulps apart at every joint, and here the labels propagated
  // across edges disagreed with their check rays (on a torus of 576 faces along the same
  // screw, envelope vertices also lay up to 9.3 ε inside the body).
  const Mesh m = uvSphere(10, 20, 0.6);
  const Affine3 B = Affine3::rotation(V(1, 0, 0), 0.4);
  const Affine3 C = Affine3::translation(V(0.5, 0.2, 1.2)) * Affine3::rotation(V(0.2, 0.1, 1), 2.0) * B;
  std::vector<Affine3> poses;
  for (int k = 0; k <= 4; ++k) poses.push_back(steady::sam(B, k / 4.0, C));
  const Motion3 four = Motion3::polySam(poses);
  const Envelope one = sweep(m, single(B, C), 2e-3);
  const Envelope env = sweep(m, four, 2e-3);
  std::size_t own = 0;  // the four spans' own cycles
  for (int k = 0; k < 4; ++k) own += sweep(m, single(poses[k], poses[k + 1]), 2e-3).cycle_triangles;
  const std::size_t n = m.f.size();
  std::printf("[ info     ] screw in four spans: cycle %zu triangles, the spans' own %zu, one span %zu, body %zu\n",
              env.cycle_triangles, own, one.cycle_triangles, n);
  EXPECT_LT(env.cycle_triangles + 3 * n / 2, own) << "own cycles " << own << ", body " << n << ", polySAM "
                                                  << env.cycle_triangles;
  // Both are within ε of the true boundary (area A): their volumes differ by at most about 2 ε A.
  const double eps = epsOf(m, 2e-3);
  EXPECT_LE(std::abs(env.volume - one.volume), 2 * eps * one.area) << env.volume << " vs " << one.volume;
  std::mt19937_64 rng(46);
  CheckOptions co;
  co.expected_euler = 99;  // small tunnels where crack mouths stay open (one span alike): not asserted
  checkEnvelope(m, four, env, eps, rng, "sphere screw in four spans", co);
}

// The caps at a polySAM's joints are merged (cycle.cpp, appendSpanCycle "Joints"): a face Front
// on both sides of a joint leaves no cap, a face Front on one side and split by a grazing chord
// on the other leaves the Back part of the split side, and a face split on both sides leaves the
// region between its two chords. Each span fanned its own caps before, through its own points on
// the edges, and the two fans of a face crossed each other: along the bundled keys.json, the
// tetrahedron (whose faces are mostly split at the joints) had 369,632 crossing pairs for a
// cycle of 70,146 triangles, and the box 124,426 for 59,922; now 16,012 for 68,050 and 3,844
// for 54,156. The cycle must stay closed as a chain, and the envelopes pass the oracle's checks.
TEST(Envelope, PolySamJointCapsAreMerged) {
  for (const char* name : {"tetrahedron", "box"}) {
    SCOPED_TRACE(name);
    const Mesh m = bundledMesh(name);
    const Motion3 motion = bundledMotion("keys", m);
    ASSERT_GT(motion.spanCount(), 32u);
    const Envelope env = sweep(m, motion);
    std::printf("[ info     ] %s along keys.json: cycle %zu triangles, %zu crossing pairs\n", name,
                env.cycle_triangles, env.intersecting_pairs);
    EXPECT_EQ(env.cycle_open_edges, 0u);
    EXPECT_LT(env.intersecting_pairs, env.cycle_triangles / 2);
    std::mt19937_64 rng(61);
    CheckOptions co;
    co.expected_euler = 0;  // the motion's loop leaves a tunnel through the swept volume
    checkEnvelope(m, motion, env, epsOf(m), rng, std::string(name) + " along keys.json", co);
  }
}

TEST(Envelope, TorusKeepsItsHole) {
  // A torus moved along its axis (with a small tilt) keeps a through hole: one shell of genus 1
  // (Euler characteristic 0).
  const Mesh m = torus(1.0, 0.3, 16, 8);
  const Motion3 motion = single(Affine3(), Affine3::translation(V(0.1, 0, 0.8)) * Affine3::rotation(V(1, 0, 0), 0.3));
  const Envelope env = sweep(m, motion);
  std::mt19937_64 rng(33);
  CheckOptions co;
  co.expected_euler = 0;
  checkEnvelope(m, motion, env, epsOf(m), rng, "torus along axis", co);
}

TEST(Envelope, ThinPlateTumbling) {
  // A plate 1.2 x 0.8 x 0.02: its two large faces are 0.02 apart, 1/70 of its size (walls
  // thinner than most features of the sweep).
  const Mesh m = box(V(-0.6, -0.4, -0.01), V(0.6, 0.4, 0.01));
  const Affine3 B = Affine3::rotation(V(1, 0, 0), 0.3);
  const Motion3 motion = single(B, Affine3::translation(V(0.4, 0.2, 0.3)) * Affine3::rotation(V(0, 1, 0.2), 2.2) * B);
  const Envelope env = sweep(m, motion, 2e-3);
  std::mt19937_64 rng(34);
  checkEnvelope(m, motion, env, epsOf(m, 2e-3), rng, "thin plate tumbling");
}

TEST(Envelope, AffineSpanWithShearAndNonUniformScale) {
  const Mesh m = lShape(0.5);
  const Affine3 B = Affine3::rotation(V(1, 1, 0), 0.4);
  const Affine3 A = Affine3::translation(V(0.3, 0, 0.2)) * Affine3::shear(V(1, 0, 0), V(0, 0, 1), 2.0) *
                    Affine3::scaling(V(1.6, 0.5, 1.2)) * Affine3::rotation(V(0, 0, 1), 0.5);
  const Motion3 motion = single(B, A * B);
  const Envelope env = sweep(m, motion);
  std::mt19937_64 rng(35);
  checkEnvelope(m, motion, env, epsOf(m), rng, "L shear+scale");
}

TEST(Envelope, PureTranslations) {
  // A non-convex body along straight lines (one span, then a zig-zag polySAM of three).
  const Mesh m = lShape(0.5);
  std::mt19937_64 rng(36);
  const Motion3 one = single(Affine3(), Affine3::translation(V(1.3, -0.7, 0.9)));
  checkEnvelope(m, one, sweep(m, one), epsOf(m), rng, "L translated");
  const Motion3 zigzag = Motion3::polySam(std::vector<Affine3>{
      Affine3(), Affine3::translation(V(1, 0.5, 0)), Affine3::translation(V(1.5, -0.5, 0.4)), Affine3::translation(V(2.5, 0, 0.2))});
  CheckOptions co;
  co.expected_euler = 99;
  checkEnvelope(m, zigzag, sweep(m, zigzag), epsOf(m), rng, "L zig-zag", co);
}

// ---- the bundled default scene ------------------------------------------------------------------

Mesh bundledBracket() {
  const steady::io::TriangleMesh t = steady::io::readMesh(STEADY_DATA_DIR "/meshes/bracket.off");
  return Mesh{t.vertices, t.faces};
}

// The envelope is closed, manifold, oriented, free of self-intersections, one shell, and
// encloses a positive volume.
void expectOneEmbeddedShell(const Envelope& env) {
  const MeshCheck mc = inspectMesh(env.vertices, env.triangles, true);
  EXPECT_TRUE(mc.closed);
  EXPECT_TRUE(mc.manifold);
  EXPECT_TRUE(mc.oriented);
  EXPECT_EQ(mc.self_intersections, 0);
  EXPECT_EQ(mc.shells, 1);
  EXPECT_GT(mc.volume, 0);
}

// The bracket translated along its z axis by 2 (the CLI's sweep test): its vertices have short
// decimal coordinates, so many arrangement points lie exactly on the borders of the arrangement's
// point-numbering grid. A first version of that grid filed each point in the cell of its box's
// lower corner only, missed equal points across a border, and left this envelope open, not
// manifold and with 256 self-intersecting pairs; the sweep tests above all passed with it.
TEST(Envelope, BracketTranslatedAlongZ) {
  const Mesh m = bundledBracket();
  const Motion3 motion = single(Affine3(), Affine3::translation(V(0, 0, 2)));
  const Envelope env = sweep(m, motion);
  std::mt19937_64 rng(47);
  CheckOptions co;
  co.expected_euler = 99;
  checkEnvelope(m, motion, env, epsOf(m), rng, "bracket translated along z", co);
  EXPECT_NEAR(env.volume, 30.87402304825592, 1e-9 * 30.87402304825592);
}

// The bundled box turning about z while moving in x and y (a planar motion: its top and bottom
// faces slide in their planes; tests/sweep/fixtures/box_planar_quarter.json and
// box_planar_30.json). Before stop 60 every sweep of these failed its check with
// self-intersecting pairs; until stop 61 a turn of 30 degrees at 1e-3 still did (214 pairs, not
// closed). The cause: the interior rows' poses, exp(τ [M u]) by Padé, missed E_22 = 1 by an ulp
// at some τ (1 - 1.1e-16 at τ = 0.993 for 30 degrees), which lowered those rows' strip vertices
// 3e-17 below the sliding planes, and the exact trimming then resolved sheets that should
// coincide into slivers that rounding tangled. A zero row of the generator now keeps its
// coordinate exactly (cycle.cpp, CleanPoses): every envelope vertex within 1e-12 of those planes
// must lie exactly on them.
TEST(Envelope, TurnsOfTheBoxInItsPlane) {
  const steady::io::TriangleMesh t = steady::io::readMesh(STEADY_DATA_DIR "/meshes/box.off");
  const Mesh m{t.vertices, t.faces};
  struct Case {
    double degrees, relative;
  };
  for (const Case c : {Case{30, 1e-3}, Case{30, 1e-2}, Case{90, 1e-3}, Case{90, 1e-2}, Case{180, 1e-3}}) {
    SCOPED_TRACE(std::to_string(c.degrees) + " degrees at " + std::to_string(c.relative));
    const Motion3 motion =
        single(Affine3(), Affine3::translation(V(2, 0.5, 0)) * Affine3::rotationDegrees(V(0, 0, 1), c.degrees));
    const Envelope env = sweep(m, motion, c.relative);
    expectOneEmbeddedShell(env);
    std::size_t near_plane = 0, off_plane = 0;
    for (const V& x : env.vertices) {
      const double h = std::abs(x.z()) - 0.25;
      if (std::abs(h) < 1e-12) ++near_plane, off_plane += h != 0.0;
    }
    EXPECT_GT(near_plane, 100u);
    EXPECT_EQ(off_plane, 0u) << "vertices within 1e-12 of the sliding planes z = +-0.25 but not on them";
    std::mt19937_64 rng(48);
    checkEnvelope(m, motion, env, epsOf(m, c.relative), rng, "box turning in its plane", CheckOptions{});
  }
}

// The arrangement merges coincident faces (coplanar layers) by comparing only the faces of cycle
// triangles that have a twin on the same three points or a coplanar crossing (trim.cpp,
// mergeCoincident). Against the merge over every face (detail::MergeEveryFace), on scenes with
// such layers: the same faces merged and cancelled, and the same envelope to the last bit. A
// triangle left unflagged whose faces had partners would keep them apart, and the counts would
// differ. The bracket's screw and the box's turn in its plane have coplanar crossings; the box
// with a second copy of itself as another shell has twins (every cap triangle and every strip
// triangle twice), and sweeps the box's own envelope. (The tetrahedron along keys.json had
// coplanar crossings too, until joint caps whose chords cross were cut at the crossing
// (cycle.cpp, splitAndFan): they came from those caps' self-overlapping fans; neither it nor
// the box and bracket along keys.json, the box along the straight-shear fixtures or along
// screw_scale.json has any now.)
TEST(Envelope, CoincidentFacesAsFoundAmongAllFaces) {
  Mesh doubled = bundledMesh("box");
  const int n = static_cast<int>(doubled.v.size());
  for (std::size_t f = 0, nf = doubled.f.size(); f < nf; ++f)
    doubled.f.push_back({{doubled.f[f][0] + n, doubled.f[f][1] + n, doubled.f[f][2] + n}});
  for (int v = 0; v < n; ++v) doubled.v.push_back(doubled.v[static_cast<std::size_t>(v)]);
  struct Case {
    std::string name;
    Mesh mesh;
    Motion3 motion;
    const Mesh* same_envelope_as;  // (a body whose envelope along the motion must be the same, or null)
  };
  const Mesh bracket = bundledMesh("bracket"), box = bundledMesh("box");
  const Case cases[] = {
      {"bracket along screw.json", bracket, bundledMotion("screw", bracket), nullptr},
      {"box turning 90 degrees in its plane", box,
       single(Affine3(), Affine3::translation(V(2, 0.5, 0)) * Affine3::rotationDegrees(V(0, 0, 1), 90)), nullptr},
      {"box doubled along screw.json", doubled, bundledMotion("screw", doubled), &box}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Envelope flagged = sweep(c.mesh, c.motion);
    Envelope every;
    {
      const steady::sweep::detail::MergeEveryFace all;
      every = sweep(c.mesh, c.motion);
    }
    std::printf("[ info     ] %s: %zu faces merged, %zu cancelled\n", c.name.c_str(), every.coincident_merged,
                every.coincident_cancelled);
    EXPECT_GT(every.coincident_merged, 0u);  // (the scene has layers to merge)
    EXPECT_EQ(flagged.coincident_merged, every.coincident_merged);
    EXPECT_EQ(flagged.coincident_cancelled, every.coincident_cancelled);
    EXPECT_TRUE(flagged.vertices == every.vertices);
    EXPECT_TRUE(flagged.triangles == every.triangles);
    if (c.same_envelope_as) {
      const Envelope other = sweep(*c.same_envelope_as, c.motion);
      EXPECT_TRUE(flagged.vertices == other.vertices);
      EXPECT_TRUE(flagged.triangles == other.triangles);
    }
  }
}

// A thin plate along an affine span that scales x by 3/2 and moves y and z (a sweep fuzz input,
// tests/fuzz/corpus/sweep/plate_shear_open_envelope): the plane x = 0 is invariant, and the
// plate's face there slides in it. Padé's exponential left the interior rows' first row at
// (1.5^τ, ~1e-17, ~1e-17 | ~1e-16), not (1.5^τ, 0, 0 | 0): strip vertices at x = 1e-15, and at
// 2e-2 an envelope that was open and not manifold, re-swept twice in vain. A generator row that
// is zero off its diagonal now gives the exponential's row exactly (cycle.cpp, CleanPoses).
TEST(Envelope, PlateScaledAwayFromAnInvariantPlane) {
  const Mesh m = box(V(0, 0, 0), V(1, 1, 0.02));
  Eigen::Matrix3d L;
  L << 1.5, 0, 0, -5.0 / 16, -1.0 / 16, -1, 39.0 / 16, 0.5, 0;
  const Motion3 motion = single(Affine3(), Affine3(L, V(0, 49.0 / 16, 1)));
  for (const double relative : {2e-2, 1e-2}) {
    SCOPED_TRACE(relative);
    const Envelope env = sweep(m, motion, relative);
    EXPECT_EQ(env.resweeps, 0u);
    expectOneEmbeddedShell(env);
    std::size_t near_plane = 0, off_plane = 0;
    for (const V& x : env.vertices)
      if (std::abs(x.x()) < 1e-12) ++near_plane, off_plane += x.x() != 0.0;
    EXPECT_GT(near_plane, 20u);
    EXPECT_EQ(off_plane, 0u) << "vertices within 1e-12 of the invariant plane x = 0 but not on it";
    std::mt19937_64 rng(52);
    checkEnvelope(m, motion, env, epsOf(m, relative), rng, "plate scaled away from x = 0", CheckOptions{});
  }
}

// The bundled tetrahedron turning 100 degrees about an axis parallel to x that passes through it
// (moving (0, 1, 0.7) while it turns). The motion keeps that axis fixed, and every grazing chord
// of a face the axis pierces passes through the pierce point, as every row of the chord's strip
// does. Until stop 61 the rows met there only to within an ulp: they crossed each other in
// thousands of faces 1e-15 wide, which the labels' rays tested in rationals (the sweep did not
// finish in 5 minutes at 3e-3). The chord is now cut at the fixed point, held as one vertex for
// all rows (cycle.cpp, planSpan).
TEST(Envelope, FixedAxisThroughTheBody) {
  const steady::io::TriangleMesh t = steady::io::readMesh(STEADY_DATA_DIR "/meshes/tetrahedron.off");
  const Mesh m{t.vertices, t.faces};
  const Affine3 end = Affine3::translation(V(0, 1, 0.7)) * Affine3::rotationDegrees(V(1, 0, 0), 100);
  const steady::Span3 span = steady::Span3::between(Affine3(), end);
  const Eigen::Matrix3d& M = span.log().M;
  const V& u = span.log().u;
  {  // the cycle: one vertex on the fixed axis per pierced face, shared by the strip's rows
    const steady::sweep::Body body(m.v, m.f);
    const auto plan = steady::sweep::detail::planSpan(body, span, nullptr, epsOf(m, 3e-3), steady::sweep::GrazingOptions{},
                                                      1 << 16, 0);
    steady::sweep::detail::Cycle cycle;
    steady::sweep::detail::appendSpanCycle(cycle, nullptr, *plan, nullptr);
    std::vector<int> on_axis;
    for (std::size_t v = 0; v < cycle.vertices.size(); ++v)
      if ((M * cycle.vertices[v] + u).norm() <= 1e-12) on_axis.push_back(static_cast<int>(v));
    ASSERT_EQ(on_axis.size(), 2u) << "the axis pierces two faces of the tetrahedron";
    for (const int v : on_axis) {
      std::size_t incident = 0;
      for (const auto& tri : cycle.triangles) incident += std::count(tri.begin(), tri.end(), v) > 0;
      EXPECT_GT(incident, 20u) << "every row of the chord's strip meets at the fixed point";
    }
  }
  const Motion3 motion = single(Affine3(), end);
  const Envelope env = sweep(m, motion, 3e-3);
  expectOneEmbeddedShell(env);
  std::mt19937_64 rng(49);
  checkEnvelope(m, motion, env, epsOf(m, 3e-3), rng, "tetrahedron about a fixed axis through it", CheckOptions{});
}

// An affine span that keeps z (a sweep fuzz input; tests/sweep/fixtures/tetra_shear_keeps_z.json):
// the tetrahedron's edges at z = +-1 slide in their planes while x and y shear, and the span
// keeps the line (8z, (1 + z) / 46, z) through the body fixed. Until stop 61 its envelope was not
// closed (168 crossing pairs and 26 shells at 2e-2); it passes since the chords are cut at the
// fixed points.
TEST(Envelope, AffineSpanKeepingAPlane) {
  const steady::io::TriangleMesh t = steady::io::readMesh(STEADY_DATA_DIR "/meshes/tetrahedron.off");
  const Mesh m{t.vertices, t.faces};
  const Motion3 motion = steady::io::readMotionFile(STEADY_TEST_FIXTURES "/tetra_shear_keeps_z.json")
                             .motion()
                             .toMotion(makeBody(m).box());
  for (const double relative : {2e-2, 3e-3}) {
    SCOPED_TRACE(relative);
    const Envelope env = sweep(m, motion, relative);
    expectOneEmbeddedShell(env);
    std::mt19937_64 rng(50);
    checkEnvelope(m, motion, env, epsOf(m, relative), rng, "tetrahedron, shear keeping z", CheckOptions{});
  }
}

// The undirected edges of a cycle's triangles not used as often one way as the other (none:
// the cycle is a closed chain).
std::size_t unmatchedEdges(const std::vector<std::array<int, 3>>& triangles) {
  std::map<std::pair<int, int>, int> net;  // +1 as (a, b) with a < b, -1 reversed
  for (const auto& tri : triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      net[{std::min(a, b), std::max(a, b)}] += a < b ? 1 : -1;
    }
  std::size_t unmatched = 0;
  for (const auto& [edge, n] : net) unmatched += n != 0;
  return unmatched;
}

// The L-shaped prism of the sweep fuzz target (tests/sweep/fixtures), and its shear along
// z += 2.25 y with a unit translation, whose trajectories are straight.
Mesh lPrism() {
  const steady::io::TriangleMesh t = steady::io::readMesh(STEADY_TEST_FIXTURES "/l_prism.off");
  return Mesh{t.vertices, t.faces};
}
Motion3 lPrismShear(const Mesh& m) {
  return steady::io::readMotionFile(STEADY_TEST_FIXTURES "/l_prism_shear.json").motion().toMotion(makeBody(m).box());
}

// Whether the triangle (a, b, c) has area: twice its area above 1e-12 of its longest side squared.
bool hasArea(const V& a, const V& b, const V& c) {
  return (b - a).cross(c - a).norm() > 1e-12 * std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
}

// Cap sides cut finely (README, "Long cap edges"): the L-shaped prism of the sweep fuzz target
// along a shear (z += 2.25 y) with a unit translation. Its trajectories are straight, so with
// the time grid of condition (1) alone (detail::UnbalancedGrids; the sweep balances such grids
// now, see TwistingStripsGetBalancedGrids) its strips need pieces in proportion to 1/eps, and
// at 1e-3 two cap faces have 786 and 1,569 points on their sides. Fanned around one point, each made that many thin triangles whose
// boxes all met (n^2 pairs for the crossing tests, and again for the output's check, 3 s at
// 5e-4); they are triangulated in graded rings now (cycle.cpp, kGradedCapPoints). The cycle
// must stay a closed chain of cap triangles with area, no vertex may lie in more than
// kGradedCapPoints (256) of them (a fan's apex lies in all of its triangles: 1,569), and their
// boxes may meet in fewer than 50 pairs per cap triangle (the rings: 29; the fans: 588).
TEST(Envelope, LongCapSidesAreTriangulatedInGradedRings) {
  const Mesh m = lPrism();
  const Motion3 motion = lPrismShear(m);
  {
    const Body body(m.v, m.f);
    const steady::sweep::detail::UnbalancedGrids unbalanced;  // (balanced grids cut the sides far less)
    const auto plan = steady::sweep::detail::planSpan(body, motion.span(0), nullptr, 0.5 * epsOf(m, 1e-3),
                                                      steady::sweep::GrazingOptions{}, 1 << 16, 0);
    steady::sweep::detail::Cycle cycle;
    steady::sweep::detail::appendSpanCycle(cycle, nullptr, *plan, nullptr);
    // (a single span's caps come first)
    const std::vector<std::array<int, 3>> caps(cycle.triangles.begin(),
                                               cycle.triangles.begin() + static_cast<std::ptrdiff_t>(cycle.cap_triangles));
    ASSERT_GT(caps.size(), 2000u);
    EXPECT_EQ(unmatchedEdges(cycle.triangles), 0u) << "the cycle is a closed chain";
    std::map<int, int> valence;
    for (const auto& tri : caps)
      for (const int v : tri) ++valence[v];
    int most = 0;
    for (const auto& [v, n] : valence) most = std::max(most, n);
    EXPECT_LE(most, 256) << "a vertex in that many cap triangles: a fan";
    std::vector<std::array<V, 2>> box(caps.size());
    for (std::size_t i = 0; i < caps.size(); ++i) {
      const V &a = cycle.vertices[caps[i][0]], &b = cycle.vertices[caps[i][1]], &c = cycle.vertices[caps[i][2]];
      box[i] = {{a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)}};
      EXPECT_TRUE(hasArea(a, b, c)) << "cap triangle " << i << " has no area";
    }
    std::size_t pairs = 0;
    for (std::size_t i = 0; i < caps.size(); ++i)
      for (std::size_t j = i + 1; j < caps.size(); ++j)
        pairs += (box[i][0].array() <= box[j][1].array()).all() && (box[j][0].array() <= box[i][1].array()).all();
    EXPECT_LE(pairs, 50 * caps.size()) << "cap triangles whose boxes meet";
  }
  const Envelope env = sweep(m, motion, 1e-3);
  expectOneEmbeddedShell(env);
  std::mt19937_64 rng(53);
  checkEnvelope(m, motion, env, epsOf(m, 1e-3), rng, "L-shaped prism along a shear, long cap sides", CheckOptions{});
}

// Balanced time grids (cycle.cpp, kBalancedPieces): the L-shaped prism along its shear at 1e-3,
// whose straight trajectories take the whole span in one step of condition (1). Its twisting
// strips then needed all their pieces along the segments: cells as long as the span and a
// thousandth as wide, and caps whose sides were cut as finely. With steps and pieces balanced,
// the cycle must stay a closed chain with far fewer cap triangles (186 against 19,124 in the
// graded rings, at the time of writing), its triangles' boxes must meet fewer others (20.9
// against 69.5 a triangle), and the volume must agree with the unbalanced cycle's within the
// tolerance times the area.
TEST(Envelope, TwistingStripsGetBalancedGrids) {
  namespace d = steady::sweep::detail;
  const Mesh m = lPrism();
  const Motion3 motion = lPrismShear(m);
  const Body body(m.v, m.f);
  const double eps = epsOf(m, 1e-3);
  const auto cycleOf = [&](bool balanced) {
    std::optional<d::UnbalancedGrids> unbalanced;
    if (!balanced) unbalanced.emplace();
    const auto plan = d::planSpan(body, motion.span(0), nullptr, 0.5 * eps, steady::sweep::GrazingOptions{}, 1 << 16, 0);
    d::Cycle c;
    d::appendSpanCycle(c, nullptr, *plan, nullptr);
    return c;
  };
  // per cycle: its volume and area, and the mean number of other triangles whose boxes meet a
  // triangle's (a sweep over the boxes sorted by their low x)
  struct Measures {
    double volume = 0, area = 0, meets = 0;
  };
  const auto measure = [](const d::Cycle& c) {
    Measures out;
    std::vector<std::array<V, 2>> box;
    for (const auto& tri : c.triangles) {
      const V &a = c.vertices[tri[0]], &b = c.vertices[tri[1]], &e = c.vertices[tri[2]];
      out.volume += a.dot(b.cross(e)) / 6, out.area += (b - a).cross(e - a).norm() / 2;
      box.push_back({{a.cwiseMin(b).cwiseMin(e), a.cwiseMax(b).cwiseMax(e)}});
    }
    std::sort(box.begin(), box.end(), [](const auto& x, const auto& y) { return x[0].x() < y[0].x(); });
    std::size_t pairs = 0;
    for (std::size_t i = 0; i < box.size(); ++i)
      for (std::size_t j = i + 1; j < box.size() && box[j][0].x() <= box[i][1].x(); ++j)
        pairs += (box[i][0].array() <= box[j][1].array()).all() && (box[j][0].array() <= box[i][1].array()).all();
    out.meets = 2.0 * static_cast<double>(pairs) / static_cast<double>(box.size());
    return out;
  };
  const d::Cycle fine = cycleOf(false), balanced = cycleOf(true);
  EXPECT_EQ(unmatchedEdges(balanced.triangles), 0u) << "the balanced cycle is a closed chain";
  const Measures f = measure(fine), b = measure(balanced);
  std::printf("[ info     ] prism shear at 1e-3: cap triangles %zu -> %zu, cycle triangles %zu -> %zu, boxes met per triangle %.1f -> %.1f, area %.4f -> %.4f\n",
              fine.cap_triangles, balanced.cap_triangles, fine.triangles.size(), balanced.triangles.size(), f.meets, b.meets, f.area, b.area);
  EXPECT_LT(20 * balanced.cap_triangles, fine.cap_triangles);
  EXPECT_LT(2 * b.meets, f.meets);
  EXPECT_NEAR(b.volume, f.volume, eps * b.area);
}

// Balanced grids through the whole sweep, against the oracle: seeded random shears (I + u v^T,
// v . u = 0, and a translation across v, so that every trajectory is straight) of the bundled
// box and bracket and the L-shaped prism at 1e-3, two each. Every envelope must be closed,
// embedded, one shell, and pass checkEnvelope; at least half of the spans must take balanced
// grids (fewer cycle triangles than with detail::UnbalancedGrids). (PolySAMs of such shears:
// PolySamsOfStraightShearsMergeTheirJoints below, and the campaign's third table.)
TEST(Envelope, RandomShearsWithBalancedGridsPassTheOracle) {
  namespace d = steady::sweep::detail;
  const std::vector<std::pair<std::string, Mesh>> meshes = {
      {"box", bundledMesh("box")},
      {"bracket", bundledMesh("bracket")},
      {"l_prism", lPrism()}};
  std::mt19937_64 rng(72);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(1.0, 2.5);
  std::size_t spans = 0, balanced = 0;
  for (const auto& [name, m] : meshes) {
    const double diag = makeBody(m).box().diagonal();
    const auto shear = [&] {
      const V v = V(unit(rng), unit(rng), unit(rng)).normalized();
      V u(unit(rng), unit(rng), unit(rng));
      u = (u - u.dot(v) * v).normalized() * size(rng);
      V t = 0.5 * diag * V(unit(rng), unit(rng), unit(rng));
      t -= t.dot(v) * v;  // (a translation along v would bend the trajectories: M v(x) = u (v . t))
      return Affine3(Eigen::Matrix3d::Identity() + u * v.transpose(), t);
    };
    for (int k = 0; k < 2; ++k) {
      const Motion3 motion = single(Affine3(), shear());
      const std::string what = name + " along random shear " + std::to_string(k);
      SCOPED_TRACE(what);
      const Envelope env = sweep(m, motion, 1e-3);
      const Body body(m.v, m.f);
      const auto cycleSize = [&](std::size_t i, bool even) {
        std::optional<d::UnbalancedGrids> unbalanced;
        if (!even) unbalanced.emplace();
        const auto plan = d::planSpan(body, motion.span(i), nullptr, 0.5 * epsOf(m, 1e-3), steady::sweep::GrazingOptions{}, 1 << 16, 0);
        d::Cycle c;
        d::appendSpanCycle(c, nullptr, *plan, nullptr);
        return c.triangles.size();
      };
      for (std::size_t i = 0; i < motion.spanCount(); ++i, ++spans) balanced += cycleSize(i, true) < cycleSize(i, false);
      expectOneEmbeddedShell(env);
      CheckOptions co;
      if (name == "bracket") co.expected_euler = 99;  // (whether the sweep closes the bracket's holes is not derived here)
      checkEnvelope(m, motion, env, epsOf(m, 1e-3), rng, what, co);
    }
  }
  std::printf("[ info     ] balanced grids in %zu of %zu random shear spans\n", balanced, spans);
  EXPECT_GE(2 * balanced, spans) << "too few spans take balanced grids: stronger shears";
}

// PolySAMs of straight shears: every velocity is along one direction u (v(x) = u (w . x) + t), so
// the grazing chords slide along themselves, or, with t = 0, stand still in the plane of fixed
// points. Where such a chord crosses an edge between two faces, its point there lies off the
// posed edge by rounding; the two spans' caps at the joint must still merge (cycle.cpp,
// "Joints"), or the flat cap of one span and the cap of the other, bent by 1e-17 at that point,
// cross at that angle over the whole face. The box along two random shears with translations,
// a shear then a translation, and two linear shears whose planes of fixed points cross it (the
// fixtures): one embedded shell each, which the oracle checks.
TEST(Envelope, PolySamsOfStraightShearsMergeTheirJoints) {
  const Mesh m = bundledMesh("box");
  std::mt19937_64 rng(73);
  for (const std::string name : {"box_two_shears", "box_shear_translation", "box_two_fixed_shears"}) {
    SCOPED_TRACE(name);
    const Motion3 motion = steady::io::readMotionFile(STEADY_TEST_FIXTURES "/" + name + ".json").motion().toMotion(makeBody(m).box());
    const Envelope env = sweep(m, motion, 1e-3);
    expectOneEmbeddedShell(env);
    checkEnvelope(m, motion, env, epsOf(m, 1e-3), rng, name);
  }
}

// Joint caps whose chords cross (cycle.cpp, splitAndFan): at a joint where a face is split in
// both spans, one chord standing still (the first span's plane of fixed points) and the other
// sliding along itself, the caps' sum is bounded by a loop that crosses itself. Fanned as it is,
// its triangles overlapped with opposite orientations, a rounding off one plane; they did not
// cancel, and the box's envelope kept a face 3.4 ε inside a posed body that its own check did
// not see. Cut at the crossing, the prism's envelope was open until the sliver of the cut was
// merged across its edge (mergeJointSlivers). Two of the campaign's polySAMs of straight shears
// (cases 27 and 22 of scripts/stress-sweep.sh --shears; the fixtures): each must cut at least
// one joint loop, and give one embedded shell that the oracle checks.
TEST(Envelope, JointCapsWhoseChordsCrossAreCutAtTheCrossing) {
  namespace d = steady::sweep::detail;
  std::mt19937_64 rng(74);
  for (const auto& [name, rel] : {std::pair<std::string, double>{"crossing_chords_box", 2e-3}, {"crossing_chords_prism", 1e-3}}) {
    SCOPED_TRACE(name);
    const steady::io::TriangleMesh t = steady::io::readMesh(STEADY_TEST_FIXTURES "/" + name + ".off");
    const Mesh m{t.vertices, t.faces};
    const Motion3 motion = steady::io::readMotionFile(STEADY_TEST_FIXTURES "/" + name + ".json").motion().toMotion(makeBody(m).box());
    // (the cycle at the sweep's first tessellation tolerance, half of ε: its cut loops)
    const Body body(m.v, m.f);
    d::Cycle c;
    d::EdgeZeros zeros(body.edges().size());
    std::vector<d::SpanPlanPtr> plans;
    for (std::size_t i = 0; i < motion.spanCount(); ++i) {
      const Affine3 end = i + 1 < motion.spanCount() ? motion.span(i + 1).start() : Affine3();
      plans.push_back(d::planSpan(body, motion.span(i), i + 1 < motion.spanCount() ? &end : nullptr, 0.5 * epsOf(m, rel),
                                  steady::sweep::GrazingOptions{}, 1 << 16, static_cast<int>(i), &zeros));
    }
    for (std::size_t i = 0; i < plans.size(); ++i)
      d::appendSpanCycle(c, i > 0 ? plans[i - 1].get() : nullptr, *plans[i], i + 1 < plans.size() ? plans[i + 1].get() : nullptr);
    EXPECT_GE(c.joint_slivers.size(), 1u) << "no joint loop crosses itself: the fixture no longer reaches the cut";
    const Envelope env = sweep(m, motion, rel);
    expectOneEmbeddedShell(env);
    checkEnvelope(m, motion, env, epsOf(m, rel), rng, name);
  }
}

// Graded rings against fans (detail::FanEveryCap), on seeded random spans whose trajectories
// are straight (a shear I + u v^T with v . u = 0, and a translation), so that strips cut cap
// sides finely: the bundled box, tetrahedron and bracket and the L-shaped prism at 5e-4, with
// the grids of condition (1) alone (detail::UnbalancedGrids). Both cycles must be closed
// chains, and the caps must cover the same polygons once: the same volume (divergence theorem,
// as a sum of tetrahedra from one point) and the same sum of unsigned cap triangle areas (a
// triangle turned over, or two that overlap, adds to it), to 1e-9 of those sums; no graded cap
// triangle may be without area. At least a third of the spans must use the rings (their cap
// triangle counts differ). The cycle of the balanced grid the sweep uses must be closed too,
// with no more cap triangles, and its volume within the tolerance times its area of theirs.
TEST(Envelope, GradedCapsCoverWhatTheFansCover) {
  namespace d = steady::sweep::detail;
  const std::vector<std::pair<std::string, Mesh>> meshes = {
      {"box", bundledMesh("box")},
      {"tetrahedron", bundledMesh("tetrahedron")},
      {"bracket", bundledMesh("bracket")},
      {"l_prism", lPrism()}};
  struct Measures {
    double volume = 0, volume_scale = 0, cap_area = 0, area = 0;
    std::size_t caps = 0, thin = 0;
    bool closed = true;
  };
  auto measure = [](const d::Cycle& c) {
    Measures out;
    const V o = c.vertices.front();
    for (std::size_t i = 0; i < c.triangles.size(); ++i) {
      const auto& tri = c.triangles[i];
      const V a = c.vertices[tri[0]] - o, b = c.vertices[tri[1]] - o, e = c.vertices[tri[2]] - o;
      const double six = a.dot(b.cross(e));
      out.volume += six / 6, out.volume_scale += std::abs(six) / 6;
      out.area += (b - a).cross(e - a).norm() / 2;
      if (i < c.cap_triangles) {
        out.cap_area += (b - a).cross(e - a).norm() / 2;
        out.thin += !hasArea(a, b, e);
      }
    }
    out.closed = unmatchedEdges(c.triangles) == 0;
    out.caps = c.cap_triangles;
    return out;
  };
  std::mt19937_64 rng(71);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(0.5, 2.5);
  std::size_t spans = 0, graded = 0;
  for (const auto& [name, m] : meshes)
    for (int k = 0; k < 6; ++k) {
      const Body body(m.v, m.f);
      const double diag = body.box().diagonal();
      const V v = V(unit(rng), unit(rng), unit(rng)).normalized();
      V u(unit(rng), unit(rng), unit(rng));
      u = (u - u.dot(v) * v).normalized() * size(rng);
      Eigen::Matrix3d L = Eigen::Matrix3d::Identity() + u * v.transpose();
      const V t = k % 2 ? V(diag * V(unit(rng), unit(rng), unit(rng))) : V::Zero();
      const Span3 span = Span3::between(Affine3(), Affine3(L, t));
      const std::string what = name + " span " + std::to_string(k);
      const auto planOf = [&] { return d::planSpan(body, span, nullptr, 0.5 * 5e-4 * diag, steady::sweep::GrazingOptions{}, 1 << 16, 0); };
      d::Cycle rings, fans, balanced;
      {
        const d::UnbalancedGrids unbalanced;
        const auto plan = planOf();
        d::appendSpanCycle(rings, nullptr, *plan, nullptr);
        const d::FanEveryCap fan;
        d::appendSpanCycle(fans, nullptr, *plan, nullptr);
      }
      d::appendSpanCycle(balanced, nullptr, *planOf(), nullptr);
      const Measures r = measure(rings), f = measure(fans), b = measure(balanced);
      // The balanced grid tessellates the same strips within the same bound (each within eps/2
      // of the true surfaces, and of each other by eps): the volumes differ by at most eps times
      // the area the strips and caps sweep, bounded here by the sum of |triangle areas|.
      EXPECT_TRUE(b.closed) << what;
      EXPECT_NEAR(b.volume, f.volume, 5e-4 * diag * b.area) << what;
      EXPECT_LE(b.caps, r.caps) << what;
      ++spans;
      graded += r.caps != f.caps;
      EXPECT_TRUE(r.closed) << what;
      EXPECT_TRUE(f.closed) << what;
      EXPECT_EQ(r.thin, 0u) << what;
      EXPECT_NEAR(r.volume, f.volume, 1e-9 * f.volume_scale) << what;
      EXPECT_NEAR(r.cap_area, f.cap_area, 1e-9 * f.cap_area) << what;
    }
  std::printf("[ info     ] graded rings in %zu of %zu random straight-trajectory spans\n", graded, spans);
  EXPECT_GE(3 * graded, spans) << "too few spans reach the rings: finer tolerance or other spans";
}

// A thin plate stretched by an affine pose and brought back along the same path (a sweep fuzz
// input, tests/fuzz/corpus/sweep/plate_stretch_label_rays): the second span's velocities are the
// first's negated, so both spans split the bottom face along one grazing line, and the caps they
// leave there at the start pose coincide. Each span used to compute the line's ends from its
// own log, an ulp apart, and to cut its chords and edge pieces from its own end (the segments run
// opposite ways in the two spans): the two caps crossed in thousands of slivers, which took the
// labels' exact rays 13 s on the fuzz input. Now the spans share their zeros (planSpan's `seen`)
// and cut every segment from its lesser end, so both make the same points (checked on the two
// spans' cycle below). At 5e-3 that cycle also read a vertex through a reference that adding
// vertices had left dangling (the joint's caps between two chords of one face, in more than one
// loop), which crashed the sweep.
// The sweep itself now leaves the second span out (it sweeps the first's poses backwards), and so
// every later stroke of a reciprocating motion: with the sheets of both spans, the envelope was
// 8 times larger, and at some tolerances kept a handle among the retraced sheets.
TEST(Envelope, StretchedAndBroughtBackAlongTheSamePath) {
  const Mesh m = box(V(0, 0, 0), V(1, 1, 0.02));
  Eigen::Matrix3d L;
  L << -1.0 / 16, -1, 3, 41.0 / 8, 0, 0.5, 0, 41.0 / 8, 0;
  const Affine3 P(L, V::Zero());
  const Motion3 motion = Motion3::polySam(std::vector<Affine3>{Affine3(), P, Affine3()});
  {  // the cycle of both spans: its points in the bottom face's plane are shared exactly
    namespace d = steady::sweep::detail;
    const steady::sweep::Body body(m.v, m.f);
    const double eps_t = epsOf(m, 5e-3) / 2;
    d::EdgeZeros zeros(body.edges().size());
    const Affine3 joint = motion.span(1).start();
    const auto first = d::planSpan(body, motion.span(0), &joint, eps_t, steady::sweep::GrazingOptions{}, 1 << 16, 0, &zeros);
    const auto last = d::planSpan(body, motion.span(1), nullptr, eps_t, steady::sweep::GrazingOptions{}, 1 << 16, 1, &zeros);
    d::Cycle cycle;
    d::appendSpanCycle(cycle, nullptr, *first, last.get());
    d::appendSpanCycle(cycle, first.get(), *last, nullptr);
    std::vector<V> bottom;  // off the plate's corners
    for (const V& x : cycle.vertices)
      if (std::abs(x.z()) <= 1e-9 && std::min(std::abs(x.x() - 0.5), std::abs(x.y() - 0.5)) < 0.5 - 1e-9) bottom.push_back(x);
    std::size_t near_misses = 0;
    for (std::size_t i = 0; i < bottom.size(); ++i)
      for (std::size_t j = i + 1; j < bottom.size(); ++j)
        near_misses += bottom[i] != bottom[j] && (bottom[i] - bottom[j]).norm() <= 1e-9;
    EXPECT_GT(bottom.size(), 0u) << "both spans split the bottom face";
    EXPECT_EQ(near_misses, 0u) << "two cycle points in the bottom face within 1e-9 of each other, not equal";
  }
  const Envelope stroke = sweep(m, single(Affine3(), P), 5e-3);
  // Strokes: to P and back; to P, back and to P again; and a return that misses the start by
  // 0.05, which is not a repeat.
  struct Case {
    std::vector<Affine3> keys;
    std::size_t repeated;
  };
  for (const Case& c : {Case{{Affine3(), P, Affine3()}, 1}, Case{{Affine3(), P, Affine3(), P}, 2},
                        Case{{Affine3(), P, Affine3::translation(V(0.05, 0, 0))}, 0}}) {
    SCOPED_TRACE(c.keys.size());
    const Motion3 strokes = Motion3::polySam(c.keys);
    const Envelope env = sweep(m, strokes, 5e-3);
    EXPECT_EQ(env.spans_repeated, c.repeated);
    expectOneEmbeddedShell(env);
    if (c.repeated > 0) {  // the first stroke's envelope, triangle for triangle
      EXPECT_EQ(env.triangles.size(), stroke.triangles.size());
      EXPECT_NEAR(env.volume, stroke.volume, 1e-12 * stroke.volume);
    }
    std::mt19937_64 rng(51);
    checkEnvelope(m, strokes, env, epsOf(m, 5e-3), rng, "thin plate stretched and brought back", CheckOptions{});
  }
}

// The thin plate of the test above, its faces split along the other diagonals, along the first
// stroke alone. The span keeps the plate's corner at the origin fixed, and the strip near it has
// faces 1e-21 wide. A label ray's side (in front of its face or behind) was taken from the
// face's normal in doubles, which on such a sliver pointed the wrong way: that ray counted the
// other side's winding number, the labels propagated across edges disagreed with it, and every
// one of the 1,581 patches was labelled by a ray (0.63 s of labels instead of 0.03 s). A
// disagreement is caught only in a component that is checked; a sliver patch with a ray of its
// own would have kept the wrong label. The side is now decided exactly.
TEST(Envelope, RaysFromSliversTakeTheirSideExactly) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.v.emplace_back(i & 1 ? 1.0 : 0.0, i & 2 ? 1.0 : 0.0, i & 4 ? 0.02 : 0.0);
  for (const std::array<int, 4>& q : std::vector<std::array<int, 4>>{
           {{0, 2, 3, 1}}, {{4, 5, 7, 6}}, {{0, 1, 5, 4}}, {{2, 6, 7, 3}}, {{0, 4, 6, 2}}, {{1, 3, 7, 5}}}) {
    m.f.push_back({{q[0], q[1], q[2]}});
    m.f.push_back({{q[0], q[2], q[3]}});
  }
  Eigen::Matrix3d L;
  L << -1.0 / 16, -1, 3, 41.0 / 8, 0, 0.5, 0, 41.0 / 8, 0;
  const Motion3 motion = single(Affine3(), Affine3(L, V::Zero()));
  const Envelope env = sweep(m, motion, 5e-3);
  EXPECT_EQ(env.label_mismatches, 0u);
  EXPECT_LT(env.patches_by_ray, env.patches / 4) << "labels propagated across edges, a sample checked by rays";
  expectOneEmbeddedShell(env);
  std::mt19937_64 rng(53);
  checkEnvelope(m, motion, env, epsOf(m, 5e-3), rng, "thin plate, slivers at a fixed corner", CheckOptions{});
}

// The end pose of one span of the bracket's screw about the z axis, which lies in its upright's
// back face: a quarter turn while rising 2.5 and scaling by 1.2.
Affine3 bracketQuarterTurn() {
  return Affine3::translation(V(0, 0, 2.5)) * Affine3::rotation(V(0, 0, 1), M_PI / 2) * Affine3::scaling(V(1.2, 1.2, 1.2));
}

// The README's main command: the bracket (non-convex, two plates with holes, genus 2) along the
// bundled growing screw, two SAM spans joined at a pose where both spans leave caps.
TEST(Envelope, BundledBracketOnTheGrowingScrew) {
  const Mesh m = bundledBracket();
  const Motion3 motion = steady::io::readMotionFile(STEADY_DATA_DIR "/motions/screw_scale.json")
                             .motion()
                             .toMotion(makeBody(m).box());
  ASSERT_EQ(motion.spanCount(), 2u);
  const Envelope env = sweep(m, motion);
  std::mt19937_64 rng(41);
  CheckOptions co;
  co.expected_euler = 99;  // whether the sweep closes the plates' holes is not derived here
  checkEnvelope(m, motion, env, epsOf(m), rng, "bracket on growing screw", co);
}

// A planar face contains the screw axis and the span rises along it: the face's grazing chord
// lies on the axis and its strip slides along itself (no area). Before such strips were built
// exactly on their line, the sliver ribbon left 20 edges with four faces (not closed, not
// manifold, 257 self-intersecting pairs).
TEST(Envelope, FaceThroughTheScrewAxis) {
  const Mesh m = bundledBracket();  // its upright's back face is the plane x = 0
  const Motion3 motion = single(Affine3(), Affine3::translation(V(0, 0, 1)) * Affine3::rotation(V(0, 0, 1), M_PI / 3));
  const Envelope env = sweep(m, motion);
  std::mt19937_64 rng(43);
  CheckOptions co;
  co.expected_euler = 99;
  checkEnvelope(m, motion, env, epsOf(m), rng, "bracket about an axis in its face", co);
}

// The bundled half-turn screw about the z axis, which lies in the plane of the bracket's upright
// back face (x = 0), with the hole's top and bottom vertices 4.6e-17 off the axis in the mesh
// (cos 90 degrees in its generator). Near the axis, the face at the end of the span lies on the
// face at its start, back to back: the swept volume holds both sides, so both go. The end cap
// used to be posed by exp(log A) at 1, whose sin(pi) = 1.2e-16 put it 3e-17 off the start cap's
// plane: the exact trimming kept the two faces as walls of a void sliver that thin, and rounding
// the arrangement's points made them cross (2 self-intersecting pairs; the area 4.2 larger).
// Now the end cap is posed by the key pose A B, and "angle_deg": 180 gives exactly
// diag(-1, -1, 1).
TEST(Envelope, HalfTurnAboutAnAxisInAFaceWithInputNoiseOnTheAxis) {
  const Mesh m = bundledBracket();
  const double noise = m.v[147].y();  // the hole's top vertex (0, 4.6e-17, 3): the noise this test is about
  ASSERT_GT(noise, 0.0);
  ASSERT_LT(noise, 1e-16);
  const Motion3 motion = steady::io::readMotionFile(STEADY_DATA_DIR "/motions/screw.json").motion().toMotion(makeBody(m).box());
  ASSERT_EQ(motion.spanCount(), 1u);
  const Envelope env = sweep(m, motion);
  expectOneEmbeddedShell(env);
  std::mt19937_64 rng(53);
  CheckOptions co;
  co.expected_euler = 99;
  checkEnvelope(m, motion, env, epsOf(m), rng, "bracket on a half-turn screw", co);
  // No void wall pair at the axis: the back-to-back faces there are about 4.2 of area.
  EXPECT_LT(env.area, 156.0);
}

// The same face through the axis on a polySAM of two such spans (the old default motion: quarter
// turns about the z axis, rising by 2.5 and scaling by 1.2). The run of mesh edges along the axis
// (body vertices at y = 0 and y = 4.6e-17) once got one line per edge, so the edge between two
// of them swept a ribbon of slivers; and the first span moved its end vertices onto its line
// while the second posed them again, so the joint caps met in points a few ulps apart (15 pairs of
// faces crossing). Now each run has one line and the second span starts from the first span's end
// vertices: the output must be closed, manifold and free of self-intersections.
TEST(Envelope, FaceThroughTheScrewAxisOnAPolySamIsClosedAndEmbedded) {
  const Mesh m = bundledBracket();
  const Affine3 quarter = bracketQuarterTurn();
  const Motion3 motion = Motion3::polySam(std::vector<Affine3>{Affine3(), quarter, quarter * quarter});
  const Envelope env = sweep(m, motion);
  EXPECT_EQ(env.cycle_open_edges, 0u);
  expectOneEmbeddedShell(env);
  EXPECT_EQ(directedEdgeFaults(env.triangles, env.vertices.size()), "");
}

// The first span of the polySAM above alone: a quarter turn about the z axis that rises by 2.5
// and scales by 1.2. The bracket's base-plate hole has a faceted wall nearly tangent to the
// motion; on it, a front sliver of a facet sweeps a slab far thinner than ε, the tessellated
// strips of its boundary swap sides, and an empty layer 0.02-0.1 ε thick runs deep inside the
// swept volume and opens onto the envelope near the span's end (a crack). Its walls were kept,
// leaving 14 of the 8,771 envelope vertices more than ε inside the body posed at tau 0.84-1.0
// (the worst at least 34 ε deep); now they are left out (Envelope::crack_faces_removed) and the
// mouth is closed. Checked: every
// envelope vertex in the box that held all 14 (the region swept by the hole wall late in the
// span, about 350 vertices) is within T = 1.01 ε of the true boundary by the certified oracle
// (within ε of some posed body and never deeper than ε inside one; the 1% is the oracle's
// resolution, as in checkEnvelope), and the whole output is closed, manifold and embedded.
TEST(Envelope, CrackAlongTheBracketHoleOnAQuarterTurn) {
  const Mesh m = bundledBracket();
  const Affine3 quarter = bracketQuarterTurn();
  const Motion3 motion = single(Affine3(), quarter);
  const auto t0 = std::chrono::steady_clock::now();
  const Envelope env = sweep(m, motion);
  expectOneEmbeddedShell(env);
  EXPECT_GT(env.crack_faces_removed, 0u);
  // (the box holds the 14 vertices found before, with margin)
  const NearCheck c = checkVerticesInBox(env, MovingBody(m, motion), V(-1.0, 3.0, 2.0), V(1.0, 5.5, 3.2));
  EXPECT_GE(c.checked, 250) << "the box no longer holds the vertices along the hole wall";
  EXPECT_EQ(c.failed, 0);
  EXPECT_LE(c.undecided, c.checked / 50) << "envelope vertices the oracle could not decide within its budget";
  std::printf("[ info     ] bracket quarter turn: %zu vertices, %d checked near the hole wall, %d fail, %d undecided, "
              "%zu crack faces removed, %.2fs\n",
              env.vertices.size(), c.checked, c.failed, c.undecided, env.crack_faces_removed,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

// The case above under the full oracle (checkEnvelope: closed, manifold, embedded, containment
// of posed bodies, a seeded sample of envelope vertices against the true boundary, and the
// inside test). Both spans have the crack of CrackAlongTheBracketHoleOnAQuarterTurn along the
// base plate's hole; its walls were kept, leaving vertices tens of eps inside a posed body.
// They are now left out face by face. The first attempt at that also took out faces along the
// screw axis near the joint: ribbons left by the strips that slide along the axis, a few ulps
// wide, whose rounded normals point anywhere, so their probes (and the probes that touched
// them) found "facing" walls at random; closing those mouths and rounding left 7 pairs of faces
// crossing. Faces without a usable normal in doubles now neither probe nor count as walls.
// The corner of the second span's crack mouth, which this sample did not reach, is checked
// vertex by vertex by CrackMouthCornerOnTheBracketPolySamIsClosed.
TEST(Envelope, FaceThroughTheScrewAxisOnAPolySam) {
  const Mesh m = bundledBracket();
  const Affine3 quarter = bracketQuarterTurn();
  const Motion3 motion = Motion3::polySam(std::vector<Affine3>{Affine3(), quarter, quarter * quarter});
  const Envelope env = sweep(m, motion);
  std::mt19937_64 rng(44);
  CheckOptions co;
  co.expected_euler = 99;
  checkEnvelope(m, motion, env, epsOf(m), rng, "bracket about an axis in its face, two spans", co);
}

// The corner of the second span's crack mouth on the polySAM above (see FaceThroughTheScrewAxis-
// OnAPolySam): the least-area filling of the mouth repeated an edge of the surface, and the
// refilling within a 3D Delaunay triangulation failed too, so the crack region was kept and the
// vertex at (-5.753, -0.382, 6.113) stayed 1.04-3.9 eps inside the body posed at tau 0.999 of
// that span. The mouth's refilling now leaves out the diagonals that repeat a surface edge.
// Every envelope vertex near that corner must pass checkVerticesInBox.
TEST(Envelope, CrackMouthCornerOnTheBracketPolySamIsClosed) {
  const Mesh m = bundledBracket();
  const Affine3 quarter = bracketQuarterTurn();
  const Motion3 motion = Motion3::polySam(std::vector<Affine3>{Affine3(), quarter, quarter * quarter});
  const Envelope env = sweep(m, motion);
  expectOneEmbeddedShell(env);
  const V corner(-5.753, -0.382, 6.113), reach(1.0, 1.0, 1.0);
  const NearCheck c = checkVerticesInBox(env, MovingBody(m, motion), corner - reach, corner + reach);
  EXPECT_GE(c.checked, 50) << "the box no longer holds the vertices near the corner";
  EXPECT_EQ(c.failed, 0);
  EXPECT_LE(c.undecided, c.checked / 50) << "envelope vertices the oracle could not decide within its budget";
  std::printf("[ info     ] bracket polySAM corner: %d vertices checked, %d fail, %d undecided\n", c.checked, c.failed,
              c.undecided);
}

// Checks every vertex of env within 50 eps of `deep` (a vertex once found too deep) with the
// certified oracle: at least 30 of them, none failing, at most 2% undecided; prints the counts
// under `what`.
void expectCrackMouthClosed(const Envelope& env, const Mesh& m, const Motion3& motion, const V& deep,
                            const char* what) {
  expectOneEmbeddedShell(env);
  const V reach = V::Constant(50 * env.tolerance);
  const MovingBody mb(m, motion);
  const NearCheck n = checkVerticesInBox(env, mb, deep - reach, deep + reach);
  EXPECT_GE(n.checked, 30) << "the box no longer holds the vertices about the crack mouth";
  EXPECT_EQ(n.failed, 0);
  EXPECT_LE(n.undecided, n.checked / 50) << "envelope vertices the oracle could not decide within its budget";
  // Against the boundary of the swept volume itself (see checkAcrossInBox).
  const AcrossCheck a = checkAcrossInBox(env, mb, deep - reach, deep + reach);
  EXPECT_EQ(a.deep.size(), 0u) << "a vertex inside the swept volume with no point outside within 1.01 eps, at "
                               << (a.deep.empty() ? V::Zero() : env.vertices[a.deep.front()]).transpose();
  EXPECT_LE(a.undecided, a.checked / 50) << "envelope vertices the oracle could not decide within its budget";
  std::printf("[ info     ] %s: %d vertices checked, %d fail, %d undecided; %d inside the swept volume, %zu deep, %d "
              "undecided; %zu mouths filled, %zu flap faces left out, kept: %zu buried patches, %zu crack faces (%zu "
              "vertices, %zu not certified within eps)\n",
              what, n.checked, n.failed, n.undecided, a.inside, a.deep.size(), a.undecided, env.pocket_mouths_filled,
              env.mouth_flaps_removed, env.buried_patches_kept, env.crack_faces_kept, env.kept_wall_vertices,
              env.kept_wall_uncertified.size());
}

// A UV sphere on a random screw (a case of a seeded stress campaign): crack mouths whose every
// triangulation repeats a surface edge as a diagonal (the surface crosses the mouth) could not
// be closed, so their crack walls were kept, and an envelope vertex lay 5.05 eps inside the
// body posed at tau 0.156. Such a mouth is now fanned around its mean point. Checked with the
// certified oracle: every envelope vertex in a box of 100 eps about that vertex (42 of them)
// is within T = 1.01 eps of the true boundary, and the output is one embedded shell, with no
// crack face or buried patch kept. With the fan disabled, the vertex failed; with flaps left
// out too (see FlapsAcrossACrackMouthAreLeftOut), it passed, but 70 crack faces and 5 buried
// patches were kept, which failed the test. Since the mouth loops are paired by position
// (MouthLoopsArePairedByPosition), the mouths close without the fan as well (measured: nothing
// kept), and the stress campaign passes every case with fans disabled: the fan decides no
// campaign case now (on bunny00's screw at 1e-3 it still closes mouths: 969 crack faces kept,
// 1,164 without it), and this test guards these mouths, however they are closed.
TEST(Envelope, UvSphereScrewCrackMouthsClose) {
  const Mesh m = uvSphere(6, 10, 0.6);
  Eigen::Matrix<double, 3, 4> b, c;
  b << -0.27680361856277474, 0.5688636745465977, -0.77445069341559547, 0.037244570071184979,  //
      -0.14473835252432621, 0.7720646249144516, 0.61884329540219707, 0.07930601758657263,      //
      0.94996345511766811, 0.2833907809669356, -0.13137389087582263, 0.1776388248258165;
  c << 0.35784787850808553, 0.4229464159615135, -0.83250298802621292, -0.86761472191173994,  //
      0.62173500863585374, 0.55726536792872061, 0.55036432364738397, 0.77925927102143577,    //
      0.69669970208393051, -0.71454295807360535, -0.063544363901014478, 0.16463481397787938;
  const Motion3 motion = single(Affine3::fromMatrix(b), Affine3::fromMatrix(c));
  const Envelope env = sweep(m, motion);
  EXPECT_EQ(env.crack_faces_kept, 0u);
  EXPECT_EQ(env.buried_patches_kept, 0u);
  expectCrackMouthClosed(env, m, motion, V(-0.3230634931278813, 0.009342144717226164, 0.65835898137252169),
                         "sphere screw crack mouths");
}

// The stress campaign's L prism on an affine span (case 1317): a crack mouth of 8 points whose
// loop is partly covered by three faces of the surface with all their corners on it (a flap
// folded over the mouth), so that every filling, fan included, crossed them; the crack was
// kept, with an envelope vertex 13.8 eps deep inside the swept volume. With the flaps left out
// the mouth closes: every envelope vertex within 50 eps of the former failure is checked.
TEST(Envelope, FlapsAcrossACrackMouthAreLeftOut) {
  const Mesh m = lShape(0.5);
  Eigen::Matrix<double, 3, 4> b, c;
  b << 0.9161238676034249, 0.023033086209158754, -0.40023310226294873, 0.27062533318929982,  //
      -0.29169887511121506, 0.72314707648626875, -0.62607513289397976, -0.49436907092500126,  //
      0.27500695530512365, 0.69030991786953488, 0.6692110218942614, 0.39889251948110205;
  c << 1.2770624885343218, 0.18275416152054147, -0.092997279366068608, 1.8910463144994361,  //
      -0.235071247449812, 0.50285512338040683, -0.96641858956008675, -1.780924721129705,     //
      -0.35141708224470702, 0.44176690926776824, 0.33491844832263179, 0.43228083684674168;
  const Motion3 motion = single(Affine3::fromMatrix(b), Affine3::fromMatrix(c));
  const Envelope env = sweep(m, motion, 2e-3);
  EXPECT_GT(env.mouth_flaps_removed, 0u);
  expectCrackMouthClosed(env, m, motion, V(1.3462980109390537, -0.47167873560580681, 1.7878563225641049),
                         "L prism affine crack mouth");
}

// The stress campaign's UV sphere on an affine span (case 7, checked on every vertex): a pocket
// mouth of 14 points whose fillings (CGAL's, the refill and the fan) all crossed faces of its
// own rim, folded over the mouth like flaps but with a corner up to 1.4 tessellation
// tolerances off the loop. The mouth failed, the buried patch at it was kept whole, and three
// envelope vertices 19 tolerances away were 1.14 to 1.99 eps deep inside the body posed at
// tau 1/32. With those rim faces left out for another round (kRimReach), the mouth closes and
// every vertex about the former failure lies on the true boundary.
TEST(Envelope, RimFacesAcrossAPocketMouthAreLeftOut) {
  const Mesh m = uvSphere(6, 10, 0.6);
  Eigen::Matrix<double, 3, 4> b, c;
  b << 0.57250006114733498, 0.3198455935517423, 0.75494534654624601, -0.0067470172765101699,  //
      -0.73868821872101575, 0.60076590584565381, 0.30564692358377143, -0.069485636882539392,  //
      -0.35578560329090114, -0.73265211571317035, 0.58020468959837346, -0.26701237502769648;
  c << 1.8951314322092667, 0.36260192133444341, 0.90711198563275253, 0.81494599430735959,  //
      -0.62018574936753101, 0.43205330432206035, 0.32899724199661423, -0.29934840129177998,  //
      -0.5948939084500855, -0.6091745132459605, 0.45337828338291064, -0.32568885210661419;
  const Motion3 motion = single(Affine3::fromMatrix(b), Affine3::fromMatrix(c));
  const Envelope env = sweep(m, motion, 2e-3);
  EXPECT_EQ(env.buried_patches_kept, 0u);
  EXPECT_GT(env.mouth_rim_faces_removed, 0u);
  expectCrackMouthClosed(env, m, motion, V(-0.53206084155595779, -0.12148789215915459, -0.052731963599349119),
                         "UV sphere affine pocket mouth");
}

// The stress campaign's torus along a polySAM of three poses (case 1279, checked on every
// vertex): a thin fold of the tessellated strips left a vertex of three faces poking 1.02 eps
// into the swept volume, with no crack face or buried patch found or kept there (so the kept
// counts did not flag it). Such a dent, whose probe towards the triangle of its neighbours ends
// inside the swept volume, is replaced by that triangle (Envelope::buried_dents_filled): every
// vertex within 50 eps of the former one is then on the true boundary.
TEST(Envelope, DentsPokingIntoTheSweptVolumeAreFilled) {
  const Mesh m = torus(0.7, 0.25, 12, 6);
  Eigen::Matrix<double, 3, 4> p0, p1, p2;
  p0 << -0.41274142775704381, 0.39856417680079215, 0.81901838244583014, -0.46538526612514486,  //
      -0.34450729902904675, 0.76407468910403131, -0.54543981371576544, 0.053958530550793915,  //
      -0.84318398628578572, -0.50728341826013268, -0.17805701005444088, -0.26945645040770716;
  p1 << 0.15174287053697844, -0.98838245793541446, -0.0086149919759961474, 1.527312834571916,  //
      -0.83871489582306047, -0.12414330318184463, -0.53023180195044306, -0.45496229121014509,  //
      0.52300231812651754, 0.087684417775618972, -0.84780895142339729, 0.34345047123090167;
  p2 << -0.48530628197562087, 0.30443401354104876, 0.8196326885100963, -0.47924484979710652,  //
      -0.82121651455336575, -0.48049840612272932, -0.30777380970176549, 0.49822085200256594,  //
      0.30013538428486114, -0.82246046294810127, 0.48319513448230594, 2.0948426058803031;
  const Motion3 motion = Motion3::polySam(
      std::vector<Affine3>{Affine3::fromMatrix(p0), Affine3::fromMatrix(p1), Affine3::fromMatrix(p2)});
  const Envelope env = sweep(m, motion, 2e-3);
  EXPECT_GT(env.buried_dents_filled, 0u);
  expectCrackMouthClosed(env, m, motion, V(1.0328932009259293, -0.36085863479414737, 0.1422234766691331),
                         "torus polySAM dent");
}

// The stress campaign's bracket on a screw span (case 970): a crack mouth whose loop shares
// points with other loops. The faces folded over it were not taken for flaps while a flap's
// corners had to lie on no other loop, every filling crossed them, and the crack was kept with
// an envelope vertex 1.84 eps deep. A flap is now any face with an edge on a loop and its third
// corner on that same loop. (The campaign's CGAL sphere under a shear and scaling, case 78,
// failed the same way: a loop covered by four such faces, 1.69 eps deep.) Since the loops are
// paired by position (MouthLoopsArePairedByPosition) this mouth closes under the old rule too
// (measured: 86 vertices checked, none failing). The stress campaign, under the old rule, then
// fails 2 cases (CGAL's sphere on screws, cases 1110 and 1200: 1.14 and 1.02 eps, among the 60
// vertices it samples per case), none under this one.
TEST(Envelope, FlapsAtPointsSharedByLoopsAreLeftOut) {
  const Mesh m = bundledBracket();
  Eigen::Matrix<double, 3, 4> b, c;
  b << 0.93403821598017778, -0.15690285842336885, 0.32086461959390772, 0.33270441604082457,  //
      0.21973766681851023, 0.96065067894206702, -0.16989888413201298, 0.097841619991081763,   //
      -0.28158119409812193, 0.22919809350586245, 0.93176191436630085, -0.43061366536882018;
  c << -0.76899836245532316, 0.29073413048719826, 0.56931114859177334, 0.17461042945371263,  //
      0.012029797777954369, 0.89701526779360474, -0.4418358216697571, -0.58027601254868266,   //
      -0.63913754584318783, -0.33292232534785138, -0.69330074482761561, 0.66837220336327707;
  const Motion3 motion = single(Affine3::fromMatrix(b), Affine3::fromMatrix(c));
  const Envelope env = sweep(m, motion);
  EXPECT_GT(env.mouth_flaps_removed, 0u);
  expectCrackMouthClosed(env, m, motion, V(3.9501023390594918, -0.44125229451952325, -1.1655026559111779),
                         "bracket screw crack mouth");
}

// The stress campaign's UV sphere on a screw (case 1445): a crack region of 15 faces was kept
// whole, with an envelope vertex 1.06 eps deep inside the body posed at tau 0.223, because a
// mouth 27 eps away could not be closed. Where several mouth loops meet at a point, which
// incoming edge the loop tracing followed by which outgoing one came from a hash map's order;
// the flaps (faces with an edge and the third corner on one loop) depend on that pairing. The
// pairing now follows the points' positions, and the mouths close: every envelope vertex within
// 50 eps of the former failure is checked. With the hash-map tracing linked in, the test fails:
// 15 of 104 vertices too deep, 256 crack faces and 16 buried patches kept.
TEST(Envelope, MouthLoopsArePairedByPosition) {
  const Mesh m = uvSphere(6, 10, 0.6);
  Eigen::Matrix<double, 3, 4> b, c;
  b << 0.066301459716110012, 0.82569999336924049, 0.56019964065460592, 0.32444180167027736,  //
      -0.80460708800456071, -0.2877875147415262, 0.51940906835722178, 0.14546176895092855,    //
      0.59009452664156647, -0.48517818099017213, 0.64528333491477496, -0.4727433546489227;
  c << -0.50406638821410621, 0.86351808960959286, -0.015924358379088066, -1.0086416270725023,  //
      -0.81999137415045231, -0.48428461096802589, -0.30509434917481104, -0.21250365738135199,   //
      -0.27116641125264662, -0.14072997014334754, 0.95218897962106941, 0.21694734366495691;
  const Motion3 motion = single(Affine3::fromMatrix(b), Affine3::fromMatrix(c));
  const Envelope env = sweep(m, motion, 2e-3);
  expectCrackMouthClosed(env, m, motion, V(0.46770365344363318, -0.0095015035288141259, 0.2358932359970595),
                         "sphere screw mouths paired by position");
}

// Expects envelope b to be a, bit for bit (triangles, then every vertex's doubles); `what`
// names the case in the messages.
void expectSameEnvelope(const Envelope& a, const Envelope& b, const std::string& what) {
  EXPECT_EQ(b.triangles, a.triangles) << what;
  ASSERT_EQ(b.vertices.size(), a.vertices.size()) << what;
  std::size_t differ = 0;
  for (std::size_t v = 0; v < a.vertices.size(); ++v) differ += !(b.vertices[v] == a.vertices[v]);
  EXPECT_EQ(differ, 0u) << "vertices not bit-identical, " << what;
}

// The re-triangulations and inside tests run in parallel, and their results are numbered in a
// fixed order afterwards: the envelope (vertices, triangles, counters) is the same, bit for bit,
// on one thread, two, and every hardware thread. (The runs on two threads and more also carry a
// cancel flag that stays false, SweepOptions::cancel: it changes nothing.)
TEST(Envelope, SameEnvelopeOnAnyNumberOfThreads) {
  const Body body = makeBody(bundledBracket());
  const Motion3 motion = single(Affine3(), bracketQuarterTurn());
  SweepOptions one;
  one.threads = 1;
  const Envelope a = sweptEnvelope(body, motion, one);
  ASSERT_GT(a.intersecting_pairs, 1000u);
  ASSERT_GT(a.crack_faces_removed + a.buried_patches_removed, 0u);
  for (const int threads : {2, 0}) {
    SweepOptions o;
    o.threads = threads;
    const std::atomic<bool> flag{false};
    o.cancel = &flag;
    const Envelope b = sweptEnvelope(body, motion, o);
    EXPECT_EQ(b.arrangement_triangles, a.arrangement_triangles) << threads << " threads";
    EXPECT_EQ(b.buried_patches_removed, a.buried_patches_removed) << threads << " threads";
    EXPECT_EQ(b.crack_faces_removed, a.crack_faces_removed) << threads << " threads";
    EXPECT_EQ(b.buried_patches_kept, a.buried_patches_kept) << threads << " threads";
    EXPECT_EQ(b.crack_faces_kept, a.crack_faces_kept) << threads << " threads";
    EXPECT_EQ(b.mouth_flaps_removed, a.mouth_flaps_removed) << threads << " threads";
    EXPECT_EQ(b.mouth_rim_faces_removed, a.mouth_rim_faces_removed) << threads << " threads";
    EXPECT_EQ(b.buried_dents_filled, a.buried_dents_filled) << threads << " threads";
    expectSameEnvelope(a, b, std::to_string(threads) + " threads");
  }
  SweepOptions bad;
  bad.threads = -1;
  EXPECT_TRUE(throwsError([&] { sweptEnvelope(body, motion, bad); }, ErrorCode::InvalidArgument, "threads"));
}

#ifdef STEADY_CGAL_MESHES
// One of CGAL's sample meshes (Debian's libcgal-demo), centred and scaled to a unit diagonal as
// in bench/sample_meshes.hpp (bit for bit).
steady::io::TriangleMesh cgalSample(const std::string& name) {
  steady::io::TriangleMesh mesh = steady::io::readMesh(std::string(STEADY_CGAL_MESHES) + "/" + name);
  V lo = mesh.vertices.front(), hi = lo;
  for (const V& x : mesh.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double s = 1.0 / (hi - lo).norm();
  const V c = 0.5 * (lo + hi);
  for (V& x : mesh.vertices) x = s * (x - c);
  return mesh;
}
// The same as a test mesh.
Mesh cgalSampleMesh(const std::string& name) {
  steady::io::TriangleMesh mesh = cgalSample(name);
  return {std::move(mesh.vertices), std::move(mesh.faces)};
}
// CGAL's sphere on the span from pose b to pose c (3x4 matrices), swept at tolerance eps: it
// keeps no wall (no crack face, no buried patch, no uncertified vertex), and every envelope
// vertex about `deep` is within T of the true boundary (expectCrackMouthClosed).
void expectSphereSpanKeepsNoWall(const Eigen::Matrix<double, 3, 4>& b, const Eigen::Matrix<double, 3, 4>& c, double eps,
                                 const V& deep, const char* what) {
  const Mesh m = cgalSampleMesh("sphere.off");
  const Motion3 motion = single(Affine3::fromMatrix(b), Affine3::fromMatrix(c));
  const Envelope env = sweep(m, motion, eps);
  EXPECT_EQ(env.crack_faces_kept, 0u);
  EXPECT_EQ(env.buried_patches_kept, 0u);
  EXPECT_TRUE(env.kept_wall_uncertified.empty())
      << env.kept_wall_uncertified.size() << " kept-wall vertices not certified";
  expectCrackMouthClosed(env, m, motion, deep, what);
}
// A sample and the benchmark's screw: a half turn about a vertical axis at x = 0.5 while
// rising 1.
struct SampleOnScrew {
  steady::io::TriangleMesh mesh;
  Span3 span;
};
SampleOnScrew cgalSampleOnTheBenchmarkScrew(const std::string& name) {
  steady::io::TriangleMesh mesh = cgalSample(name);
  const V axis_point(0.5, 0, 0);
  const Affine3 end = Affine3::translation(axis_point + V(0, 0, 1)) * Affine3::rotation(V(0, 0, 1), M_PI * (1 - 1e-9)) *
                      Affine3::translation(-axis_point);
  return {std::move(mesh), Span3::between(Affine3(), end)};
}
#endif

// The mouth rounds take a refill from the round before when the loop, the faces it avoids, its
// usable diagonals and the surface near it are as they were (MouthMemory::Refilled in trim.cpp).
// Each refill taken must be the one a search anew would give: the same triangles tested, with
// the same outcomes and surface faces reported, and the same filling
// (detail::RefillMemory::kVerify); and the envelopes must be those of sweeps that search every
// refill anew (kForget), to the last bit. Scenes whose mouths take several rounds. Taking
// refills without looking for new surface faces across their clear triangles gives 9 that
// differ in CGAL's sphere along screw.json at 1e-2 (none in the others); without looking their
// crossing triangles up again, every refill taken differs. Along keys.json at 5e-3 one refill
// no longer applies because a diagonal became an edge of the surface; taken anyway, it happens
// to give the same filling.
TEST(Envelope, RefillsTakenFromTheRoundBeforeAsSearchedAnew) {
  using steady::sweep::detail::RefillMemory;
  using steady::sweep::detail::RefillMemoryProbe;
  struct Case {
    std::string name;
    Mesh mesh;
    Motion3 motion;
    double relative;
  };
  const Mesh bracket = bundledMesh("bracket");
  std::vector<Case> cases = {{"bracket along keys.json at 1e-3", bracket, bundledMotion("keys", bracket), 1e-3}};
#ifdef STEADY_CGAL_MESHES
  const steady::io::TriangleMesh read = steady::io::readMesh(std::string(STEADY_CGAL_MESHES) + "/sphere.off");
  const Mesh sphere{read.vertices, read.faces};  // (as read, as the CLI sweeps it)
  cases.push_back({"CGAL's sphere along screw.json at 1e-2", sphere, bundledMotion("screw", sphere), 1e-2});
  cases.push_back({"CGAL's sphere along keys.json at 5e-3", sphere, bundledMotion("keys", sphere), 5e-3});
#endif
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Envelope verified, anew;
    std::size_t taken = 0;
    {
      const RefillMemoryProbe probe(RefillMemory::kVerify);
      verified = sweep(c.mesh, c.motion, c.relative);
      taken = probe.taken();
      EXPECT_EQ(probe.differing(), 0u);
    }
    {
      const RefillMemoryProbe probe(RefillMemory::kForget);
      anew = sweep(c.mesh, c.motion, c.relative);
      EXPECT_EQ(probe.taken(), 0u);
    }
    std::printf("[ info     ] %s: %zu refills taken from the round before\n", c.name.c_str(), taken);
    EXPECT_GT(taken, 0u);  // (the scene takes some)
    EXPECT_TRUE(verified.vertices == anew.vertices);
    EXPECT_TRUE(verified.triangles == anew.triangles);
  }
}

// Pinned: CGAL's sphere (unit diagonal) along the bundled growing screw at 1e-3, an envelope
// whose mouths take several rounds to close. The rounds take CGAL's fillings of the loops they
// traced before from the mouth memory (MouthMemory::filled) instead of searching again, which
// must leave the envelope as it was: the face count, vertex count and volume below were recorded
// with the code before that reuse (c09830a), and recorded again when the caps at the polySAM's
// joints were merged (cycle.cpp; the volume moved by 5.4e-10 of itself), and again in stop 61,
// when the last span ended at its key pose as given and the points on edges were placed as
// a + r (b - a) (the same counts; the volume moved by 3.4e-9 of itself), and in stop 62, when a
// generator column that is λ e_j gave the pose's column e^(λτ) e_j exactly (the screw's axis
// column; the same counts, the volume moved by 4.0e-10 of itself). A reused filling that
// differed would not show elsewhere: the rounds' own checks refill a bad one, and the other
// envelope tests all pass with the reused fillings reversed, while this envelope's volume then
// moves by 5.5e-13 of itself (the CLI's copy of the sphere, at its own size, gets 42 faces
// more). The tolerance, 1e-14 of the volume, is for the rounding of the volume's sum alone; the
// sweep gives the same envelope on any number of threads. (An intended change of the envelope records these again.)
TEST(Envelope, SphereOnTheGrowingScrewIsTheRecordedEnvelope) {
#ifndef STEADY_CGAL_MESHES
  GTEST_SKIP() << "CGAL's sample meshes (Debian libcgal-demo) were not found when the build was configured";
#else
  const Mesh m = cgalSampleMesh("sphere.off");
  const Motion3 motion = steady::io::readMotionFile(STEADY_DATA_DIR "/motions/screw_scale.json")
                             .motion()
                             .toMotion(makeBody(m).box());
  const Envelope env = sweep(m, motion);
  EXPECT_EQ(env.pocket_mouths_filled, 1193u);
  EXPECT_EQ(env.triangles.size(), 39618u);
  EXPECT_EQ(env.vertices.size(), 19361u);
  EXPECT_NEAR(env.volume, 3.380955902334104, 1e-14 * 3.380955902334104);
#endif
}

// bunny00 (CGAL's sample mesh, 75k faces, from Debian's libcgal-demo), centred and scaled to a
// unit diagonal as in bench/, on the benchmark's screw (a half turn about a vertical axis at
// x = 0.5 while rising 1), tolerance 1e-3: BM_SteadySweep/bunny00/screw/eps0.001. Its envelope
// touches itself at points where one of the fans is folded (its faces' vector area nearly
// cancels): moving every copy, or moving them into or out of their fans, makes faces cross at
// every step, and such pinches were left touching (193 face pairs at 4 points; at tolerances
// 3e-3 and 1e-2, 147 and 45 pinches) until the copy whose fan opens the widest was moved alone.
// The envelope must come out closed, manifold, one shell, without self-intersection, with no
// pinch left touching. (About 80 s on two cores.)
TEST(Envelope, FoldedFanPinchesOnTheBunnyScrewAreSeparated) {
#ifndef STEADY_CGAL_MESHES
  GTEST_SKIP() << "CGAL's sample meshes (Debian libcgal-demo) were not found when the build was configured";
#else
  const SampleOnScrew scene = cgalSampleOnTheBenchmarkScrew("bunny00.off");
  SweepOptions o;
  o.relative_tolerance = 1e-3;
  const Envelope env = sweptEnvelope(Body(scene.mesh.vertices, scene.mesh.faces), scene.span, o);
  EXPECT_GT(env.pinched_vertices_split, 0u);
  EXPECT_EQ(env.pinches_touching, 0u);
  expectOneEmbeddedShell(env);
#endif
}

// Run to run as well, where parallel work could leave traces: CGAL's sphere.off on the
// benchmark's screw at two tolerances, on one thread and three times on two. Two causes made
// these differ before (each seen in 2 to 4 of 4 runs on two threads): the doubles of the
// arrangement's points were read from the lazy kernel's intervals after the parallel steps,
// which narrow the intervals of whatever points they happen to evaluate exactly (1e-2), and
// CGAL's hole filling within a 3D Delaunay triangulation chose differently among fillings of
// equal weight (1e-3).
TEST(Envelope, SameEnvelopeRunToRunOnTheCgalSphereScrew) {
#ifndef STEADY_CGAL_MESHES
  GTEST_SKIP() << "CGAL's sample meshes (Debian libcgal-demo) were not found when the build was configured";
#else
  const SampleOnScrew scene = cgalSampleOnTheBenchmarkScrew("sphere.off");
  const Body body(scene.mesh.vertices, scene.mesh.faces);
  const Span3& span = scene.span;
  for (const double rel : {1e-2, 1e-3}) {
    SweepOptions one;
    one.relative_tolerance = rel;
    one.threads = 1;
    const Envelope a = sweptEnvelope(body, span, one);
    ASSERT_GT(a.pocket_mouths_filled, 0u) << rel;
    for (int run = 0; run < 3; ++run) {
      SweepOptions two = one;
      two.threads = 2;
      const Envelope b = sweptEnvelope(body, span, two);
      expectSameEnvelope(a, b, "tolerance " + std::to_string(rel) + ", run " + std::to_string(run));
    }
  }
#endif
}

// The stress campaign's random convex body on a screw (case 3320, tolerance 1e-3): crack walls
// joined across edges into regions that run along the strips for hundreds of eps; a mouth that no
// filling closes at one end of such a region kept the whole region (846 crack faces), and 143
// envelope vertices, up to 1.66 eps inside the swept volume, lay on walls far from that mouth.
// Regions are now kept by pieces (the faces in one cell of a grid of kCrackCell tessellation
// tolerances, 1 eps; 71 crack faces kept with cells of 16 eps, 48 with 4, 40 with 1), and
// around the vertex that was 1.10 eps deep every envelope vertex is within T = 1.01 eps of the
// true boundary (38 of them were not). With cells of 4 eps, a kept piece at another mouth held a
// vertex 1.23 eps deep, 10 eps from that mouth (its faces are long along the strips): the box
// about it is checked too.
TEST(Envelope, CrackRegionsAreKeptByPiecesNearTheirFailedMouths) {
  std::mt19937_64 rng(73003761ull ^ 0x9E3779B97F4A7C15ull);  // (as the campaign draws it)
  const Mesh m = randomConvex(rng, 10 + static_cast<int>(rng() % 7));
  ASSERT_EQ(m.f.size(), 20u);
  Eigen::Matrix<double, 3, 4> b, c;
  b << -0.75059439347520807, 0.19179811256557838, 0.63231443167135326, -0.42597805186707782,  //
      0.30164580724944406, 0.95087290108128497, 0.069645767696914648, -0.00017816203345810688,  //
      -0.58789273124645447, 0.24301071993955964, -0.77157496495288203, 0.027468300350615538;
  c << -0.048185711107250617, 0.42095392932271558, -0.90580126221641732, -0.06673996817172273,  //
      0.31298896236125728, 0.86754593862520901, 0.38652548921763008, -0.66021975353732931,      //
      0.94853362970698729, -0.26488079160760414, -0.17355725151147378, -0.46420688662665233;
  const Motion3 motion = single(Affine3::fromMatrix(b), Affine3::fromMatrix(c));
  const Envelope env = sweep(m, motion, 1e-3);
  EXPECT_GT(env.crack_faces_removed, 0u);
  expectCrackMouthClosed(env, m, motion, V(-0.077330055573830131, -0.48945229024906567, 0.67040394660703762),
                         "convex screw crack walls");
  expectCrackMouthClosed(env, m, motion, V(0.47910808059323562, -0.83085823285709459, 0.16289383310152697),
                         "convex screw crack walls at another mouth");
}

// The stress campaign's random convex body on a general affine span (case 1342, tolerance
// 1e-3): a crack mouth of 12 points, about 30 eps long and 10 eps wide, that no filling closed.
// CGAL's and the refill's triangulations all crossed faces folded over the mouth (corners on the
// loop and up to 1.2 eps off it), and the fan's apex, the loop's mean, lay farther than kFanReach
// from the loop, so the loop was left with no filling at all and its rim was never looked for:
// the rounds kept the crack walls, whose output vertices lay up to 1.78 eps inside the body
// posed at tau 0.72 (listed by the envelope as uncertified). A loop left with no filling now takes
// its rim from the faces that any of its fillings crossed, and the mouth closed so. The loop
// shares points with neighbouring loops, and is now joined with them and filled as one (see
// Joined mouths in trim.cpp) before any rim is needed (RimFacesAcrossAPocketMouthAreLeftOut
// still takes a rim). Checked against the certified oracle in a box of 50 eps about the formerly
// deepest vertex: every vertex is within T = 1.01 eps of the true boundary, and the envelope
// keeps no wall there that its certificate leaves uncertified.
TEST(Envelope, MouthWhoseFillingsAllCrossItsRimCloses) {
  std::mt19937_64 rng(29003831ull ^ 0x9E3779B97F4A7C15ull);  // (as the campaign draws it)
  const Mesh m = randomConvex(rng, 10 + static_cast<int>(rng() % 7));
  ASSERT_EQ(m.f.size(), 16u);
  Eigen::Matrix<double, 3, 4> b, c;
  b << 0.55953123099938273, -0.82593164938852581, 0.069005159768416591, 0.20188659338349901,  //
      0.48732632349348659, 0.26050767949855624, -0.83345593965883946, 0.16709485657442613,     //
      0.67040126489039165, 0.49997265871308066, 0.5482604167480416, 0.28836539810969164;
  c << 1.408729308169457, -1.1833373974901069, 0.0029537492292094347, -0.76988273124167883,  //
      0.39579737638367535, 0.3248944833652202, -0.98606243136348792, -0.11428705270401154,    //
      0.85651783992389297, 0.2686070055235511, -0.085821089876590262, 0.11310213078355374;
  const Motion3 motion = single(Affine3::fromMatrix(b), Affine3::fromMatrix(c));
  const Envelope env = sweep(m, motion, 1e-3);
  EXPECT_EQ(env.crack_faces_kept, 0u);
  EXPECT_TRUE(env.kept_wall_uncertified.empty())
      << env.kept_wall_uncertified.size() << " kept-wall vertices not certified";
  expectCrackMouthClosed(env, m, motion, V(0.56262003301811003, -0.46592578517088085, 0.3234162597455737),
                         "convex affine mouth closed through its rim");
}

// The torus polySAM of KeptWallsBesideThinOutsideLayersAreCertified (campaign case 604,
// tolerance 1e-3).
Motion3 thinLayersMotion() {
  Eigen::Matrix<double, 3, 4> p0, p1, p2;
  p0 << 0.89070993109068142, -0.0089455110116924332, 0.45448409926990102, 0.19139562122889719,  //
      0.018014312820796637, 0.99971558865232435, -0.01562774261149643, 0.17863624554840629,      //
      -0.45421504069111146, 0.022107004280914881, 0.89061775031249835, -0.069249736453529054;
  p1 << 0.48828179539616368, -0.048032828867323539, 0.87530771844670074, 1.4519383189336805,  //
      0.28675876951633011, 0.59441105922395321, 0.22521647432941871, 0.56162414623465751,      //
      -0.50470654882119947, -0.099475694717672702, 0.59842643776913362, -0.48665483745297949;
  p2 << 1.1331034251949794, 0.33864176084322806, 1.9744249456395175, 4.214478439210767,  //
      -0.30477399644273451, 0.19725815105764827, -0.75893216506763217, -1.2960883589048533,  //
      -0.094672181046677795, 0.092283179473092447, 0.59188922233285557, 0.01289957063117611;
  return Motion3::polySam(
      std::vector<Affine3>{Affine3::fromMatrix(p0), Affine3::fromMatrix(p1), Affine3::fromMatrix(p2)});
}

// The torus polySAM of UncertifiedKeptWallVerticesAreMovedOntoTheBoundary (campaign case
// 12979, tolerance 2e-3).
Motion3 movedKeptWallsMotion() {
  Eigen::Matrix<double, 3, 4> p0, p1, p2, p3;
  p0 << 0.40004197984217998, -0.87751908656329924, 0.26443650860095291, 0.37802545371853546,  //
      0.91348659304215041, 0.35840463022333513, -0.19258339847120517, -0.16645815953199661,     //
      0.074220338831033517, 0.31860064932700216, 0.94497881857331556, 0.4036169205758674;
  p1 << -0.29998922705410769, -1.4718117571332081, 0.1072577549260092, -0.2625244491334412,  //
      1.2849257822373628, 1.0259349864353309, 0.3792886488901881, -1.142455557863391,         //
      -0.21676484516106295, 0.10593551436022924, 0.72741558331206169, 0.26133742601814319;
  p2 << -0.0018227476621533456, -2.1888880768876731, 1.0804063052991588, -1.4718061365732902,  //
      1.2519094590928532, 1.0248645535898033, 0.96013259766894254, -1.9619021841191908,         //
      -0.3346031928683677, 0.12526206368075149, 0.80557301509665702, 0.11837723806154882;
  p3 << -0.0018227476621533456, -2.1888880768876731, 1.0804063052991588, -1.5594663586893429,  //
      1.2519094590928532, 1.0248645535898033, 0.96013259766894254, -2.7550590965818946,         //
      -0.3346031928683677, 0.12526206368075149, 0.80557301509665702, 0.094062508291527486;
  return Motion3::polySam(std::vector<Affine3>{Affine3::fromMatrix(p0), Affine3::fromMatrix(p1),
                                               Affine3::fromMatrix(p2), Affine3::fromMatrix(p3)});
}

// The torus polySAM of DeepKeptWallsAreReported (campaign case 47764, tolerance 1e-3), drawn
// as the campaign draws it.
Motion3 deepKeptWallsMotion() {
  std::mt19937_64 rng(1061005109ull);
  return randomMotion(MotionKind::PolySam, rng);
}

// The torus screw of DoubtfulEnvelopesAreSweptAgain (campaign case 48210, tolerance 1e-3).
Motion3 resweptScrewMotion() {
  std::mt19937_64 rng(1071004735ull);
  return randomMotion(MotionKind::Screw, rng);
}

// The stress campaign's torus on a polySAM of three poses (case 604, tolerance 1e-3): slit
// mouths of about 40 points and hundreds of eps long that no filling closes (their fillings
// cross faces of the true envelope 6 to 41 eps from the loop: not a rim), so walls are kept
// there. Beside those walls lie layers of outside space a few hundredths of eps thick, over
// part of a face's angle at a vertex, which 1 to 20 of 20,000 random directions meet: the
// kept-wall vertices lie within eps of the true boundary, and the envelope's own certificate
// (Envelope::kept_wall_depth_bound, the exact inside test probing across the boundary) must
// say so. It listed 9 of them as uncertified (bound over 8 eps) while it probed just off each
// face towards its centroid only; it now probes between the face's edges too (depth_bound.hpp).
// Checked against the certified oracle as well, in a box of 50 eps about the vertex that the
// fewest directions clear (none of 20,000 at 0.98 eps): every vertex inside the swept volume
// has a point outside within T = 1.01 eps (checkAcross, whose probes include the same kind).
// The faces at the kept walls are checked too (tenth round): one of them, with an edge 23 eps
// long, has its centroid deeper than T in the swept volume by the oracle, and the envelope
// must list it (Envelope::kept_wall_faces_uncertified); every listed face the oracle confirms
// deep is counted, and the bound then exceeds eps. (The first sweep only: a re-sweep, see
// SweepOptions::refinements, leaves no such face; DoubtfulEnvelopesAreSweptAgain.)
TEST(Envelope, KeptWallsBesideThinOutsideLayersAreCertified) {
  const Mesh m = torus(0.7, 0.25, 12, 6);
  const Motion3 motion = thinLayersMotion();
  const Envelope env = sweep(m, motion, 1e-3, 0);
  EXPECT_EQ(env.resweeps, 0u);
  expectOneEmbeddedShell(env);
  EXPECT_GT(env.kept_wall_vertices, 0u) << "no wall is kept here any more: pick another case";
  EXPECT_TRUE(env.kept_wall_uncertified.empty())
      << env.kept_wall_uncertified.size() << " kept-wall vertices not certified within eps";
  const MovingBody mb(m, motion);
  const AcrossCheck listed = checkCentroidsAcross(env, mb, env.kept_wall_faces_uncertified);
  EXPECT_GE(listed.deep.size(), 1u) << "no deep face listed (" << env.kept_wall_faces_uncertified.size()
                                    << " listed): the long kept face is gone, update this comment";
  EXPECT_GT(env.kept_wall_depth_bound, env.tolerance);
  const V center(2.392175798741099, -0.09082776517538249, -0.24973823446566681);
  const V reach = V::Constant(50 * env.tolerance);
  const AcrossCheck a = checkAcrossInBox(env, mb, center - reach, center + reach);
  EXPECT_GE(a.checked, 20) << "the box no longer holds the vertices about the kept walls";
  EXPECT_GE(a.inside, 10);
  for (const int v : a.deep)
    ADD_FAILURE() << "vertex " << v << " at " << env.vertices[v].transpose()
                  << " has no outside point within T";
  std::printf("[ info     ] torus polySAM kept walls: %zu vertices, bound %.3g eps; in the box %d vertices checked, %d "
              "inside the swept volume, %zu without an outside point within T; %zu faces listed, %zu of them deep\n",
              env.kept_wall_vertices, env.kept_wall_depth_bound / env.tolerance, a.checked, a.inside, a.deep.size(),
              env.kept_wall_faces_uncertified.size(), listed.deep.size());
}

// The stress campaign's UV sphere along a screw (case 28400, tolerance 1e-3): a crack mouth
// that CGAL's search, the refill and the fan all leave open, so its crack walls were kept (21
// faces, 23 vertices, certified). The strip between two of its sharpest points (Strips in
// sweep/src/trim.cpp) passes the checks and the depth probes, and no wall is kept.
TEST(Envelope, CrackMouthIsClosedByAStrip) {
  const Mesh m = uvSphere(6, 10, 0.6);
  std::mt19937_64 motion_rng(631002405ull);  // (as the campaign draws it)
  const Motion3 motion = randomMotion(MotionKind::Screw, motion_rng);
  const Envelope env = sweep(m, motion, 1e-3);
  EXPECT_EQ(env.crack_faces_kept, 0u);
  EXPECT_EQ(env.buried_patches_kept, 0u);
  EXPECT_EQ(env.deep_fillings_taken, 0u);
  EXPECT_EQ(env.check.shells, 1);
  std::mt19937_64 rng(28400);
  CheckOptions co;
  co.expected_euler = 99;  // (as in the campaign: a random screw may close a handle)
  checkEnvelope(m, motion, env, epsOf(m), rng, "UV sphere screw, crack mouth closed by a strip", co);
}

// The stress campaign's torus along a screw (case 25530, tolerance 1e-3): a crack opens onto
// the envelope at slits, mouth loops of 43 to 47 points about 1,100 eps long, that neither
// CGAL's search nor the fan (its apex lies too far from so long a loop) fills, and that the
// refill does not take (over 32 points). Their strips pass the checks but are probed 2 to 4 eps
// deep (at a wide end of the slit) and are refused, as a strip still deep always is. Before
// the strips those loops had no filling, the rounds that failed there ran no depth check, and
// they ended by taking a filling elsewhere with a probe 4 eps deep
// (Envelope::deep_fillings_taken 1); now the depth checks of those rounds refuse it early and
// the rounds end with walls kept there instead, every kept-wall vertex and face certified.
TEST(Envelope, DeepStripIsRefused) {
  const Mesh m = torus(0.7, 0.25, 12, 6);
  std::mt19937_64 motion_rng(567003223ull);  // (as the campaign draws it)
  const Motion3 motion = randomMotion(MotionKind::Screw, motion_rng);
  const Envelope env = sweep(m, motion, 1e-3);
  EXPECT_EQ(env.deep_fillings_taken, 0u);
  EXPECT_LE(env.filling_depth_bound, epsOf(m));
  EXPECT_TRUE(env.kept_wall_uncertified.empty()) << env.kept_wall_uncertified.size() << " kept-wall vertices not certified";
  EXPECT_TRUE(env.kept_wall_faces_uncertified.empty()) << env.kept_wall_faces_uncertified.size() << " kept-wall faces not certified";
  std::mt19937_64 rng(25530);
  CheckOptions co;
  co.expected_euler = 99;  // (a screw of a torus may close a handle)
  checkEnvelope(m, motion, env, epsOf(m), rng, "torus screw, slit mouth", co);
}

// The stress campaign's torus on a polySAM of three poses (case 47764, tolerance 1e-3): walls
// are kept (87 crack faces) at mouths that no filling closes, and two of their vertices lie
// deeper than 8 eps in the swept volume, with no point outside within T of them (no probe of
// the certificate finds the outside either, so they cannot be moved onto the boundary). That
// is an error of the envelope (see README, Limits), and the envelope must report it: every
// vertex the certified oracle finds without an outside point within T, in a box of 40 eps about
// them, is listed as a kept-wall vertex not certified within eps, and the bound exceeds eps.
// (Once no wall there is kept so deep, the first expectation fails: pick another such case
// from the campaign.) The first sweep only. (Until the twenty-ninth round this was case 12979,
// whose vertex 2 eps deep is now moved onto the boundary: see
// UncertifiedKeptWallVerticesAreMovedOntoTheBoundary.)
TEST(Envelope, DeepKeptWallsAreReported) {
  const Mesh m = torus(0.7, 0.25, 12, 6);
  const Motion3 motion = deepKeptWallsMotion();
  const Envelope env = sweep(m, motion, 1e-3, 0);
  expectOneEmbeddedShell(env);
  const V center(-0.22650927503374602, -1.1549978358836488, 0.070252787088139618);
  const V reach = V::Constant(40 * env.tolerance);
  const MovingBody mb(m, motion);
  const AcrossCheck a = checkAcrossInBox(env, mb, center - reach, center + reach);
  EXPECT_FALSE(a.deep.empty()) << "no vertex here is deeper than T any more: pick another case";
  for (const int v : a.deep)
    EXPECT_TRUE(std::binary_search(env.kept_wall_uncertified.begin(), env.kept_wall_uncertified.end(), v))
        << "vertex " << v << " at " << env.vertices[v].transpose()
        << " has no outside point within T, and the envelope does not list it";
  if (!a.deep.empty()) {
    EXPECT_GT(env.kept_wall_depth_bound, env.tolerance);
  }
  std::printf("[ info     ] torus polySAM deep kept wall: %zu kept-wall vertices, %zu listed, bound %.3g eps; in the box "
              "%d vertices checked, %d inside the swept volume, %zu without an outside point within T\n",
              env.kept_wall_vertices, env.kept_wall_uncertified.size(), env.kept_wall_depth_bound / env.tolerance,
              a.checked, a.inside, a.deep.size());
}

// SweepOptions::refinements: the torus polySAM above (case 604) and a torus screw (case 48210)
// leave doubt on their first sweep (kept-wall face centroids not certified within eps). By default they are swept
// again with a finer tessellation, and the envelope returned is certified throughout and
// passes the campaign's oracle (sampled containment, every vertex on the true boundary, face
// sides). Every span is refined: the polySAM's doubtful points lie near one of its two spans,
// more than kRefineFew of them (see ReSweepsRefineOnlyTheSpansNearTheDoubt). With
// refinements = 0 the first sweep comes back as it was.
TEST(Envelope, DoubtfulEnvelopesAreSweptAgain) {
  const Mesh m = torus(0.7, 0.25, 12, 6);
  const struct {
    Motion3 motion;
    double rel;
    const char* name;
    std::uint64_t seed;
    std::size_t spans_refined;
  } cases[] = {{thinLayersMotion(), 1e-3, "torus polySAM, thin outside layers", 604, 2},
               {resweptScrewMotion(), 1e-3, "torus screw, kept-wall faces", 48210, 1}};
  for (const auto& c : cases) {
    const Envelope first = sweep(m, c.motion, c.rel, 0);
    EXPECT_EQ(first.resweeps, 0u) << c.name;
    EXPECT_EQ(first.spans_refined, 0u) << c.name;
    EXPECT_DOUBLE_EQ(first.tessellation_tolerance, 0.5 * first.tolerance) << c.name;
    EXPECT_FALSE(first.kept_wall_uncertified.empty() && first.kept_wall_faces_uncertified.empty())
        << c.name << ": the first sweep leaves no doubt any more: pick another case";
    const Envelope env = sweep(m, c.motion, c.rel);
    EXPECT_GE(env.resweeps, 1u) << c.name;
    EXPECT_LT(env.tessellation_tolerance, first.tessellation_tolerance) << c.name;
    EXPECT_EQ(env.spans_refined, c.spans_refined) << c.name << " (of " << env.spans << " spans)";
    EXPECT_TRUE(env.kept_wall_uncertified.empty()) << c.name << ": " << env.kept_wall_uncertified.size();
    EXPECT_TRUE(env.kept_wall_faces_uncertified.empty()) << c.name << ": " << env.kept_wall_faces_uncertified.size();
    EXPECT_TRUE(env.cavity_uncertified.empty()) << c.name;
    EXPECT_TRUE(env.cavity_faces_uncertified.empty()) << c.name;
    EXPECT_LE(env.kept_wall_depth_bound, env.tolerance) << c.name;
    std::mt19937_64 rng(c.seed);
    CheckOptions co;
    co.expected_euler = 99;  // (a polySAM of a torus may close its handle)
    checkEnvelope(m, c.motion, env, epsOf(m, c.rel), rng, c.name, co);
    std::printf("[ info     ] %s: first sweep %zu + %zu uncertified; %zu re-sweep(s), eps_t = eps / %.0f on %zu of %zu "
                "spans, %zu kept-wall vertices\n",
                c.name, first.kept_wall_uncertified.size(), first.kept_wall_faces_uncertified.size(), env.resweeps,
                env.tolerance / env.tessellation_tolerance, env.spans_refined, env.spans, env.kept_wall_vertices);
  }
}

// SweepOptions::cancel. A flag set before the call stops it at once (no progress reported);
// set from the progress callback at the first report of each stage (on one thread and on two),
// it stops the sweep before the next report, in that stage. The report that opens the output
// stage is followed by parallel loops only (probes, mouth fillings) until the stage's closing
// report, so there the sweep must stop between two work items, as the message says. (Without
// the checks in the loops it stops at the closing report, and the message says so.)
TEST(Envelope, CancelStopsTheSweepAtItsNextCheck) {
  EXPECT_STREQ(steady::to_string(ErrorCode::Cancelled), "cancelled");
  const Body body = makeBody(bundledBracket());
  const Motion3 motion = single(Affine3(), bracketQuarterTurn());
  {
    std::atomic<bool> flag{true};
    SweepOptions o;
    o.cancel = &flag;
    int reports = 0;
    o.progress = [&](const steady::sweep::SweepProgress&) { ++reports; };
    EXPECT_TRUE(throwsError([&] { sweptEnvelope(body, motion, o); }, ErrorCode::Cancelled, "cancelled .*before it began"));
    EXPECT_TRUE(throwsError([&] { sweptEnvelope(body, motion.span(0), o); }, ErrorCode::Cancelled, "before it began"));
    EXPECT_EQ(reports, 0);
    // Nothing is left behind: with the flag still set, work outside a sweep (inspectMesh's
    // parallel check) is not cancelled. (Until stop 71 the thread kept the flag of a sweep that
    // threw before it began, and later calls on it read the flag, long gone by then: 18 tests
    // of this suite failed at random with "cancelled" when the tests' order changed.)
    const Mesh cube = box(V(0, 0, 0), V(1, 1, 1));
    EXPECT_NO_THROW(inspectMesh(cube.v, cube.f, true));
  }
  for (const int threads : {1, 2})
    for (const std::string stage : {"cycle", "intersect", "label", "output"}) {
      const std::string what = stage + " on " + std::to_string(threads) + " thread(s)";
      std::atomic<bool> flag{false};
      SweepOptions o;
      o.threads = threads;
      o.cancel = &flag;
      std::vector<std::string> after;  // (the reports that came after the flag was set)
      o.progress = [&](const steady::sweep::SweepProgress& p) {
        if (flag) after.push_back(std::string(p.stage) + " " + std::to_string(p.fraction));
        if (p.stage == stage) flag = true;
      };
      const std::string where = stage == "output" ? "output stage, between two work items" : stage + " stage";
      EXPECT_TRUE(throwsError([&] { sweptEnvelope(body, motion, o); }, ErrorCode::Cancelled, "cancelled .*in its " + where))
          << what;
      EXPECT_TRUE(after.empty()) << what << ": went on to " << after.front();
    }
}

// A cancellation during a re-sweep is not a re-sweep that failed (which ends the series with
// the envelopes before it): the call throws, it does not return the first sweep's envelope. The
// torus screw of DoubtfulEnvelopesAreSweptAgain, cancelled as its re-sweep starts its cycle.
TEST(Envelope, CancelDuringAReSweepThrows) {
  const Mesh m = torus(0.7, 0.25, 12, 6);
  const Motion3 motion = resweptScrewMotion();
  std::atomic<bool> flag{false};
  SweepOptions o;
  o.relative_tolerance = 1e-3;
  o.cancel = &flag;
  int cycles = 0;
  o.progress = [&](const steady::sweep::SweepProgress& p) {
    if (std::string(p.stage) == "cycle" && ++cycles == 2) flag = true;
  };
  EXPECT_TRUE(throwsError([&] { sweptEnvelope(makeBody(m), motion, o); }, ErrorCode::Cancelled, "cancelled"));
  EXPECT_EQ(cycles, 2) << "the first sweep left no doubt: no re-sweep to cancel, pick another case";
}

// Along a motion of many spans a re-sweep refines only the spans near the points the sweep
// before it listed (detail::spansNear, kRefineFew). The torus polySAM of
// DoubtfulEnvelopesAreSweptAgain, whose doubt lies near its second span, continued by six
// translations of about one torus diameter each along the torus's axis: 8 spans, of which the re-sweep refines
// at most 2 (it refines 1), and the envelope returned is certified throughout and passes the
// campaign's oracle. Refining every span fails the count (8 refined, though the envelope then
// passes too: 17,894 triangles against 14,826); refining none leaves the doubt.
TEST(Envelope, ReSweepsRefineOnlyTheSpansNearTheDoubt) {
  const Mesh m = torus(0.7, 0.25, 12, 6);
  std::vector<Affine3> poses;
  const Motion3 head = thinLayersMotion();
  for (std::size_t i = 0; i < head.spanCount(); ++i) poses.push_back(head.span(i).start());
  const auto& tail = head.span(head.spanCount() - 1);
  const Affine3 last = tail.relative() * tail.start();
  poses.push_back(last);
  // (along the torus's axis, so that the translations leave no cavity)
  const V axis = (last.linear() * V(0, 0, 1)).normalized();
  for (int k = 1; k <= 6; ++k) poses.push_back(Affine3::translation(2.0 * k * axis) * last);
  const Motion3 motion = Motion3::polySam(poses);
  ASSERT_EQ(motion.spanCount(), 8u);
  const Envelope first = sweep(m, motion, 1e-3, 0);
  EXPECT_FALSE(first.kept_wall_uncertified.empty() && first.kept_wall_faces_uncertified.empty())
      << "the first sweep leaves no doubt any more: pick another case";
  const Envelope env = sweep(m, motion, 1e-3);
  EXPECT_GE(env.resweeps, 1u);
  EXPECT_GE(env.spans_refined, 1u);
  EXPECT_LE(env.spans_refined, 2u);
  EXPECT_TRUE(env.kept_wall_uncertified.empty()) << env.kept_wall_uncertified.size();
  EXPECT_TRUE(env.kept_wall_faces_uncertified.empty()) << env.kept_wall_faces_uncertified.size();
  EXPECT_TRUE(env.cavity_uncertified.empty());
  EXPECT_TRUE(env.cavity_faces_uncertified.empty());
  std::mt19937_64 rng(604);
  CheckOptions co;
  co.expected_euler = 99;  // (a polySAM of a torus may close its handle)
  checkEnvelope(m, motion, env, epsOf(m, 1e-3), rng, "torus polySAM of 8 spans", co);
  std::printf("[ info     ] torus polySAM of 8 spans: first sweep %zu + %zu uncertified; %zu re-sweep(s), %zu spans "
              "refined; %zu triangles against %zu\n",
              first.kept_wall_uncertified.size(), first.kept_wall_faces_uncertified.size(), env.resweeps,
              env.spans_refined, env.triangles.size(), first.triangles.size());
}

// Re-sweeps stop certifying an envelope past detail::kDoubtCap points deeper than eps, and
// finish the certificates of the envelope they return (doubt.hpp). With the cap lowered to 1, so
// that it matters on these small cases:
// - the torus screw of DoubtfulEnvelopesAreSweptAgain (first sweep: 9 face centroids
//   uncertified, then a clean re-sweep) returns the same envelope as with the normal cap;
// - the thin-layers torus with max_steps 23, which lets the first sweep's grids through (they
//   need 20 steps) but not the re-sweep's (27), returns its first sweep (2 face centroids
//   uncertified, so the cap cuts its list), whose certificates must be complete: the same
//   lists and bounds as that sweep measured in full (refinements = 0).
TEST(Envelope, CertificatesGivenUpAreFinishedOnTheEnvelopeReturned) {
  const Mesh m = torus(0.7, 0.25, 12, 6);
  const auto expectSame = [](const Envelope& a, const Envelope& b, const char* name) {
    expectSameEnvelope(b, a, name);
    EXPECT_EQ(a.resweeps, b.resweeps) << name;
    EXPECT_EQ(a.tessellation_tolerance, b.tessellation_tolerance) << name;
    EXPECT_EQ(a.kept_wall_vertices, b.kept_wall_vertices) << name;
    EXPECT_EQ(a.kept_wall_uncertified, b.kept_wall_uncertified) << name;
    EXPECT_EQ(a.kept_wall_faces_uncertified, b.kept_wall_faces_uncertified) << name;
    EXPECT_EQ(a.kept_wall_depth_bound, b.kept_wall_depth_bound) << name;
    EXPECT_EQ(a.cavity_vertices, b.cavity_vertices) << name;
    EXPECT_EQ(a.cavity_uncertified, b.cavity_uncertified) << name;
    EXPECT_EQ(a.cavity_faces_uncertified, b.cavity_faces_uncertified) << name;
    EXPECT_EQ(a.cavity_depth_bound, b.cavity_depth_bound) << name;
  };
  {
    const Motion3 motion = resweptScrewMotion();
    SweepOptions o;
    o.relative_tolerance = 1e-3;
    const Envelope normal = sweptEnvelope(makeBody(m), motion, o);
    const Envelope capped = steady::sweep::detail::sweptEnvelope(makeBody(m), motion, o, 1);
    EXPECT_EQ(normal.resweeps, 1u) << "the first sweep leaves no doubt any more, or the re-sweep does: pick another case";
    EXPECT_EQ(normal.kept_wall_uncertified.size() + normal.kept_wall_faces_uncertified.size(), 0u);
    expectSame(capped, normal, "torus screw, cap 1");
  }
  {
    const Motion3 motion = thinLayersMotion();
    SweepOptions o;
    o.relative_tolerance = 1e-3;
    o.max_steps = 23;
    SweepOptions finer = o;
    finer.relative_tolerance = 5e-4;  // (eps_t = 1e-3 / 4, as the re-sweep's)
    finer.refinements = 0;
    EXPECT_TRUE(throwsError([&] { sweptEnvelope(makeBody(m), motion, finer); }, ErrorCode::InvalidArgument, "max_steps"))
        << "the re-sweep's grids fit in 23 steps now: pick another max_steps";
    SweepOptions full = o;
    full.refinements = 0;
    Envelope first = sweptEnvelope(makeBody(m), motion, full);
    EXPECT_GE(first.kept_wall_uncertified.size() + first.kept_wall_faces_uncertified.size(), 2u)
        << "the first sweep leaves less doubt than the cap of 1 can cut: pick another case";
    o.refinements = 1;
    const Envelope capped = steady::sweep::detail::sweptEnvelope(makeBody(m), motion, o, 1);
    EXPECT_EQ(capped.resweeps, 1u);
    first.resweeps = 1;  // (the re-sweep was tried)
    expectSame(capped, first, "thin layers, cap 1, the re-sweep throws");
    o.threads = 1;  // (where the measuring stops depends on the threads; what is returned must not)
    expectSame(steady::sweep::detail::sweptEnvelope(makeBody(m), motion, o, 1), first,
               "thin layers, cap 1, the re-sweep throws, one thread");
  }
  EXPECT_TRUE(throwsError([&] { steady::sweep::detail::sweptEnvelope(makeBody(m), thinLayersMotion(), {}, 0); },
                          ErrorCode::InvalidArgument, "doubt_cap"));
}

// An envelope without doubt is not swept again (and passes its check); a negative refinements
// is refused.
TEST(Envelope, CertifiedEnvelopeIsNotSweptAgain) {
  const Mesh m = box(V(0, 0, 0), V(1, 1, 1));
  const Motion3 motion = single(Affine3(), Affine3::translation(V(2, 0.5, 0.25)) * Affine3::rotation(V(0, 0, 1), 0.5));
  const Envelope env = sweep(m, motion);
  EXPECT_EQ(env.resweeps, 0u);
  EXPECT_DOUBLE_EQ(env.tessellation_tolerance, 0.5 * env.tolerance);
  EXPECT_GE(env.timings.total, env.timings.cycle + env.timings.intersect + env.timings.label + env.timings.output);
  EXPECT_TRUE(passedCheck(env));
  Envelope open = env;
  open.check.closed = false;
  EXPECT_FALSE(passedCheck(open));
  SweepOptions bad;
  bad.refinements = -1;
  EXPECT_TRUE(throwsError([&] { sweptEnvelope(makeBody(m), motion, bad); }, ErrorCode::InvalidArgument, "refinements"));
}

// The stress campaign's CGAL sphere on a polySAM of three spans (case 2959, tolerance 2e-3): a
// buried pocket whose mouth closes, next to a crack mouth (a slit of 15 points) that no filling
// closes. The pocket touched that slit at a point only, yet it was kept with the crack, and its
// walls left envelope vertices up to 14 eps inside the body posed later. Only the patches with
// an edge on a mouth that fails are kept now (in the first rounds): around the former pocket
// every envelope vertex is within T = 1.01 eps of the true boundary, and no buried patch is kept.
// Since a loop with no filling takes its rim from all its fillings' crossings (see
// MouthWhoseFillingsAllCrossItsRimCloses), the slit closes as well, and no crack wall is kept:
// this case no longer exercises the rule for patches touching a failed mouth at a point (which
// PatchesTouchingAFailedMouthAtAPointAreLeftOutOnAScrew does), but still checks the vertices
// about both mouths.
TEST(Envelope, PocketTouchingAFailedMouthAtAPointIsLeftOut) {
#ifndef STEADY_CGAL_MESHES
  GTEST_SKIP() << "CGAL's sample meshes (Debian libcgal-demo) were not found when the build was configured";
#else
  const Mesh m = cgalSampleMesh("sphere.off");
  Eigen::Matrix<double, 3, 4> k0, k1, k2, k3;
  k0 << -0.65754003591899091, -0.73565034332209478, 0.16266429704682026, -0.16036400332688805,  //
      0.75340361307075321, -0.64061175436610573, 0.14832254036361098, 0.24793109766535337,       //
      -0.0049088670370028287, 0.22007987763097336, 0.97546950259162313, -0.49463158272754981;
  k1 << -0.65754003591899091, -0.73565034332209478, 0.16266429704682026, -1.2008259909744097,  //
      0.75340361307075321, -0.64061175436610573, 0.14832254036361098, -0.047991257131619669,    //
      -0.0049088670370028287, 0.22007987763097336, 0.97546950259162313, -1.6843190669646426;
  k2 << -1.2739592585877699, -0.94827471071750657, 0.47931278405096367, -1.9197484906148585,  //
      0.76268016752078327, -0.18931182041825642, 0.11077384240443881, 0.69170568467935922,     //
      1.16945262305499, 1.1675081346816325, 0.25001459604138138, 1.8526897734306131;
  k3 << -1.2739592585877699, -0.94827471071750657, 0.47931278405096367, -2.3811792464961923,  //
      0.76268016752078327, -0.18931182041825642, 0.11077384240443881, 0.28453060229585153,     //
      1.16945262305499, 1.1675081346816325, 0.25001459604138138, 1.7395563583683442;
  const Motion3 motion = Motion3::polySam(std::vector<Affine3>{Affine3::fromMatrix(k0), Affine3::fromMatrix(k1),
                                                               Affine3::fromMatrix(k2), Affine3::fromMatrix(k3)});
  const Envelope env = sweep(m, motion, 2e-3);
  EXPECT_EQ(env.buried_patches_kept, 0u);
  EXPECT_EQ(env.crack_faces_kept, 0u);
  expectCrackMouthClosed(env, m, motion, V(-1.9488137768458405, 0.37802826517829513, 1.3893085382497807),
                         "CGAL sphere polySAM pocket");
#endif
}

// The stress campaign's CGAL sphere on a screw span (case 2820, tolerance 1e-3): mouths that no
// filling closes, with buried patches and crack regions that touch them at a point only. Kept
// with the walls at such a mouth (the rule before PocketTouchingAFailedMouthAtAPointIsLeftOut),
// they left 7 envelope vertices that the envelope could not certify within eps (bound 1.5 eps),
// with no point outside the swept volume within T = 1.01 eps by the oracle (measured: the
// campaign with that rule restored fails 9 cases of 3,600 instead of 1, this one and 1110, 2239,
// 2284, 2509, 2844, 3320 and 3394 besides 604). Only the patches with
// an edge on a failed mouth are kept now: every vertex about the former deepest one is within T
// of the true boundary, and every kept-wall vertex is certified within eps.
TEST(Envelope, PatchesTouchingAFailedMouthAtAPointAreLeftOutOnAScrew) {
#ifndef STEADY_CGAL_MESHES
  GTEST_SKIP() << "CGAL's sample meshes (Debian libcgal-demo) were not found when the build was configured";
#else
  const Mesh m = cgalSampleMesh("sphere.off");
  Eigen::Matrix<double, 3, 4> b, c;
  b << 0.68807897172965504, -0.20378824367721066, 0.69643210753268592, -0.32800463112892397,  //
      0.53625460730754959, 0.78938506541122622, -0.2988347614437451, -0.21458374556233728,     //
      -0.48885409357484833, 0.57908684171259839, 0.65244164869392085, 0.012562168653292738;
  c << 0.049589483894708131, -0.34472202286228676, 0.93739405270184539, -0.30524890483617806,  //
      0.99592404476964569, 0.087864649292176356, -0.020374014195337686, 0.3567870347829924,     //
      -0.075340428301977666, 0.93458361335864215, 0.34767411394117137, 0.2981535626758417;
  const Motion3 motion = single(Affine3::fromMatrix(b), Affine3::fromMatrix(c));
  const Envelope env = sweep(m, motion, 1e-3);
  EXPECT_TRUE(env.kept_wall_uncertified.empty())
      << env.kept_wall_uncertified.size() << " kept-wall vertices not certified";
  expectCrackMouthClosed(env, m, motion, V(-0.13660465237222508, 0.33959445554237538, -0.030016727134602822),
                         "CGAL sphere screw, patches touching failed mouths");
#endif
}

// Kept-wall vertices that the certificate lists, moved onto the true boundary
// (detail::settleVertices), on the first sweep (no re-sweep). Every kept-wall vertex is then
// certified, the oracle agrees about the vertices in a box about them, and the envelope passes
// every check of the campaign (the posed bodies inside it within eps, every vertex on the true
// boundary, closed and embedded). Two campaign cases:
// - the torus on a polySAM of four poses (case 12979, tolerance 2e-3): walls kept (293 crack
//   faces) at mouths that no filling closes, one of whose vertices lay about 2 eps deep in the
//   swept volume, with no point outside within T (DeepKeptWallsAreReported until the
//   twenty-ninth round);
// - CGAL's sphere on a screw span (case 48405, tolerance 2e-3): 64 buried patches kept, 18 of
//   whose vertices lay 1.0 to 1.25 eps inside (bound 1.25 eps; the oracle found no outside
//   point within T for them), which only a re-sweep at eps/4 cleared before. (10 were moved
//   until stop 61, 6 since: the span ends at its key pose as given and points on edges are
//   placed as a + r (b - a), which moved the envelope by rounding.)
void expectKeptWallVerticesMoved(const Mesh& m, const Motion3& motion, double rel, const V& center,
                                 std::size_t at_least, const char* name, std::uint64_t seed) {
  const Envelope env = sweep(m, motion, rel, 0);
  EXPECT_GT(env.buried_patches_kept + env.crack_faces_kept, 0u) << name << ": no wall is kept here any more";
  EXPECT_GE(env.uncertified_vertices_moved, at_least) << name;
  EXPECT_TRUE(env.kept_wall_uncertified.empty())
      << name << ": " << env.kept_wall_uncertified.size() << " kept-wall vertices not certified within eps";
  EXPECT_TRUE(env.kept_wall_faces_uncertified.empty()) << name;
  EXPECT_LE(env.kept_wall_depth_bound, env.tolerance) << name;
  const MovingBody mb(m, motion);
  const V reach = V::Constant(30 * env.tolerance);
  const AcrossCheck a = checkAcrossInBox(env, mb, center - reach, center + reach);
  EXPECT_GE(a.checked, 20) << name << ": the box no longer holds the vertices that were moved";
  EXPECT_TRUE(a.deep.empty()) << name << ": " << a.deep.size()
                              << " vertices inside the swept volume with no outside point within T";
  std::mt19937_64 rng(seed);
  CheckOptions co;
  co.expected_euler = 99;  // (the kept walls may close handles: unchecked, as in the campaign)
  checkEnvelope(m, motion, env, epsOf(m, rel), rng, name, co);
  std::printf("[ info     ] %s: %zu kept-wall vertices, %zu moved onto the boundary; in the box %d vertices checked, "
              "%d inside the swept volume\n",
              name, env.kept_wall_vertices, env.uncertified_vertices_moved, a.checked, a.inside);
}

TEST(Envelope, UncertifiedKeptWallVerticesAreMovedOntoTheBoundary) {
  expectKeptWallVerticesMoved(torus(0.7, 0.25, 12, 6), movedKeptWallsMotion(), 2e-3,
                              V(-0.3464770621714698, -0.33437785487241933, 0.2989461426866816), 1,
                              "torus polySAM, kept wall 2 eps deep", 12979);
#ifndef STEADY_CGAL_MESHES
  GTEST_SKIP() << "CGAL's sample meshes (Debian libcgal-demo) were not found when the build was configured";
#else
  Eigen::Matrix<double, 3, 4> b, c;
  b << -0.92698568629219213, 0.37396703250207031, -0.02908944844766298, -0.40289131759129337,  //
      0.23488429881167108, 0.51826263716430154, -0.82233399850137123, -0.31333754563985561,     //
      -0.29244983087897886, -0.76912450066364368, -0.56826103059928146, 0.4836395694463167;
  c << -0.4346175273306716, 0.10052205277476711, 0.89498766574904254, 0.21370479706467263,  //
      -0.13501341746459219, 0.97524920469692999, -0.17510101610937956, 0.040951683510945913,  //
      -0.89043752281757793, -0.19693731399598308, -0.41028857200090629, 0.93911661917451283;
  expectKeptWallVerticesMoved(cgalSampleMesh("sphere.off"), single(Affine3::fromMatrix(b), Affine3::fromMatrix(c)),
                              2e-3, V(-0.055, -0.513, 0.571), 5, "CGAL sphere screw, 18 kept-wall vertices", 48405);
#endif
}

// The stress campaign's CGAL sphere on a screw span (case 8985, tolerance 2e-3): neighbouring
// mouths whose fillings were each good alone but not together: two loops of 5 and 6 points whose
// fillings crossed, and two of 6 points, with points less than eps apart, whose fillings took
// the same diagonal. The refill chose the same fillings again, the fans' apexes lay too far from
// the long loops, and the crack walls kept at one of them left two envelope vertices 1.0 to
// 1.05 eps inside the swept volume (listed as uncertified, bound 1.25 eps). The loop of the
// higher index is now refilled avoiding the other's filling faces and edges: every mouth
// closes, no wall is kept, and every vertex about the former deepest one is within T of the
// true boundary.
TEST(Envelope, NeighbouringMouthsWhoseFillingsCollideAreRefilledApart) {
#ifndef STEADY_CGAL_MESHES
  GTEST_SKIP() << "CGAL's sample meshes (Debian libcgal-demo) were not found when the build was configured";
#else
  Eigen::Matrix<double, 3, 4> b, c;
  b << 0.64429856222512405, -0.76340898298496618, 0.04567370592033565, -0.12464383269582713,  //
      -0.081008851371201895, -0.12751148182681088, -0.98852333710532569, -0.30337184259706262,  //
      0.76047151735890561, 0.63320419036847064, -0.14399834924627886, -0.13348981454818465;
  c << 0.8174151253589812, -0.25597317377492179, -0.51605256238289776, 0.19635418087254364,  //
      -0.26202801241607554, 0.63258301763677804, -0.72882099757541885, -0.55342949224031868,  //
      0.5130047110345497, 0.73096953432078249, 0.45001078470545208, -0.55846258194112097;
  expectSphereSpanKeepsNoWall(b, c, 2e-3, V(0.23692385047200498, -0.16378601311916058, -0.48544631182830555),
                              "CGAL sphere screw, neighbouring mouths refilled apart");
#endif
}

// The stress campaign's CGAL sphere on a shear-and-scale span (case 15738, tolerance 1e-3):
// neighbouring mouths of 4 and 5 points that share two points. Filled one by one they failed
// (their fillings crossed each other, the smaller loop's refill found no triangulation and its
// fan crossed the other's filling), and the buried patches kept there left two envelope
// vertices about 28 eps away deeper than eps (listed, bound 4 eps). A bad loop is now joined
// with the loops it shares points with, cut back at those points into simple loops with the
// edges paired either way, and refilled (Joined mouths in trim.cpp), and the refill leaves out
// triangles that cross each other. Without either of the two, the walls are kept again.
TEST(Envelope, MouthsSharingPointsAreFilledAsOne) {
#ifndef STEADY_CGAL_MESHES
  GTEST_SKIP() << "CGAL's sample meshes (Debian libcgal-demo) were not found when the build was configured";
#else
  Eigen::Matrix<double, 3, 4> b, c;
  b << -0.23883557743889741, 0.0066910213363851612, -0.9710369700391972, 0.018306420362370734,  //
      0.84613432905055519, 0.49208214068402334, -0.20472387262358094, -0.19308839038326664,      //
      0.47646013910042401, -0.8705230594609803, -0.12318822506676258, -0.42354656744912622;
  c << -0.54756658035724637, 0.094077354228005422, -0.46636577363448672, 1.0618815941837692,  //
      0.59940068284058889, 0.87611521490138267, -0.29211994801725355, -0.13515676579236149,    //
      -0.035235914916156436, -0.13870513573353144, -0.87878368564608211, 0.38834429473510679;
  expectSphereSpanKeepsNoWall(b, c, 1e-3, V(0.17017710803806657, -0.4363547288797397, -0.53331828375602663),
                              "CGAL sphere shear-and-scale, mouths sharing points filled as one");
#endif
}

// The stress campaign's CGAL sphere on a general affine span (case 482, tolerance 1e-3): a
// buried patch of 18 faces, 56 eps long, had an edge on a mouth that no filling closed, 14 eps
// from its far end, and was kept whole; that end lay 1.02 eps inside the body posed at tau 0.213
// (the only envelope vertex beyond T = 1.01 eps). Buried patches were then kept by pieces, as
// crack regions are (cells of kCrackCell tessellation tolerances), and every envelope vertex
// around that end came within T of the true boundary. Since a bad loop is joined with the loops
// it shares points with (Joined mouths in trim.cpp), that mouth closes and no patch is kept; the
// pieces are still exercised by CrackRegionsAreKeptByPiecesNearTheirFailedMouths (the same
// numbering for both) and DeepKeptWallsAreReported.
TEST(Envelope, BuriedPatchEndThatWasDeepLiesWithinTolerance) {
#ifndef STEADY_CGAL_MESHES
  GTEST_SKIP() << "CGAL's sample meshes (Debian libcgal-demo) were not found when the build was configured";
#else
  const Mesh m = cgalSampleMesh("sphere.off");
  Eigen::Matrix<double, 3, 4> b, c;
  b << -0.66328833732556092, -0.74652413601920109, -0.052443263711160037, -0.16875185315539787,  //
      0.38315698160623957, -0.39895961371680533, 0.83307980054094033, 0.15380470190145168,        //
      -0.6428369225661269, 0.53247811313116222, 0.55066119349559073, -0.15086913713438854;
  c << -0.36493366081466272, -0.58937631331535112, 0.19260945014727535, -0.60489558942064559,  //
      1.0058730917008065, -1.4735293890785783, 1.4267708802232537, 1.6347371980089456,          //
      -0.4186911598348747, 0.61375825845840815, -0.022383449772908966, -1.4927240084171807;
  const Motion3 motion = Motion3::polySam(std::vector<Affine3>{Affine3::fromMatrix(b), Affine3::fromMatrix(c)});
  const Envelope env = sweep(m, motion, 1e-3);
  EXPECT_EQ(env.buried_patches_kept, 0u);
  expectCrackMouthClosed(env, m, motion, V(-0.28778706138516252, 0.076471311501048106, -0.60388097557305231),
                         "CGAL sphere affine pocket");
#endif
}

// The four poses of a campaign case's polySAM (the stress harness's keyframes, at equal times).
Motion3 polySamOf(const std::vector<std::array<double, 12>>& rows) {
  std::vector<Affine3> poses;
  for (const auto& r : rows) poses.push_back(Affine3::fromMatrix(Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(r.data())));
  return Motion3::polySam(poses);
}

// The stress campaign's torus on a polySAM of four poses (case 22969, tolerance 2e-3): a mouth
// filling 260 eps across, flat where the true boundary is curved, cut into the swept volume,
// and the body posed at tau 0.597 of the second span stuck out of the envelope by 2.61 eps,
// with no wall kept and nothing reported. Fillings are now probed away from their loops with the
// exact inside test (Deep fillings in trim.cpp), and a loop whose filling lies farther than
// 1.5 eps from the true boundary is not filled. Here the body posed about that time must lie
// inside the envelope or within eps of it, vertices and face points alike.
TEST(Envelope, FillingsThatCutIntoTheSweptVolumeAreRejected) {
  const Mesh m = torus(0.7, 0.25, 12, 6);
  const Motion3 motion = polySamOf({
      {0.8192651677636158, 0.47197017477705755, -0.32565125365975217, -0.43013597946053594, -0.52361769502525346,
       0.84725285360338154, -0.089370641249615829, 0.11929598202713299, 0.23372867677222481, 0.24373501221991203,
       0.94125668628300552, 0.3850085767905127},
      {1.2309642774921652, 0.41640074852003783, -0.17299667907134902, -1.8246451420062488, -0.49611878229683615,
       0.35114262116515732, 0.11667497287573048, 0.32623491357344914, 0.089678334931730497, -0.0090615296546373569,
       0.49175628269443933, 0.26569774997463702},
      {1.2309642774921652, 0.41640074852003783, -0.17299667907134902, -0.18112245608332045, -0.49611878229683615,
       0.35114262116515732, 0.11667497287573048, 0.75079108023675922, 0.089678334931730497, -0.0090615296546373569,
       0.49175628269443933, 1.6855264514669472},
      {1.2309642774921652, 0.41640074852003783, -0.17299667907134902, -0.87092635560452636, -0.49611878229683615,
       0.35114262116515732, 0.11667497287573048, 2.161185296778513, 0.089678334931730497, -0.0090615296546373569,
       0.49175628269443933, 2.1441773273919122},
  });
  const Envelope env = sweep(m, motion, 2e-3);
  expectOneEmbeddedShell(env);
  const MovingBody mb(m, motion);
  int checked = 0;
  double worst = 0;
  for (double tau = 0.55; tau <= 0.65; tau += 0.005) {
    const std::vector<V> w = mb.posed(1, tau);
    std::vector<V> points = w;
    for (const auto& f : m.f)
      for (int i = 1; i <= 4; ++i)
        for (int j = 1; i + j <= 5; ++j)
          points.push_back(w[f[0]] + (i / 6.0) * (w[f[1]] - w[f[0]]) + (j / 6.0) * (w[f[2]] - w[f[0]]));
    for (const V& x : points) {
      ++checked;
      if (windingNumber(env.vertices, env.triangles, x) >= 0.5) continue;
      worst = std::max(worst, meshDistance(env.vertices, env.triangles, x) / env.tolerance);
    }
  }
  EXPECT_LE(worst, 1.0) << "the posed body sticks out of the envelope (of " << checked << " points)";
  std::printf("[ info     ] torus polySAM wide filling: %d posed points, worst %.3f eps outside; %zu mouths filled, "
              "kept %zu buried patches and %zu crack faces\n",
              checked, worst, env.pocket_mouths_filled, env.buried_patches_kept, env.crack_faces_kept);
}

// The envelope of m along the motion (relative tolerance rel), one embedded shell, and the
// check of its face interiors (checkFaceSides, every face, seeded). A face that fails it must
// be reported by the envelope: a filling taken with a probe deeper than eps
// (Envelope::deep_fillings_taken), whose bound covers the failure.
SideCheck sweepAndCheckFaceSides(const Mesh& m, const Motion3& motion, double rel, std::uint64_t seed, Envelope& env,
                                 int refinements = -1) {
  env = sweep(m, motion, rel, refinements);
  expectOneEmbeddedShell(env);
  std::mt19937_64 rng(seed);
  ::testing::TestPartResultArray failures;
  SideCheck sides;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD,
                                                         &failures);
    sides = checkFaceSides(env, MovingBody(m, motion), SweptVolume(makeBody(m), motion), env.triangles.size(), rng);
  }
  // (a face off the true boundary must be reported: at a deep filling taken, within its bound, or
  // listed as a face whose centroid is not certified)
  std::vector<int> unlisted;
  for (const int f : sides.off_faces)
    if (!std::binary_search(env.kept_wall_faces_uncertified.begin(), env.kept_wall_faces_uncertified.end(), f) &&
        !std::binary_search(env.cavity_faces_uncertified.begin(), env.cavity_faces_uncertified.end(), f))
      unlisted.push_back(f);
  if (sides.failed > 0 && !(unlisted.empty() && sides.failed == static_cast<int>(sides.off_faces.size()))) {
    EXPECT_GT(env.deep_fillings_taken, 0u) << sides.failed << " faces off the true boundary, not reported; the first: "
                                           << failures.GetTestPartResult(0).message();
    EXPECT_GE(env.filling_depth_bound, sides.worst * env.tolerance) << "the faces lie farther off than reported";
  }
  return sides;
}

// The stress campaign's star prism on a polySAM of four poses (case 224, tolerance 1e-3): before
// the filling probes, mouth fillings lay across a concave stretch of the swept volume's
// boundary, up to more than 8 eps outside it, every vertex on the boundary; the vertex checks
// passed. The check of face interiors (checkFaceSides) sees it: without the probes' refusal (a
// temporary switch) 31 faces fail, their centroids at least 1.2 to 2.7 eps outside the swept
// volume, and nothing is reported. Now the fillings are refused in the first mouth rounds and
// the walls at those mouths kept (3 of their vertices listed as uncertified, which the
// campaign's across check confirms); one filling, still deep when the refusals stop, is taken
// and reported (bound 8 eps), and the 4 faces that fail the check lie within that bound.
TEST(Envelope, FillingsThatBulgeOutOfTheSweptVolumeAreRefusedOrReported) {
  const Mesh m = starPrismOf({{{0.9876496841295046, 0.07722852597965268},
                               {0.30548657424341935, 0.2073294056036241},
                               {0.390462752955827, 0.5814630351681107},
                               {0.05960259439027066, 0.4305519219359564},
                               {-0.422764802142331, 0.6625102121624774},
                               {-0.302035187755121, 0.14526900742770507},
                               {-0.8861320269957002, 0.09701949009864451},
                               {-0.2668063320010029, -0.1245497328876179},
                               {-0.4132628476590741, -0.7408086587525701},
                               {0.05426346332229743, -0.4850199494483198},
                               {0.4074467675850175, -0.6709140644374049},
                               {0.35066241387930647, -0.263139594188123}}},
                             0.35744096812051745);
  const Motion3 motion = polySamOf({
      {0.75106171360725638, -0.53623680291756215, -0.38517060317485696, -0.34637589477570341, 0.36437407025014612,
       -0.14984072845246138, 0.91911875893497974, -0.26963627833704518, -0.55057954855104552, -0.8306610905138071,
       0.08285115221733233, -0.40154232213682672},
      {0.12277027268666729, 0.98764064666289486, -0.097434148037227442, 1.6529177679387761, -0.67055748918214075,
       0.15492779294145737, 0.72549985022467944, 0.99203431806931996, 0.73162839874227437, -0.023734616777775969,
       0.68129035962666296, -0.84453976904002515},
      {0.12277027268666729, 0.98764064666289486, -0.097434148037227442, 0.15157985430205678, -0.67055748918214075,
       0.15492779294145737, 0.72549985022467944, 0.19125210845303398, 0.73162839874227437, -0.023734616777775969,
       0.68129035962666296, -0.72809445072715984},
      {0.9479198150307595, 0.028145208946887545, -0.31726309505737826, -1.9317091214068414, 0.30283599624279445,
       0.22897508497627014, 0.92512743437849954, -0.75884337828960424, 0.098683249093678399, -0.97302531193872155,
       0.20852663780646635, 1.6126985708376242},
  });
  Envelope env;
  const SideCheck sides = sweepAndCheckFaceSides(m, motion, 1e-3, 224, env);
  EXPECT_LE(sides.undecided, 2);
  std::printf("[ info     ] star polySAM concave mouths: %d face side points, %d suspects, %d faces fail (worst %.2f "
              "eps), %d undecided; kept %zu crack faces, %zu vertices uncertified; %zu deep fillings taken (bound %.2f "
              "eps)\n",
              sides.checked, sides.suspects, sides.failed, sides.worst, sides.undecided, env.crack_faces_kept,
              env.kept_wall_uncertified.size(), env.deep_fillings_taken, env.filling_depth_bound / env.tolerance);
}

// The stress campaign's star prism on a polySAM of four poses (case 2024, tolerance 1e-3): the
// mouths' depth checks found 6 deep fillings in round 2 and 4 in round 4, the first round in
// which they were no longer refused; taken, they left 3 faces up to 1.08 eps off the true
// boundary (reported by deep_fillings_taken). A check that finds fewer deep fillings than the
// one before it now refuses them still (see kRefuseRounds in trim.cpp): the next round finds
// none, and every face lies on the true boundary.
TEST(Envelope, DeepFillingsAreRefusedWhileTheirCountFalls) {
  const Mesh m = starPrismOf({{{0.72949891118408217, -0.094368276446845506},
                               {0.27651483745537903, 0.11977953320570781},
                               {0.36285666385269316, 0.76683474432860543},
                               {0.04024359284369311, 0.30724282234661726},
                               {-0.26610179977098769, 0.67896736293380433},
                               {-0.47051272447969672, 0.28598405818300993},
                               {-0.9616130484352241, 0.13297618142159542},
                               {-0.33905261866002556, -0.24980495613691628},
                               {-0.56022498364012929, -0.73431101019949518},
                               {-0.022496079533362311, -0.39418147731896802},
                               {0.45511881003427879, -0.881707654176623},
                               {0.30265876464875174, -0.11949629216379637}}},
                             0.34658895605043555);
  const Motion3 motion = polySamOf({
      {0.84840663165306074, 0.52706161554414477, -0.049114567972284057, -0.35671323686875567, -0.26183456590620008,
       0.3372063601217915, -0.90428675252384649, 0.22559416744929606, -0.46005309200549849, 0.78006276934193508,
       0.42409106147473974, 0.073202668700679707},
      {0.26485167386071934, 0.83859349530713523, -0.84453455483350492, -0.82356147179249573, -0.45205974354441197,
       0.76857480497476716, -1.0531349649141142, 0.70044464414551721, -0.79183094612395077, 1.9727399074566474,
       0.23047340494080287, -0.27052317739102805},
      {0.51584366410403726, -0.45722817844633257, -0.63094214513256075, 0.11501842501754012, -1.0268064585118013,
       2.0636373167585536, -1.8636099207411365, 1.7260380259853847, -0.20891557004568129, 2.6726183335471854,
       -0.16324325245154681, -2.427226321136073},
      {1.6081035494172968, -3.2905345130575325, -0.10888006875059386, 0.72528424781990486, -1.182372430868293,
       1.9067786359640482, -2.4446858165307361, 3.6833773867878428, 0.065554706469349799, 1.7592274419469742,
       -1.7744046791106745, 0.21334424052033263},
  });
  Envelope env;
  const SideCheck sides = sweepAndCheckFaceSides(m, motion, 1e-3, 2024, env);
  EXPECT_EQ(env.deep_fillings_taken, 0u) << "bound " << env.filling_depth_bound / env.tolerance << " eps";
  EXPECT_EQ(sides.failed, 0) << "worst " << sides.worst << " eps";
  EXPECT_TRUE(env.kept_wall_uncertified.empty());
  std::printf("[ info     ] star polySAM, deep fillings refused while fewer: %d face side points, %d suspects, %d faces "
              "fail; kept %zu crack faces, %zu buried patches\n",
              sides.checked, sides.suspects, sides.failed, env.crack_faces_kept, env.buried_patches_kept);
}

// The stress campaign's bracket on a general affine span (case 22842, tolerance 1e-3): a mouth
// filling's face whose centroid lay 2.3 eps from its loop, where the filling probes did not
// look (they cover points at least 4 eps from it), stood 1.15 eps off the true boundary, and
// nothing was reported. Each filling face's centroid is now probed as well (Deep fillings in
// trim.cpp): that filling is refused, its mouth's walls kept and certified, and every face lies
// on the true boundary.
TEST(Envelope, FillingFacesAreProbedAtTheirCentroids) {
  const Mesh m = bundledBracket();
  const Motion3 motion = polySamOf({
      {0.9997267766628664, -0.006584652715293181, -0.022427981895263897, 0.45808176852154425, 0.006001602062594469,
       0.9996448260676676, -0.025965409467692338, -0.4902029829005119, 0.022590989264695, 0.025823711289465097,
       0.9994112182376587, -0.324088675548156},
      {0.5739084067284858, -0.5699179438174178, -0.44099220271106093, -0.6008623682744328, -0.39910525473249964,
       2.349412244666763, 1.015078032735736, -0.24539465233326574, -0.06846498942268153, 0.5387963372645501,
       0.9687552501294481, 0.3846777589947381},
  });
  Envelope env;
  const SideCheck sides = sweepAndCheckFaceSides(m, motion, 1e-3, 22842, env);
  EXPECT_EQ(sides.failed, 0) << "worst " << sides.worst << " eps";
  EXPECT_EQ(env.deep_fillings_taken, 0u) << "bound " << env.filling_depth_bound / env.tolerance << " eps";
  EXPECT_TRUE(env.kept_wall_uncertified.empty());
  EXPECT_TRUE(env.kept_wall_faces_uncertified.empty());
  std::printf("[ info     ] bracket affine span, filling centroids probed: %d face side points, %d suspects, %d faces "
              "fail; kept %zu crack faces, %zu buried patches\n",
              sides.checked, sides.suspects, sides.failed, env.crack_faces_kept, env.buried_patches_kept);
}

#ifdef STEADY_CGAL_MESHES
// The stress campaign's CGAL sphere on a polySAM of four poses (case 20374, tolerance 1e-3):
// walls are kept at mouths whose fillings were refused, and every vertex on them is certified
// within eps, but two kept crack faces have their centroids 1.01 and 1.04 eps deep in a posed
// body; nothing was reported. The centroids of the faces at kept walls are now certified too
// (Envelope::kept_wall_faces_uncertified): every face that the oracle finds off the true
// boundary must be listed (sweepAndCheckFaceSides), and some must be found (else the case no
// longer shows the error: pick another).
TEST(Envelope, KeptWallFacesOffTheTrueBoundaryAreListed) {
  const Mesh m = cgalSampleMesh("sphere.off");
  const Motion3 motion = polySamOf({
      {0.29748579078567805, 0.7857644408181461, 0.5422881594008541, -0.4853302752817743, 0.0911848264406821,
       0.5420229899786272, -0.8354019426369632, 0.4719183865078116, -0.9503617899029836, 0.29796865922505233,
       0.08959434363854729, -0.14753702782122335},
      {-0.14153385624228623, 0.7317207729863153, 0.12008623879782135, -0.6497569181381684, -0.17601724296150317,
       0.3315079024753458, -0.6581011457251389, -0.7354387778106002, -0.7412561853635032, 0.6291172971020016,
       0.33118504661884157, -1.2478274326071923},
      {0.6273190933885437, -0.4109671116403063, 0.10700910993311458, 1.8835915288887324, 0.3572700556824539,
       -0.9225989894409128, -0.016214062757995945, -0.015744140247823335, 0.2816087658526723, -0.14497755125830025,
       -0.7385712642781836, 0.0024818708220681884},
      {0.6273190933885437, -0.4109671116403063, 0.10700910993311458, 4.085352600624303, 0.3572700556824539,
       -0.9225989894409128, -0.016214062757995945, -1.0965263443343358, 0.2816087658526723, -0.14497755125830025,
       -0.7385712642781836, -0.09195245060572935},
  });
  Envelope env;
  // (the first sweep only: a re-sweep leaves no such face)
  const SideCheck sides = sweepAndCheckFaceSides(m, motion, 1e-3, 20374, env, 0);
  EXPECT_GE(sides.off_faces.size(), 1u) << "no face off the true boundary here any more: pick another case";
  EXPECT_GT(env.kept_wall_depth_bound, env.tolerance);
  EXPECT_TRUE(env.kept_wall_uncertified.empty());
  std::printf("[ info     ] CGAL sphere polySAM kept-wall faces: %zu faces off the true boundary (worst %.3f eps), %zu "
              "listed, bound %.3g eps\n",
              sides.off_faces.size(), sides.worst, env.kept_wall_faces_uncertified.size(),
              env.kept_wall_depth_bound / env.tolerance);
}
#endif

// The stress campaign's bracket on a screw (case 18970, tolerance 1e-3): the flat fillings of two
// wide mouths (loops of 6 and 10 points) bulged out of the swept volume, up to 2.7 and 1.9 eps
// off the curved true boundary; they were refused, the walls kept at them held two vertices
// deeper than eps (the tenth round's code listed them as uncertified), and the case failed.
// Deep fillings are now refined onto the true boundary (Refined fillings in trim.cpp): both
// mouths close within eps at every probe, no wall vertex or face is left uncertified, and the
// oracle finds every face on the true boundary.
TEST(Envelope, DeepFillingsOfWideMouthsAreRefinedOntoTheBoundary) {
  const Mesh m = bundledBracket();
  const Motion3 motion = polySamOf({
      {0.64436018943477713, 0.76472188737710456, -0.00061744471598892958, -0.25150233905635844,
       -0.72799655697015841, 0.61316755182243876, -0.30667012640893454, 0.027626460546923859,
       -0.23413876080472698, 0.19805551837420746, 0.95181566089781833, -0.35443352634414271},
      {-0.28298196411280752, -0.069709343902654541, 0.95658863434577723, 0.4926627092861347,
       -0.54367438874435581, -0.80998800369788426, -0.21985811990683382, 0.80240683350395181,
       0.79015148358419807, -0.58228862365512324, 0.1913128112581936, -1.7590743348221676},
  });
  Envelope env;
  const SideCheck sides = sweepAndCheckFaceSides(m, motion, 1e-3, 18970, env);
  EXPECT_GT(env.fillings_refined, 0u) << "no filling refined here any more: pick another case";
  EXPECT_EQ(sides.failed, 0) << "worst " << sides.worst << " eps";
  EXPECT_EQ(env.deep_fillings_taken, 0u) << "bound " << env.filling_depth_bound / env.tolerance << " eps";
  EXPECT_LE(env.filling_depth_bound, env.tolerance);
  EXPECT_TRUE(env.kept_wall_uncertified.empty());
  EXPECT_TRUE(env.kept_wall_faces_uncertified.empty());
  std::printf("[ info     ] bracket screw, wide mouths: %zu fillings refined (bound %.3g eps); %d face side points, "
              "%d faces fail; kept %zu crack faces, %zu buried patches\n",
              env.fillings_refined, env.filling_depth_bound / env.tolerance, sides.checked, sides.failed,
              env.crack_faces_kept, env.buried_patches_kept);
}

// The stress campaign's star prism translated along two spans (case 764, tolerance 1e-3): the
// swept volume is a polyhedron and the envelope has 206 faces, 6 of them dent triangles
// (fillBuriedDents) about 1 across, whose centroids stood 1.1 to 2.5 eps off the true boundary
// with every vertex on it. A dent triangle is now probed (its centroid and the foot of the tip)
// and refused when it strays farther than eps; with the probes taken out, the face check fails
// on 5 faces.
TEST(Envelope, DentTrianglesOffTheTrueBoundaryAreRefused) {
  const Mesh m = starPrismOf({{{0.8126095088906724, 0.0028863312554753525},
                               {0.30741873677927994, 0.19695856930488287},
                               {0.387009829914174, 0.6285717107269947},
                               {-0.010609420977256463, 0.48403402985898136},
                               {-0.4804621583058014, 0.6764944358387301},
                               {-0.4592165003636003, 0.2790004539030773},
                               {-0.7044946593393617, 0.07336729435548676},
                               {-0.26166375732044894, -0.15359595155777675},
                               {-0.5368528188286759, -0.6643299803443169},
                               {-0.03665043364046616, -0.29475350285687146},
                               {0.3403132188225882, -0.6772597219856619},
                               {0.26790305667914555, -0.14453859961729582}}},
                             0.42148485087135534);
  const Motion3 motion = polySamOf({
      {0.91609154510687252, -0.19793058257890431, -0.34871157919357715, -0.49800802752241291, 0.37204660605462958,
       0.74389946888341418, 0.55515304477072414, 0.062026660621168905, 0.14952459298367671, -0.63830797008571805,
       0.75511941533648574, 0.26668117455767326},
      {0.91609154510687252, -0.19793058257890431, -0.34871157919357715, -1.4430468018573279, 0.37204660605462958,
       0.74389946888341418, 0.55515304477072414, 0.88014795067467311, 0.14952459298367671, -0.63830797008571805,
       0.75511941533648574, 2.2653425729365271},
      {0.91609154510687252, -0.19793058257890431, -0.34871157919357715, -1.7415796553499441, 0.37204660605462958,
       0.74389946888341418, 0.55515304477072414, -0.28080335680260993, 0.14952459298367671, -0.63830797008571805,
       0.75511941533648574, 1.1944297246551323},
  });
  Envelope env;
  const SideCheck sides = sweepAndCheckFaceSides(m, motion, 1e-3, 764, env);
  EXPECT_EQ(sides.failed, 0);
  EXPECT_EQ(sides.undecided, 0);
  std::printf("[ info     ] star translated along two spans: %zu faces, %zu dents filled, %d face side points, %d "
              "suspects\n",
              env.triangles.size(), env.buried_dents_filled, sides.checked, sides.suspects);
}

// The stress campaign's torus on a polySAM of four poses (case 22339, tolerance 2e-3): the
// envelope has two inner shells, cavities the true sweep has too, but one vertex of one lies
// 1.28 eps off the true boundary (by the campaign's oracle). Nothing reported it: only the
// kept walls' vertices were certified. Every vertex of an inner shell is now certified the
// same way (Envelope::cavity_uncertified), so each cavity vertex that the certified oracle finds
// off the true boundary, or inside the swept volume with no outside point within 1.01 eps,
// must be listed.
TEST(Envelope, CavityVerticesOffTheTrueBoundaryAreListed) {
  const Mesh m = torus(0.7, 0.25, 12, 6);
  const Motion3 motion = polySamOf({
      {-0.086046980105537907, -0.33959573025295114, -0.93662727763432252, 0.37465429444717757, -0.97777350060414481,
       -0.15162787392834831, 0.14480320909526023, 0.36497839607751592, -0.1911933543066649, 0.9282692108660795,
       -0.31900058530829106, 0.076307882882814981},
      {-0.27789380784481565, 0.35585783912129254, -0.89226690507797779, -0.69717309226501367, -0.81222603413342209,
       0.40889697642611034, 0.41604342579288378, 0.54192914915929691, 0.51289755413474347, 0.84033830152237465,
       0.1754070635894931, -0.93472984772971457},
      {-0.27789380784481565, 0.35585783912129254, -0.89226690507797779, -0.23966108389959911, -0.81222603413342209,
       0.40889697642611034, 0.41604342579288378, 0.97722272738748672, 0.51289755413474347, 0.84033830152237465,
       0.1754070635894931, -0.11919101436577295},
      {0.89645746006770477, -0.43877913476736219, -0.061942660434992906, 0.59198606321615777, -0.39899387495608435,
       -0.73842988181379243, -0.54362229294979902, 1.0003995488228594, 0.19278980791651884, 0.51204900208600512,
       -0.83704116351959557, -0.88300660921372132},
  });
  const Envelope env = sweep(m, motion, 2e-3);
  EXPECT_GT(env.cavity_vertices, 0u) << "the envelope has no cavity any more: pick another case";
  // (the vertices of the shells other than the one of largest volume)
  const steady::sweep::MeshCheck mc = inspectMesh(env.vertices, env.triangles, false);
  EXPECT_EQ(static_cast<std::size_t>(mc.shells) > 1, env.cavity_vertices > 0);
  std::vector<int> cavity;
  {
    std::vector<int> shell(env.vertices.size(), -1);
    const std::vector<Faces> parts = edgeComponents(env.triangles);
    std::size_t outer = 0;
    for (std::size_t k = 0; k < parts.size(); ++k)
      if (meshVolume(env.vertices, parts[k]) > meshVolume(env.vertices, parts[outer])) outer = k;
    for (std::size_t k = 0; k < parts.size(); ++k)
      if (k != outer)
        for (const auto& t : parts[k])
          for (const int v : t) shell[static_cast<std::size_t>(v)] = static_cast<int>(k);
    for (std::size_t v = 0; v < shell.size(); ++v)
      if (shell[v] >= 0) cavity.push_back(static_cast<int>(v));
  }
  EXPECT_EQ(cavity.size(), env.cavity_vertices);
  const MovingBody mb(m, motion);
  const double T = env.tolerance * 1.01;
  auto listed = [&](int v) {
    return std::binary_search(env.cavity_uncertified.begin(), env.cavity_uncertified.end(), v);
  };
  int off = 0;
  for (const int v : cavity) {
    const MinBracket b = boundaryBracket(mb, env.vertices[static_cast<std::size_t>(v)], T);
    if (b.lo > T || b.hi < -T) {
      ++off;
      EXPECT_TRUE(listed(v)) << "cavity vertex " << v << " is off the true boundary and not listed";
    }
  }
  const AcrossCheck a = checkAcross(env, mb, cavity);
  for (const int v : a.deep) EXPECT_TRUE(listed(v)) << "cavity vertex " << v << " is deep and not listed";
  std::printf("[ info     ] torus polySAM cavities: %zu vertices, %d off the true boundary, %zu deep, %zu listed "
              "(bound %.3g eps)\n",
              cavity.size(), off, a.deep.size(), env.cavity_uncertified.size(), env.cavity_depth_bound / env.tolerance);
}

// The armadillo on the benchmark's screw (CGAL's sample, 52k faces), tolerance 1e-3, on one thread
// and on two: the same envelope bit for bit. Before the mouth refill was a search of our own,
// CGAL's refill within a 3D Delaunay triangulation chose by memory addresses, and this case came
// out in two ways (the scratch driver's hashes: 11064a189aa49559 on one thread, 85a8c50e7ca2c95b
// on two). About a minute on two cores.
TEST(Envelope, SameEnvelopeOnOneAndTwoThreadsOnTheArmadilloScrew) {
#ifndef STEADY_CGAL_MESHES
  GTEST_SKIP() << "CGAL's sample meshes (Debian libcgal-demo) were not found when the build was configured";
#else
  const SampleOnScrew scene = cgalSampleOnTheBenchmarkScrew("armadillo.off");
  const Body body(scene.mesh.vertices, scene.mesh.faces);
  SweepOptions one;
  one.relative_tolerance = 1e-3;
  one.threads = 1;
  SweepOptions two = one;
  two.threads = 2;
  const Envelope a = sweptEnvelope(body, scene.span, one);
  const Envelope b = sweptEnvelope(body, scene.span, two);
  ASSERT_GT(a.pocket_mouths_filled, 1000u);
  expectSameEnvelope(a, b, "one thread against two");
#endif
}

// ---- seeded property test ----------------------------------------------------------------------

TEST(Envelope, ContainsEveryPosedBodyOnRandomMotions) {
  // Motions from one generator, checks from one per case: the cases do not depend on how many
  // draws the checks of earlier envelopes took.
  std::mt19937_64 rng(4242);
  const std::vector<std::pair<std::string, Mesh>> meshes = {
      {"box", box(V(-0.5, -0.3, -0.2), V(0.5, 0.3, 0.2))},
      {"sphere", uvSphere(6, 10, 0.6)},
      {"L", lShape(0.5)},
      {"torus", torus(0.7, 0.25, 12, 6)},
  };
  const MotionKind kinds[] = {MotionKind::Screw, MotionKind::Affine, MotionKind::PolySam};
  int n = 0;
  for (const auto& [mname, mesh] : meshes)
    for (const MotionKind kind : kinds) {
      // Every other case: a coarser tolerance, to keep the run short.
      const double rel = ++n % 2 ? 2e-3 : 1e-3;
      const Motion3 motion = randomMotion(kind, rng);
      Envelope env;
      try {
        env = sweep(mesh, motion, rel);
      } catch (const steady::Error& e) {
        ADD_FAILURE() << mname << "/" << motionName(kind) << ": sweptEnvelope threw " << steady::to_string(e.code()) << ": "
                      << e.what();
        continue;
      }
      CheckOptions co;
      co.containment_points = 120;
      co.boundary_vertices = 60;
      co.cross_points = 60;
      co.expected_euler = 99;  // a random sweep may enclose a void or close a handle
      std::mt19937_64 check_rng(1000 + static_cast<unsigned>(n));
      checkEnvelope(mesh, motion, env, epsOf(mesh, rel), check_rng, mname + "/" + motionName(kind), co);
    }
}

// The face side check itself (checkFaceSides) must see a face off the true boundary whose
// vertices all lie on it: the L prism translated along z, against the prism over the L's convex
// hull, whose faces across the notch stand up to 0.71 off the true boundary. The true envelope
// of the same sweep passes.
TEST(EnvelopeOracle, FaceSidesSeeAFaceAcrossAConcaveNotch) {
  const Mesh m = lShape(0.6);
  const Motion3 motion = single(Affine3(), Affine3::translation(V(0, 0, 0.1)));
  const MovingBody mb(m, motion);
  const SweptVolume sv(makeBody(m), motion);
  std::mt19937_64 rng(7);
  const Envelope good = sweep(m, motion);
  EXPECT_EQ(checkFaceSides(good, mb, sv, good.triangles.size(), rng).failed, 0);
  const Mesh hull = prism({{{0, 0}}, {{2, 0}}, {{2, 1}}, {{1, 2}}, {{0, 2}}}, 0.0, 0.7, 0);
  Envelope bad;
  bad.vertices = hull.v;
  bad.triangles = hull.f;
  bad.tolerance = good.tolerance;
  ::testing::TestPartResultArray failures;
  SideCheck c;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD,
                                                         &failures);
    c = checkFaceSides(bad, mb, sv, bad.triangles.size(), rng);
  }
  // (at least the two side faces across the notch, whose centroids lie 0.24 to 0.47 from the
  // L: 80 to 160 eps)
  EXPECT_GE(c.failed, 2);
  EXPECT_EQ(failures.size(), std::min(c.failed, kMaxMessages));
  EXPECT_GT(c.worst, 50.0);
  for (int i = 0; i < failures.size(); ++i)
    EXPECT_NE(std::string(failures.GetTestPartResult(i).message()).find("from every posed body"), std::string::npos);
}

// ---- inspectMesh and bad input -----------------------------------------------------------------

TEST(Envelope, InspectMeshReportsDefects) {
  const Mesh b = box(V(0, 0, 0), V(1, 1, 1));
  MeshCheck c = inspectMesh(b.v, b.f);
  EXPECT_TRUE(c.closed && c.manifold && c.oriented);
  EXPECT_EQ(c.self_intersections, 0);
  EXPECT_EQ(c.shells, 1);
  EXPECT_NEAR(c.volume, 1.0, 1e-15);
  EXPECT_NEAR(c.area, 6.0, 1e-14);
  // Flipped: oriented (consistently), negative volume.
  const Mesh f = flipped(b);
  c = inspectMesh(f.v, f.f);
  EXPECT_TRUE(c.closed && c.oriented);
  EXPECT_NEAR(c.volume, -1.0, 1e-15);
  // Open: one face removed.
  Mesh open = b;
  open.f.pop_back();
  c = inspectMesh(open.v, open.f);
  EXPECT_FALSE(c.closed);
  // One face reversed: closed but not oriented.
  Mesh bad = b;
  std::swap(bad.f[3][1], bad.f[3][2]);
  c = inspectMesh(bad.v, bad.f);
  EXPECT_FALSE(c.oriented);
  EXPECT_NE(directedEdgeFaults(bad.f, bad.v.size()), "");
  // Two overlapping boxes: two shells that cross.
  Mesh two = b;
  const Mesh other = box(V(0.5, 0.5, 0.5), V(1.5, 1.5, 1.5));
  for (const auto& t : other.f) two.f.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  two.v.insert(two.v.end(), other.v.begin(), other.v.end());
  c = inspectMesh(two.v, two.f);
  EXPECT_EQ(c.shells, 2);
  EXPECT_GT(c.self_intersections, 0);
  c = inspectMesh(two.v, two.f, false);
  EXPECT_EQ(c.self_intersections, -1);
  // Two boxes that share one corner vertex: closed and oriented, but not manifold there.
  Mesh pinched = b;
  const Mesh next = box(V(1, 1, 1), V(2, 2, 2));
  auto indexOf = [](const Mesh& m, const V& x) {
    return static_cast<int>(std::find(m.v.begin(), m.v.end(), x) - m.v.begin());
  };
  const int shared = indexOf(b, V(1, 1, 1)), corner = indexOf(next, V(1, 1, 1));
  ASSERT_LT(shared, 8);
  ASSERT_LT(corner, 8);
  for (const auto& t : next.f) {
    std::array<int, 3> u;
    for (int k = 0; k < 3; ++k) u[k] = t[k] == corner ? shared : t[k] + 8;
    pinched.f.push_back(u);
  }
  pinched.v.insert(pinched.v.end(), next.v.begin(), next.v.end());
  c = inspectMesh(pinched.v, pinched.f);
  EXPECT_TRUE(c.closed && c.oriented);
  EXPECT_FALSE(c.manifold);
  EXPECT_EQ(c.shells, 2);
  EXPECT_NEAR(c.volume, 2.0, 1e-14);
  Mesh out = b;
  out.f[0][0] = 8;
  EXPECT_TRUE(throwsError([&] { inspectMesh(out.v, out.f); }, ErrorCode::InvalidArgument, "vertex|range|index"));
}

TEST(Envelope, BadToleranceIsATypedError) {
  const Mesh m = box(V(0, 0, 0), V(1, 1, 1));
  const Body body = makeBody(m);
  const Span3 span = Span3::between(Affine3(), Affine3::translation(V(0, 0, 1)) * Affine3::rotation(V(0, 0, 1), 1.0));
  const Motion3 motion = single(Affine3(), Affine3::translation(V(0, 0, 1)) * Affine3::rotation(V(0, 0, 1), 1.0));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const double bad : {0.0, -1e-3, nan, inf}) {
    SweepOptions o;
    o.tolerance = bad;
    EXPECT_TRUE(throwsError([&] { sweptEnvelope(body, span, o); }, ErrorCode::InvalidArgument, "tolerance"));
    EXPECT_TRUE(throwsError([&] { sweptEnvelope(body, motion, o); }, ErrorCode::InvalidArgument, "tolerance"));
    SweepOptions r;
    r.relative_tolerance = bad;
    EXPECT_TRUE(throwsError([&] { sweptEnvelope(body, span, r); }, ErrorCode::InvalidArgument, "relative_tolerance"));
  }
  // A tolerance far too small for the turn needs more than max_steps steps.
  SweepOptions tiny;
  tiny.tolerance = 1e-9;
  tiny.max_steps = 8;
  EXPECT_TRUE(throwsError([&] { sweptEnvelope(body, span, tiny); }, ErrorCode::InvalidArgument, "step|tolerance"));
}

}  // namespace
