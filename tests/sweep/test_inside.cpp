// The swept-volume inside test (inside.hpp): known answers (a box translated: the Minkowski sum
// with a segment; a box turning about its axis: a closed form), a seeded comparison with an
// independent oracle (a certified bracket of the minimum over time of the signed distance to the
// posed body, by Lipschitz branch and bound, envelope_check.hpp) over several bodies (convex,
// non-convex, a torus, a body with a cavity) and motions (screws, translations, general affine
// spans with shear and scaling, polySAMs, an exact half turn, more than a full turn), sliding
// contact, a body at rest, and bad input.
#include <steady/sweep/inside.hpp>

#include "sweep/envelope_check.hpp"
#include "sweep/sweep_test.hpp"

#include <steady/core/motion.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

namespace {

using steady::Affine3;
using steady::ErrorCode;
using steady::Motion3;
using steady::Span3;
using steady::sweep::Body;
using steady::sweep::InsideHint;
using steady::sweep::InsideOptions;
using steady::sweep::InsideResult;
using steady::sweep::SweptVolume;
using steady::sweep::sweptContains;
using namespace steady_sweep_test;



// Radius of the union of the squares [-a, a]^2 turned by every angle in [0, theta], in the
// direction alpha (the union is star-shaped about the centre). The square's radial function
// rho(beta) = a / max(|cos beta|, |sin beta|) peaks (a sqrt 2) at the corners beta = pi/4 + k pi/2
// and is monotone between a corner and a side's midpoint, so over the window
// [alpha - theta, alpha] its maximum is a sqrt 2 when the window holds a corner, and otherwise
// the larger of its values at the two ends.
double turnedSquareRadius(double a, double theta, double alpha) {
  auto rho = [&](double beta) { return a / std::max(std::abs(std::cos(beta)), std::abs(std::sin(beta))); };
  // The first corner at or after alpha - theta.
  const double start = alpha - theta;
  const double k = std::ceil((start - M_PI / 4) / (M_PI / 2));
  const double corner = M_PI / 4 + k * M_PI / 2;
  if (corner <= alpha) return a * std::sqrt(2.0);
  return std::max(rho(alpha), rho(start));
}

// The oracle's verdict on x: clearly inside (the minimum over time of the signed distance is
// below -margin), clearly outside (certified above +margin), or too close to call.
enum class Truth { Inside, Outside, Unknown };

Truth oracle(const MovingBody& mb, const V& x, double margin, int budget = 6000) {
  const MinBracket b = minSignedDistance(
      mb, x, [&](double lo, double hi) { return hi < -margin || lo > margin || (hi < margin && lo > -margin); }, budget);
  if (b.hi < -margin) return Truth::Inside;
  if (b.lo > margin) return Truth::Outside;
  return Truth::Unknown;
}

// Bounding box of the body posed at 33 times per span (for drawing query points).
void sweptBox(const MovingBody& mb, V& lo, V& hi) {
  lo = V::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (std::size_t s = 0; s < mb.motion.spanCount(); ++s)
    for (int k = 0; k <= 32; ++k)
      for (const V& p : mb.posed(s, k / 32.0)) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
}

// Span and span time of a motion time (the span reported by the query).
double spanTime(const Motion3& m, std::size_t span, double t) {
  return (t - m.spanBegin(span)) / (m.spanEnd(span) - m.spanBegin(span));
}

struct Tally {
  int inside = 0, outside = 0, unknown = 0, wrong = 0, bad_witness = 0, late = 0;
};

// Compares SweptVolume with the oracle on `count` points, half drawn in the swept box (inflated
// by a fifth), half near the moving surface (a random point of a random face, posed at a random
// time, moved by up to a tenth of the box), checks the witness time of every inside answer (x
// within 2 delta of the posed body there) and, for every 4th, that no earlier time has x
// clearly inside.
Tally compareWithOracle(const Mesh& mesh, const Motion3& motion, std::mt19937_64& rng, int count, const std::string& name) {
  const Body body = makeBody(mesh);
  const SweptVolume sv(body, motion);
  const MovingBody mb(mesh, motion);
  V lo, hi;
  sweptBox(mb, lo, hi);
  const V pad = 0.2 * (hi - lo);
  lo -= pad;
  hi += pad;
  const double scale = (hi - lo).norm();
  const double margin = 1e-5 * scale;
  Tally t;
  for (int n = 0; n < count; ++n) {
    V x(uniform(rng, lo.x(), hi.x()), uniform(rng, lo.y(), hi.y()), uniform(rng, lo.z(), hi.z()));
    if (n % 2) {
      const std::size_t s = rng() % motion.spanCount();
      const std::vector<V> w = mb.posed(s, uniform(rng, 0, 1));
      const auto& f = mesh.f[rng() % mesh.f.size()];
      double b0 = uniform(rng, 0, 1), b1 = uniform(rng, 0, 1);
      if (b0 + b1 > 1) b0 = 1 - b0, b1 = 1 - b1;
      x = w[f[0]] + b0 * (w[f[1]] - w[f[0]]) + b1 * (w[f[2]] - w[f[0]]) + uniform(rng, 0, 0.1 * scale) * randomUnit(rng);
    }
    const InsideResult r = sv.query(x);
    const Truth truth = oracle(mb, x, margin);
    if (truth == Truth::Unknown) {
      ++t.unknown;
    } else {
      ++(truth == Truth::Inside ? t.inside : t.outside);
      if ((truth == Truth::Inside) != r.inside) {
        ++t.wrong;
        ADD_FAILURE() << name << ": point " << x.transpose() << " is " << (truth == Truth::Inside ? "inside" : "outside")
                      << " by the oracle, query says " << (r.inside ? "inside" : "outside") << " (time " << r.time << ")";
      }
    }
    if (!r.inside) continue;
    // The witness: x is inside the posed body or within 2 delta of it at the reported time.
    const double sd = mb.signedDistance(r.span, spanTime(motion, r.span, r.time), x);
    if (!(sd <= 2 * sv.tolerance() + 1e-12 * scale)) {
      ++t.bad_witness;
      ADD_FAILURE() << name << ": point " << x.transpose() << " reported inside at time " << r.time << " (span " << r.span
                    << ", face " << r.face << ") where its signed distance to the posed body is " << sd;
    }
    // Earliest: no earlier time at which x is clearly inside (checked on every 4th inside point).
    if (n % 4 == 0 && (r.span > 0 || spanTime(motion, r.span, r.time) > 0)) {
      const MinBracket b = minSignedDistance(
          mb, x, [&](double blo, double bhi) { return bhi < -margin || blo >= -margin; }, 6000, 16,
          std::max(1e-9, spanTime(motion, r.span, r.time)), r.span);
      if (b.hi < -margin) {
        ++t.late;
        ADD_FAILURE() << name << ": point " << x.transpose() << " reported first reached at time " << r.time
                      << " but it is inside by " << -b.hi << " at span " << b.span << " time " << b.tau;
      }
    }
  }
  return t;
}

// ---- known answers -----------------------------------------------------------------------------

TEST(Inside, BoxTranslatedIsTheMinkowskiSum) {
  // The box [0, 1]^3 translated by d in body coordinates, from a turned start pose: x is inside
  // iff B^-1 x - tau d is in the box for some tau in [0, 1].
  const Mesh m = box(V(0, 0, 0), V(1, 1, 1));
  const Body body = makeBody(m);
  const V d(2, 0.5, 0.3);
  const Affine3 B = Affine3::translation(V(0.3, -1, 2)) * Affine3::rotation(V(1, 2, 3), 0.8);
  const Span3 span = Span3::between(B, B * Affine3::translation(d));
  const SweptVolume sv(body, span);
  std::mt19937_64 rng(11);
  int inside = 0, outside = 0;
  for (int n = 0; n < 4000; ++n) {
    const V y(uniform(rng, -0.3, 3.3), uniform(rng, -0.2, 1.7), uniform(rng, -0.2, 1.5));
    const double depth = minkowskiDepth(y, V(0, 0, 0), V(1, 1, 1), d);
    if (std::abs(depth) < 1e-7) continue;
    const V x = B.applyPoint(y);
    const InsideResult r = sv.query(x);
    ASSERT_EQ(r.inside, depth > 0) << "body point " << y.transpose() << ", depth " << depth;
    ++(r.inside ? inside : outside);
  }
  EXPECT_GT(inside, 800);
  EXPECT_GT(outside, 800);
  // A point first reached at a known time: (2.5, 0.5, 0.5) is entered through the face x = 1 at
  // tau = 0.75 (with y and z inside throughout).
  const InsideResult r = sv.query(B.applyPoint(V(2.5, 0.5, 0.5)));
  EXPECT_TRUE(r.inside);
  EXPECT_NEAR(r.time, 0.75, 1e-9);
  EXPECT_GE(r.face, 0);
}

TEST(Inside, BoxTurningAboutItsAxisClosedForm) {
  // The box [-a, a]^2 x [0, h] turned about the z axis by theta (a quarter turn and less, and
  // more): inside iff 0 <= z <= h and the radius is at most turnedSquareRadius().
  const double a = 0.5, h = 0.7;
  const Body body = makeBody(box(V(-a, -a, 0), V(a, a, h)));
  std::mt19937_64 rng(12);
  for (const double theta : {0.3, 1.1, 2.0, 3.0}) {
    const SweptVolume sv(body, Span3::between(Affine3(), Affine3::rotation(V(0, 0, 1), theta)));
    int inside = 0, outside = 0;
    for (int n = 0; n < 3000; ++n) {
      const V x(uniform(rng, -0.8, 0.8), uniform(rng, -0.8, 0.8), uniform(rng, -0.2, 0.9));
      const double rad = std::hypot(x.x(), x.y()), alpha = std::atan2(x.y(), x.x());
      const double rb = turnedSquareRadius(a, theta, alpha);
      if (std::abs(rad - rb) < 1e-7 || std::abs(x.z()) < 1e-7 || std::abs(x.z() - h) < 1e-7) continue;
      const bool want = rad < rb && x.z() > 0 && x.z() < h;
      ASSERT_EQ(sv.contains(x), want) << "theta " << theta << ", point " << x.transpose() << ", radius " << rad
                                      << " vs boundary " << rb;
      ++(want ? inside : outside);
    }
    EXPECT_GT(inside, 500) << theta;
    EXPECT_GT(outside, 500) << theta;
    // On the planes of the top and bottom faces, which slide in them: inside the swept section
    // (on the boundary: the body touches the point) or beside it.
    int on = 0, off = 0;
    for (int n = 0; n < 1000; ++n) {
      const V x(uniform(rng, -0.8, 0.8), uniform(rng, -0.8, 0.8), n % 2 ? h : 0.0);
      const double rad = std::hypot(x.x(), x.y()), rb = turnedSquareRadius(a, theta, std::atan2(x.y(), x.x()));
      if (std::abs(rad - rb) < 1e-7) continue;
      ASSERT_EQ(sv.contains(x), rad < rb) << "theta " << theta << ", point " << x.transpose() << " on a face plane";
      ++(rad < rb ? on : off);
    }
    EXPECT_GT(on, 100);
    EXPECT_GT(off, 100);
  }
}

TEST(Inside, SlidingOnAGrazingFace) {
  // The unit box translated by (2, 0, 0): the faces y = 0, y = 1, z = 0, z = 1 slide in their
  // planes. Points on the plane y = 0 are on the swept volume's boundary inside [0, 3] x [0, 1]
  // and outside beyond it; a wide root band on that plane must still find the entry time.
  const Body body = makeBody(box(V(0, 0, 0), V(1, 1, 1)));
  const SweptVolume sv(body, Span3::between(Affine3(), Affine3::translation(V(2, 0, 0))));
  InsideResult r = sv.query(V(2.5, 0, 0.5));
  EXPECT_TRUE(r.inside);
  EXPECT_NEAR(r.time, 0.75, 1e-9);  // reached by the edge x = 1 of the face y = 0
  EXPECT_TRUE(sv.contains(V(1.5, 0, 0)));      // on the swept edge y = z = 0
  EXPECT_TRUE(sv.contains(V(3, 1, 1)));        // the far corner at the end
  EXPECT_FALSE(sv.contains(V(3.5, 0, 0.5)));   // on the plane, beyond the end
  EXPECT_FALSE(sv.contains(V(-0.5, 0, 0.5)));  // on the plane, before the start
  EXPECT_FALSE(sv.contains(V(2.5, -1e-6, 0.5)));
  EXPECT_TRUE(sv.contains(V(2.5, 1e-6, 0.5)));
  EXPECT_FALSE(sv.contains(V(3 + 1e-6, 0.5, 0.5)));
  EXPECT_TRUE(sv.contains(V(3 - 1e-6, 0.5, 0.5)));
  // On the plane y = 0 but beside the swept face (above, below): the trajectory slides in the
  // face's plane past the face without meeting it.
  EXPECT_FALSE(sv.contains(V(2.5, 0, 1.2)));
  EXPECT_FALSE(sv.contains(V(1.5, 0, -0.2)));
  EXPECT_FALSE(sv.contains(V(0.5, 0, 1 + 1e-6)));
  EXPECT_TRUE(sv.contains(V(0.5, 0, 1 - 1e-6)));
}

TEST(Inside, BodyAtRest) {
  // A span from a pose to itself: the swept volume is the posed body.
  const Mesh m = lShape();
  const Body body = makeBody(m);
  const Affine3 B = Affine3::translation(V(1, 2, 3)) * Affine3::rotation(V(0, 1, 1), 1.0);
  const SweptVolume sv(body, Span3::between(B, B));
  std::mt19937_64 rng(13);
  int inside = 0;
  for (int n = 0; n < 2000; ++n) {
    const V y(uniform(rng, -0.3, 2.3), uniform(rng, -0.3, 2.3), uniform(rng, -0.3, 0.9));
    const double sd = signedDistance(m.v, m.f, y);
    if (std::abs(sd) < 1e-7) continue;
    ASSERT_EQ(sv.contains(B.applyPoint(y)), sd < 0) << y.transpose();
    inside += sd < 0;
  }
  EXPECT_GT(inside, 300);
  // On the plane of the top face (z = 0.6), outside the L and inside it.
  EXPECT_FALSE(sv.contains(B.applyPoint(V(1.5, 1.5, 0.6))));
  EXPECT_TRUE(sv.contains(B.applyPoint(V(0.5, 1.5, 0.6))));
}

TEST(Inside, CavityIsOutsideUntilTheMaterialArrives) {
  // A box with a cubic cavity (an inward shell). The origin starts in the cavity.
  Mesh m = box(V(-1, -1, -1), V(1, 1, 1));
  const Mesh hole = flipped(box(V(-0.5, -0.5, -0.5), V(0.5, 0.5, 0.5)));
  for (const auto& f : hole.f) m.f.push_back({f[0] + 8, f[1] + 8, f[2] + 8});
  m.v.insert(m.v.end(), hole.v.begin(), hole.v.end());
  const Body body = makeBody(m);
  // Moving by 0.3 along x keeps the origin in the cavity; by 0.8 the cavity wall x = -0.5 passes
  // the origin at tau = 0.625.
  EXPECT_FALSE(sweptContains(body, Span3::between(Affine3(), Affine3::translation(V(0.3, 0, 0))), V(0, 0, 0)));
  const SweptVolume sv(body, Span3::between(Affine3(), Affine3::translation(V(0.8, 0, 0))));
  const InsideResult r = sv.query(V(0, 0, 0));
  EXPECT_TRUE(r.inside);
  EXPECT_NEAR(r.time, 0.625, 1e-9);
  EXPECT_FALSE(sv.containsAtStart(V(0, 0, 0)));
  EXPECT_TRUE(sv.containsAtStart(V(0.75, 0, 0)));
}

// ---- against the oracle ------------------------------------------------------------------------

TEST(Inside, MatchesTheOracleOnRandomMotions) {
  std::mt19937_64 rng(2024);
  const std::vector<std::pair<std::string, Mesh>> meshes = {
      {"box", box(V(-0.5, -0.3, -0.2), V(0.5, 0.3, 0.2))},
      {"sphere", uvSphere(6, 10, 0.6)},
      {"L", lShape(0.5)},
      {"torus", torus(0.7, 0.25, 10, 6)},
  };
  Tally total;
  for (const auto& [mname, mesh] : meshes)
    for (const MotionKind kind :
         {MotionKind::Screw, MotionKind::Translation, MotionKind::Affine, MotionKind::ShearScale, MotionKind::PolySam}) {
      const Motion3 motion = randomMotion(kind, rng);
      const Tally t = compareWithOracle(mesh, motion, rng, 120, mname + "/" + motionName(kind));
      total.inside += t.inside;
      total.outside += t.outside;
      total.unknown += t.unknown;
      total.wrong += t.wrong;
      total.bad_witness += t.bad_witness;
      total.late += t.late;
    }
  std::printf("[ info     ] oracle: %d inside, %d outside, %d too close to call; %d wrong, %d bad witnesses, %d late\n",
              total.inside, total.outside, total.unknown, total.wrong, total.bad_witness, total.late);
  EXPECT_EQ(total.wrong, 0);
  EXPECT_EQ(total.bad_witness, 0);
  EXPECT_EQ(total.late, 0);
  EXPECT_GT(total.inside, 300);
  EXPECT_GT(total.outside, 300);
  EXPECT_LT(total.unknown, (total.inside + total.outside) / 20);
}

TEST(Inside, ExactHalfTurnAndMoreThanAFullTurn) {
  std::mt19937_64 rng(7);
  const Mesh L = lShape(0.4);
  // An exact half turn about a vertical axis off the body (it has infinitely many logs; the
  // span's own choice is what the oracle follows too).
  const Affine3 turn = Affine3::translation(V(2.5, 0.5, 0)) * Affine3::rotation(V(0, 0, 1), M_PI) * Affine3::translation(V(-2.5, -0.5, 0));
  const Tally a = compareWithOracle(L, single(Affine3(), turn), rng, 200, "half turn");
  // Four spans of 100 degrees with a small rise: 400 degrees, the body passes over its own path.
  std::vector<Affine3> poses{Affine3()};
  const Affine3 step = Affine3::translation(V(0, 0, 0.1)) * Affine3::translation(V(2.5, 0.5, 0)) *
                       Affine3::rotation(V(0, 0, 1), 100 * M_PI / 180) * Affine3::translation(V(-2.5, -0.5, 0));
  for (int i = 0; i < 4; ++i) poses.push_back(step * poses.back());
  const Tally b = compareWithOracle(torus(0.6, 0.2, 10, 6, V(1, 1, 0)), Motion3::polySam(poses), rng, 200, "400 degrees");
  EXPECT_EQ(a.wrong + b.wrong + a.bad_witness + b.bad_witness + a.late + b.late, 0);
  EXPECT_GT(a.inside + b.inside, 60);
  EXPECT_GT(a.outside + b.outside, 60);
}

TEST(Inside, ThinPlateAndStrongShear) {
  std::mt19937_64 rng(8);
  const Mesh plate = box(V(-0.6, -0.4, -0.01), V(0.6, 0.4, 0.01));
  const Affine3 B = Affine3::rotation(V(1, 0, 0), 0.3);
  const Affine3 tumble = Affine3::translation(V(0.4, 0.2, 0.3)) * Affine3::rotation(V(0, 1, 0.2), 2.2);
  const Tally a = compareWithOracle(plate, single(B, tumble * B), rng, 250, "thin plate");
  const Affine3 shear = Affine3::translation(V(0.3, 0, 0.2)) * Affine3::shear(V(1, 0, 0), V(0, 0, 1), 2.5) *
                        Affine3::scaling(V(1.6, 0.5, 1.2));
  const Tally b = compareWithOracle(lShape(0.5), single(B, shear * B), rng, 250, "shear+scale");
  EXPECT_EQ(a.wrong + b.wrong + a.bad_witness + b.bad_witness + a.late + b.late, 0);
  EXPECT_GT(a.inside + b.inside, 40);
}

TEST(Inside, FreeFunctionsAgreeWithTheClass) {
  std::mt19937_64 rng(9);
  const Mesh m = uvSphere(5, 8, 0.5);
  const Body body = makeBody(m);
  const Motion3 motion = randomMotion(MotionKind::PolySam, rng);
  const SweptVolume sv(body, motion);
  for (int n = 0; n < 50; ++n) {
    const V x(uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3));
    EXPECT_EQ(sweptContains(body, motion, x), sv.contains(x));
    EXPECT_EQ(sweptContains(body, motion.span(0), x), SweptVolume(body, motion.span(0)).contains(x));
  }
  EXPECT_EQ(sv.spanCount(), motion.spanCount());
  EXPECT_DOUBLE_EQ(sv.tolerance(), 1e-9 * body.box().diagonal());
}

TEST(Inside, QueryRate) {
  // Not a target: the figure is printed for the record (a 1,920-face sphere on a screw).
  const Mesh m = uvSphere(16, 64, 1.0);
  const Body body = makeBody(m);
  const Span3 span = Span3::between(Affine3(), Affine3::translation(V(0, 0, 1.5)) * Affine3::rotation(V(0, 0, 1), 2.0) *
                                                   Affine3::translation(V(-1.5, 0, 0)));
  const SweptVolume sv(body, span);
  std::mt19937_64 rng(10);
  int inside = 0;
  const int n = 3000;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < n; ++i) inside += sv.contains(V(uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -1.2, 2.7)));
  const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / n;
  std::printf("[ info     ] %zu faces, screw: %.1f us per query (%d of %d inside)\n", m.f.size(), us, inside, n);
  EXPECT_GT(inside, 0);
}

// ---- hints --------------------------------------------------------------------------------------

TEST(Inside, HintIsATimeInsideThePosedBody) {
  // The translated box of BoxTranslatedIsTheMinkowskiSum: body point y is inside the posed box
  // at tau iff y - tau d lies in [0, 1]^3.
  const Body body = makeBody(box(V(0, 0, 0), V(1, 1, 1)));
  const V d(2, 0.5, 0.3);
  const Affine3 B = Affine3::translation(V(0.3, -1, 2)) * Affine3::rotation(V(1, 2, 3), 0.8);
  const SweptVolume sv(body, Span3::between(B, B * Affine3::translation(d)));
  auto strictlyIn = [&](const V& y, double tau) {
    const V z = y - tau * d;
    return (z.array() > 1e-9).all() && (z.array() < 1 - 1e-9).all();
  };
  // Entered through the face x = 1 at tau = 0.75, inside until the end: the hint lies just
  // after the entry (the scan's first 256 steps of 2^-16 are all inside).
  const V y(2.5, 0.5, 0.5);
  const std::optional<InsideHint> h = sv.hint(B.applyPoint(y));
  ASSERT_TRUE(h.has_value());
  EXPECT_EQ(h->span, 0u);
  EXPECT_GT(h->tau, 0.75);
  EXPECT_LT(h->tau, 0.75 + 257.0 / 65536);
  EXPECT_TRUE(strictlyIn(y, h->tau));
  // Inside at the start: the hint starts at tau = 0.
  const std::optional<InsideHint> h0 = sv.hint(B.applyPoint(V(0.5, 0.5, 0.5)));
  ASSERT_TRUE(h0.has_value());
  EXPECT_LT(h0->tau, 257.0 / 65536);
  // Never reached: no hint.
  EXPECT_FALSE(sv.hint(B.applyPoint(V(0.5, 2.5, 0.5))).has_value());
  EXPECT_FALSE(sv.hint(B.applyPoint(V(-1, 0.5, 0.5))).has_value());
  // Random points about their own hints' times agree with the closed form.
  std::mt19937_64 rng(31);
  int hinted = 0;
  for (int n = 0; n < 400; ++n) {
    const V p(uniform(rng, -0.3, 3.3), uniform(rng, -0.2, 1.7), uniform(rng, -0.2, 1.5));
    const std::optional<InsideHint> hp = sv.hint(B.applyPoint(p));
    if (!hp) continue;
    ++hinted;
    ASSERT_TRUE(strictlyIn(p, hp->tau)) << p.transpose() << " at " << hp->tau;
  }
  EXPECT_GT(hinted, 80);
}

// contains(y, hint) gives contains(y)'s answers: points near hinted points (where the static
// test settles most inside answers), far from them (where it falls back), with hints of the
// wrong time and with hints out of range. Seeded, over the oracle test's meshes and motions.
TEST(Inside, HintedAnswersMatchThePlainOnes) {
  std::mt19937_64 rng(2025);
  const std::vector<Mesh> meshes = {box(V(-0.5, -0.3, -0.2), V(0.5, 0.3, 0.2)), uvSphere(6, 10, 0.6), lShape(0.5),
                                    torus(0.7, 0.25, 10, 6)};
  int hinted = 0, near_inside = 0, compared = 0;
  for (const Mesh& mesh : meshes)
    for (const MotionKind kind :
         {MotionKind::Screw, MotionKind::Translation, MotionKind::Affine, MotionKind::ShearScale, MotionKind::PolySam}) {
      const Motion3 motion = randomMotion(kind, rng);
      const Body body = makeBody(mesh);
      const SweptVolume sv(body, motion);
      const MovingBody mb(mesh, motion);
      V lo, hi;
      sweptBox(mb, lo, hi);
      const double size = (hi - lo).norm();
      for (int n = 0; n < 40; ++n) {
        // (a point of a random face posed at a random time, moved a little: near the surface)
        const auto& f = mesh.f[std::uniform_int_distribution<std::size_t>(0, mesh.f.size() - 1)(rng)];
        const double t = uniform(rng, motion.beginTime(), motion.endTime());
        const V x = motion.pose(t).applyPoint((mesh.v[f[0]] + mesh.v[f[1]] + mesh.v[f[2]]) / 3.0) +
                    0.01 * size * V(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
        const std::optional<InsideHint> h = sv.hint(x);
        if (!h) continue;
        ++hinted;
        for (int k = 0; k < 30; ++k) {
          const double r = size * (k % 3 == 0 ? 1e-3 : k % 3 == 1 ? 2e-2 : 0.3);
          const V q = x + r * V(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
          const bool plain = sv.contains(q);
          ASSERT_EQ(sv.contains(q, *h), plain) << "near a hinted point, radius " << r;
          near_inside += plain;
          ++compared;
        }
        for (const InsideHint& wrong : {InsideHint{h->span, 1.0 - h->tau}, InsideHint{h->span, 0.0},
                                        InsideHint{sv.spanCount(), 0.5}, InsideHint{h->span, -0.5}}) {
          const V q = x + size * 1e-3 * V(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
          ASSERT_EQ(sv.contains(q, wrong), sv.contains(q)) << "hint " << wrong.span << ", " << wrong.tau;
        }
      }
    }
  std::printf("[ info     ] %d hinted points, %d of %d nearby points inside\n", hinted, near_inside, compared);
  EXPECT_GT(hinted, 200);
  EXPECT_GT(near_inside, compared / 4);
  EXPECT_LT(near_inside, compared);
}

// ---- bad input ---------------------------------------------------------------------------------

TEST(Inside, BadInput) {
  const Body body = makeBody(box(V(0, 0, 0), V(1, 1, 1)));
  const Span3 span = Span3::between(Affine3(), Affine3::translation(V(1, 0, 0)));
  const SweptVolume sv(body, span);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const V& x : {V(nan, 0, 0), V(0, inf, 0), V(0, 0, -inf)}) {
    EXPECT_TRUE(throwsError([&] { (void)sv.contains(x); }, ErrorCode::NonFinite, "NaN or infinite"));
    EXPECT_TRUE(throwsError([&] { (void)sv.query(x); }, ErrorCode::NonFinite, "NaN or infinite"));
    EXPECT_TRUE(throwsError([&] { (void)sv.containsAtStart(x); }, ErrorCode::NonFinite, "NaN or infinite"));
    EXPECT_TRUE(throwsError([&] { (void)sv.hint(x); }, ErrorCode::NonFinite, "NaN or infinite"));
    EXPECT_TRUE(throwsError([&] { (void)sv.contains(x, InsideHint{0, 0.5}); }, ErrorCode::NonFinite, "NaN or infinite"));
    EXPECT_TRUE(throwsError([&] { (void)sweptContains(body, span, x); }, ErrorCode::NonFinite, "NaN or infinite"));
  }
  for (const double tol : {0.0, -1e-3, nan, inf}) {
    InsideOptions o;
    o.tolerance = tol;
    EXPECT_TRUE(throwsError([&] { SweptVolume(body, span, o); }, ErrorCode::InvalidArgument, "tolerance must be finite and positive"));
    InsideOptions r;
    r.relative_tolerance = tol;
    EXPECT_TRUE(throwsError([&] { SweptVolume(body, span, r); }, ErrorCode::InvalidArgument, "relative_tolerance"));
  }
  InsideOptions o;
  o.roots.time_tolerance = 0;
  EXPECT_TRUE(throwsError([&] { SweptVolume(body, span, o); }, ErrorCode::InvalidArgument, "time_tolerance"));
}

}  // namespace
