// Point/plane contact times along SAM spans: known answers in closed form, the special spans
// (pure translation, scaling, shear with eigenvalue 1, half turn), grazing and sliding contacts,
// bad input, and a seeded property test against an independent 50-digit oracle.
#include <steady/collide/span_roots.hpp>

#include "oracle/hp_oracle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

namespace {

using steady::Affine3;
using steady::ErrorCode;
using steady::ContactRoot;
using steady::Span3;
using steady::SpanRoots;
using V = Eigen::Vector3d;

std::vector<ContactRoot> allRoots(const Span3& span, const V& x0, const V& m, double h, double s0 = 0,
                                double s1 = 1) {
  std::vector<ContactRoot> out;
  SpanRoots(span).pointPlane(x0, m, h, s0, s1, out);
  return out;
}

// The cube-on-slab set-up of the peers' note: a cube of half-size 0.5 starting at (0, 2, 0),
// turned by -theta about the x axis while sliding along x; slab top at z = -1.2. A vertex
// (x, y, z) of the start pose is at z(s) = -y sin(theta s) + z cos(theta s), so its contact
// solves R cos(theta s + a) = -1.2 with R = |(y, z)|, a = atan2(y, z).
double cubeFirstContact(double theta) {
  double best = 2;
  for (double y : {1.5, 2.5})
    for (double z : {-0.5, 0.5}) {
      const double R = std::hypot(y, z), a = std::atan2(y, z);
      const double base = std::acos(-1.2 / R);  // theta s + a = +-base + 2 pi k
      for (int k = -2; k <= 2; ++k)
        for (double sg : {1.0, -1.0}) {
          const double s = (sg * base + 2 * M_PI * k - a) / theta;
          if (s >= 0 && s <= 1) best = std::min(best, s);
        }
    }
  return best;
}

TEST(SpanRoots, CubeOnSlabKnownAnswers) {
  const double expected_note[] = {0.292664, 0.146332, 0.097555};  // peers.md, 6 digits
  int i = 0;
  for (double theta : {1.0, 2.0, 3.0}) {
    const Affine3 B = Affine3::translation(V(0, 2, 0));
    const Affine3 C = Affine3::translation(V(0.7, 0, 0)) * Affine3::rotation(V(1, 0, 0), -theta) * B;
    const SpanRoots solver(Span3::between(B, C));
    double first = 2;
    for (int v = 0; v < 8; ++v) {
      const V p(v & 1 ? 0.5 : -0.5, v & 2 ? 0.5 : -0.5, v & 4 ? 0.5 : -0.5);
      if (auto r = solver.firstPointPlane(B.applyPoint(p), V(0, 0, 1), -1.2)) first = std::min(first, r->t);
    }
    EXPECT_NEAR(first, cubeFirstContact(theta), 1e-12) << "theta " << theta;
    EXPECT_NEAR(first, expected_note[i++], 5e-7) << "theta " << theta;
  }
}

TEST(SpanRoots, PureTranslationIsLinear) {
  const Span3 span(Affine3::translation(V(1, -2, 3)));
  const V x0(0.5, 0.25, -1), m(0.3, -0.4, 1.2);
  const double h = 0.7;
  const double expected = (h - m.dot(x0)) / m.dot(V(1, -2, 3));
  const auto roots = allRoots(span, x0, m, h);
  ASSERT_EQ(roots.size(), 1u);
  EXPECT_NEAR(roots[0].t, expected, 1e-13);
  EXPECT_LE(roots[0].lo, expected + 1e-15);
  EXPECT_GE(roots[0].hi, expected - 1e-15);
  EXPECT_LE(roots[0].hi - roots[0].lo, 1e-12);
  EXPECT_EQ(roots[0].crossing, m.dot(V(1, -2, 3)) > 0 ? 1 : -1);
}

TEST(SpanRoots, ScalingSpanSolvesAnExponential) {
  // x(s) = 2^s x0 about the origin: m.x = h at s = log2(h / m.x0).
  const Span3 span(Affine3::scaling(2.0));
  const V x0(1, 1, 1), m(1, 0, 0);
  const auto roots = allRoots(span, x0, m, 1.5);
  ASSERT_EQ(roots.size(), 1u);
  EXPECT_NEAR(roots[0].t, std::log2(1.5), 1e-13);
  EXPECT_EQ(roots[0].crossing, 1);
}

TEST(SpanRoots, ShearWithEigenvalueOneFollowsAParabola) {
  // L = [[1,1,0],[0,1,0],[0,0,1]], t = (0,1,0): the origin moves on (s(s-1)/2, s, 0) (ear-math
  // §7.7), so x = c holds at s = (1 +- sqrt(1 + 8c)) / 2; over [-1, 2] both roots of c = 0.1.
  Eigen::Matrix3d L = Eigen::Matrix3d::Identity();
  L(0, 1) = 1;
  const Span3 span(Affine3(L, V(0, 1, 0)));
  const double c = 0.1, d = std::sqrt(1 + 8 * c);
  const auto roots = allRoots(span, V::Zero(), V(1, 0, 0), c, -1, 2);
  ASSERT_EQ(roots.size(), 2u);
  EXPECT_NEAR(roots[0].t, (1 - d) / 2, 1e-12);
  EXPECT_NEAR(roots[1].t, (1 + d) / 2, 1e-12);
  EXPECT_EQ(roots[0].crossing, -1);
  EXPECT_EQ(roots[1].crossing, 1);
}

TEST(SpanRoots, HalfTurnSpanFindsBothCrossings) {
  // A half turn about z: (1,0,0) moves on (cos pi s, sin pi s, 0) (counter-clockwise convention),
  // meeting y = 1/2 at s = 1/6 and 5/6.
  const Span3 span(Affine3::rotation(V(0, 0, 1), M_PI));
  const auto roots = allRoots(span, V(1, 0, 0), V(0, 1, 0), 0.5);
  ASSERT_EQ(roots.size(), 2u);
  EXPECT_NEAR(roots[0].t, 1.0 / 6, 1e-12);
  EXPECT_NEAR(roots[1].t, 5.0 / 6, 1e-12);
}

TEST(SpanRoots, GrazingContactIsReportedNotDropped) {
  // (1,0,0) on a quarter turn about z touches the plane x + y = sqrt 2 at s = 1/2 (45 degrees)
  // without crossing it: a double root. Time accuracy of a double root is limited to
  // sqrt(eps_g / g'') ~ 1e-7 by the rounding of g itself.
  const Span3 span(Affine3::rotation(V(0, 0, 1), M_PI / 2));
  const auto roots = allRoots(span, V(1, 0, 0), V(1, 1, 0), std::sqrt(2.0));
  ASSERT_GE(roots.size(), 1u);
  EXPECT_EQ(roots[0].crossing, 0);
  EXPECT_NEAR(roots[0].t, 0.5, 2e-7);
  for (const auto& r : roots) EXPECT_NEAR(r.t, 0.5, 2e-7);
  // Moved off by 1e-6, the plane is never reached (minimum distance 1e-6 >> eps_g).
  EXPECT_TRUE(allRoots(span, V(1, 0, 0), V(1, 1, 0), std::sqrt(2.0) + 1e-6).empty());
}

TEST(SpanRoots, SlidingInThePlaneIsOneContactFromTheStart) {
  const Span3 span(Affine3::translation(V(1, 1, 0)));
  const auto roots = allRoots(span, V(0, 0, 2), V(0, 0, 1), 2.0);
  ASSERT_EQ(roots.size(), 1u);
  EXPECT_EQ(roots[0].crossing, 0);
  EXPECT_EQ(roots[0].lo, 0.0);
  EXPECT_EQ(roots[0].hi, 1.0);
}

TEST(SpanRoots, FirstStopsAtTheEarliest) {
  const Span3 span(Affine3::rotation(V(0, 0, 1), M_PI));
  const SpanRoots solver(span);
  const auto r = solver.firstPointPlane(V(1, 0, 0), V(0, 1, 0), 0.5);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(r->t, 1.0 / 6, 1e-12);
  EXPECT_FALSE(solver.firstPointPlane(V(1, 0, 0), V(0, 1, 0), 1.5).has_value());
  // A sub-range: only the second crossing.
  const auto r2 = solver.firstPointPlane(V(1, 0, 0), V(0, 1, 0), 0.5, 0.5, 1.0);
  ASSERT_TRUE(r2.has_value());
  EXPECT_NEAR(r2->t, 5.0 / 6, 1e-12);
}

TEST(SpanRoots, BadInputGivesTypedErrors) {
  const SpanRoots solver(Span3(Affine3::translation(V(1, 0, 0))));
  auto code = [&](auto f) {
    try {
      f();
    } catch (const steady::Error& e) {
      return e.code();
    }
    return ErrorCode::InvalidFile;  // "no error": a code these calls never produce
  };
  EXPECT_EQ(code([&] { solver.firstPointPlane(V(NAN, 0, 0), V(1, 0, 0), 0); }), ErrorCode::NonFinite);
  EXPECT_EQ(code([&] { solver.firstPointPlane(V(0, 0, 0), V(0, 0, 0), 0); }), ErrorCode::DegenerateInput);
  EXPECT_EQ(code([&] { solver.firstPointPlane(V(0, 0, 0), V(1, 0, 0), 0, 1, 0); }), ErrorCode::InvalidArgument);
  EXPECT_EQ(code([&] { solver.firstPointPlane(V(0, 0, 0), V(1, 0, 0), INFINITY); }), ErrorCode::NonFinite);
}

// ---- independent oracle -------------------------------------------------------------------------

using HP = steady::oracle::HP;
using HMat = steady::oracle::Mat<HP, 4>;

// A contact function of the 4x4 homogeneous pose P = A^s, evaluated in 50 digits.
struct OracleFn {
  HMat X;  // the span's homogeneous log, in 50 digits
  std::function<HP(const HMat&)> g;
  HP at(const HP& s) const { return g(steady::oracle::expm<HP, 4>(s * X)); }
};

// Sign changes of g on a grid of n steps, each refined by 50-digit bisection to 1e-14.
std::vector<double> oracleRoots(const OracleFn& o, int n) {
  std::vector<double> out;
  const HMat step = steady::oracle::expm<HP, 4>(HP(1) / n * o.X);
  HMat P = HMat::identity();
  HP gprev = o.g(P);
  for (int k = 1; k <= n; ++k) {
    P = P * step;
    const HP g = o.g(P);
    if ((g < 0) != (gprev < 0)) {
      HP lo = HP(k - 1) / n, hi = HP(k) / n;
      const bool neg_lo = gprev < 0;
      while (hi - lo > HP(1e-14)) {
        const HP mid = (lo + hi) / 2;
        if ((o.at(mid) < 0) == neg_lo) lo = mid; else hi = mid;
      }
      out.push_back(static_cast<double>((lo + hi) / 2));
    }
    gprev = g;
  }
  return out;
}

// A random span for the oracle tests: log entries uniform in [-1.5, 1.5] (rotations up to about
// 2.6 rad). The span is built from A = exp(X) rounded to double, and the oracle takes the
// 50-digit log of that same double matrix, so both describe exactly the same motion.
Span3 randomSpan(std::mt19937_64& rng, HMat& X) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  HMat Xh = HMat::zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) Xh(i, j) = HP(1.5 * U(rng));
  const HMat Ahp = steady::oracle::expm<HP, 4>(Xh);
  Eigen::Matrix<double, 3, 4> Ad;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) Ad(i, j) = static_cast<double>(Ahp(i, j));
  X = steady::oracle::logm<HP, 4>(steady::oracle::homogeneousFrom<HP, 4>(Ad));
  return Span3(Affine3::fromMatrix(Ad));
}

HP hpDot3(const HP a[3], const HP b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Compares reported roots with the oracle's: every oracle root found within 1e-9, every
// reported crossing an oracle root (two reported roots closer than the grid step are invisible
// to the oracle: allowed as a pair). Returns the oracle root count.
int compareWithOracle(const std::vector<double>& expected, const std::vector<ContactRoot>& got, int trial,
                      int grid, double& worst) {
  for (double t : expected) {
    double best = 1;
    for (const auto& r : got) best = std::min(best, std::abs(r.t - t));
    worst = std::max(worst, best);
    EXPECT_LE(best, 1e-9) << "trial " << trial << ": oracle root " << t << " not found";
  }
  for (const auto& r : got) {
    double best = 1;
    for (double t : expected) best = std::min(best, std::abs(r.t - t));
    if (best > 1e-9 && r.crossing != 0) {
      int near = 0;
      for (const auto& q : got) near += std::abs(q.t - r.t) < 1.0 / grid ? 1 : 0;
      EXPECT_GE(near, 2) << "trial " << trial << ": reported root " << r.t << " is not an oracle root";
    }
  }
  return static_cast<int>(expected.size());
}

// Seeded random spans, points and planes placed so that most cases have contacts.
TEST(SpanRootsOracle, PointPlaneAgreesWithFiftyDigitSampling) {
  std::mt19937_64 rng(8675309);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int total = 0;
  double worst = 0;
  for (int trial = 0; trial < 400; ++trial) {
    OracleFn o;
    const Span3 span = randomSpan(rng, o.X);
    const V x0(2 * U(rng), 2 * U(rng), 2 * U(rng)), m(U(rng), U(rng), U(rng));
    const double h = m.dot(span.power(0.5 + 0.5 * U(rng)).applyPoint(x0)) + 0.3 * U(rng);
    const HP xh[3] = {HP(x0[0]), HP(x0[1]), HP(x0[2])}, mh[3] = {HP(m[0]), HP(m[1]), HP(m[2])};
    const HP hh(h);
    o.g = [&](const HMat& P) {
      HP x[3];
      for (int i = 0; i < 3; ++i) x[i] = P(i, 0) * xh[0] + P(i, 1) * xh[1] + P(i, 2) * xh[2] + P(i, 3);
      return hpDot3(mh, x) - hh;
    };
    total += compareWithOracle(oracleRoots(o, 400), allRoots(span, x0, m, h), trial, 400, worst);
  }
  EXPECT_GT(total, 250);  // the set does exercise contacts
  std::printf("point/plane: oracle roots %d, worst time difference %.3g\n", total, worst);
}

// Seeded random spans and edge pairs placed so that the lines become coplanar during the span.
TEST(SpanRootsOracle, EdgeEdgeAgreesWithFiftyDigitSampling) {
  std::mt19937_64 rng(1234567);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int total = 0;
  double worst = 0;
  for (int trial = 0; trial < 300; ++trial) {
    OracleFn o;
    const Span3 span = randomSpan(rng, o.X);
    const V p0(U(rng), U(rng), U(rng)), p1 = p0 + V(U(rng), U(rng), U(rng));
    // The static edge passes near the moving edge's position at a random time.
    const Affine3 Pm = span.power(0.5 + 0.5 * U(rng));
    const V mid = Pm.applyPoint(0.5 * (p0 + p1)) + 0.2 * V(U(rng), U(rng), U(rng));
    const V dir(U(rng), U(rng), U(rng));
    const V q0 = mid - dir, q1 = mid + dir;
    const HP ph[3] = {HP(p0[0]), HP(p0[1]), HP(p0[2])};
    const HP eh[3] = {HP(p1[0]) - ph[0], HP(p1[1]) - ph[1], HP(p1[2]) - ph[2]};
    const HP qh[3] = {HP(q0[0]), HP(q0[1]), HP(q0[2])};
    const HP dh[3] = {HP(q1[0]) - qh[0], HP(q1[1]) - qh[1], HP(q1[2]) - qh[2]};
    o.g = [&](const HMat& P) {
      HP x[3], e[3];
      for (int i = 0; i < 3; ++i) {
        x[i] = P(i, 0) * ph[0] + P(i, 1) * ph[1] + P(i, 2) * ph[2] + P(i, 3);
        e[i] = P(i, 0) * eh[0] + P(i, 1) * eh[1] + P(i, 2) * eh[2];
      }
      const HP n[3] = {e[1] * dh[2] - e[2] * dh[1], e[2] * dh[0] - e[0] * dh[2], e[0] * dh[1] - e[1] * dh[0]};
      const HP w[3] = {qh[0] - x[0], qh[1] - x[1], qh[2] - x[2]};
      return hpDot3(n, w);
    };
    std::vector<ContactRoot> got;
    SpanRoots(span).edgeEdge(p0, p1, q0, q1, 0, 1, got);
    total += compareWithOracle(oracleRoots(o, 400), got, trial, 400, worst);
  }
  EXPECT_GT(total, 200);
  std::printf("edge/edge: oracle roots %d, worst time difference %.3g\n", total, worst);
}

TEST(SpanRoots, EdgeEdgeKnownAnswer) {
  // A vertical edge at (cos a, sin a) turned a quarter turn about z meets the horizontal line
  // y = 1/2, z = 0 when sin a = 1/2: a = pi/6, s = 1/3. Before that the lines are skew.
  const SpanRoots solver(Span3(Affine3::rotation(V(0, 0, 1), M_PI / 2)));
  std::vector<ContactRoot> roots;
  solver.edgeEdge(V(1, 0, -1), V(1, 0, 1), V(-2, 0.5, 0), V(2, 0.5, 0), 0, 1, roots);
  ASSERT_EQ(roots.size(), 1u);
  EXPECT_NEAR(roots[0].t, 1.0 / 3, 1e-12);
  auto first = solver.firstEdgeEdge(V(1, 0, -1), V(1, 0, 1), V(-2, 0.5, 0), V(2, 0.5, 0));
  ASSERT_TRUE(first.has_value());
  EXPECT_NEAR(first->t, 1.0 / 3, 1e-12);
  // Translating edges: (0,0,0)-(1,0,0) moving by (0,0,2) meets the static line x = 0.5, z = 1
  // (direction y) at s = 1/2.
  const SpanRoots slide(Span3(Affine3::translation(V(0, 0, 2))));
  roots.clear();
  slide.edgeEdge(V(0, 0, 0), V(1, 0, 0), V(0.5, -1, 1), V(0.5, 1, 1), 0, 1, roots);
  ASSERT_EQ(roots.size(), 1u);
  EXPECT_NEAR(roots[0].t, 0.5, 1e-13);
  EXPECT_THROW(slide.edgeEdge(V(0, 0, 0), V(0, 0, 0), V(0, 0, 0), V(1, 0, 0), 0, 1, roots), steady::Error);
}

}  // namespace
