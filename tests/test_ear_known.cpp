// Known answers of the EAR (ear-math.md §7), every case of §3 reached in 2D and 3D, and each
// erratum of the SAM paper (§4) pinned as a regression with literal numbers.

#include "check.hpp"

#include <steady/core/ear.hpp>

#include <gtest/gtest.h>

#include <cmath>

using steady::Affine2;
using steady::Affine3;
using steady::LinearCase;
using steady::TranslationCase;
using steady::testing::matNear;
using steady::testing::near;

namespace {

const double kPi = std::acos(-1.0);
const double kLn2 = std::log(2.0), kLn3 = std::log(3.0);

Eigen::Matrix2d R2(double a) {
  Eigen::Matrix2d R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return R;
}
Eigen::Matrix2d J2() {
  Eigen::Matrix2d J;
  J << 0, -1, 1, 0;
  return J;
}
Eigen::Matrix2d M2(double a, double b, double c, double d) {
  Eigen::Matrix2d m;
  m << a, b, c, d;
  return m;
}
Eigen::Matrix3d M3(std::initializer_list<double> v) {
  Eigen::Matrix3d m;
  auto it = v.begin();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = *it++;
  return m;
}
Affine2 A2(const Eigen::Matrix2d& L, double tx = 0, double ty = 0) { return Affine2(L, {tx, ty}); }
Affine3 A3(const Eigen::Matrix3d& L, const Eigen::Vector3d& t = Eigen::Vector3d::Zero()) {
  return Affine3(L, t);
}

// A^s applied to a point, by the library.
Eigen::Vector2d flow(const Affine2& A, double s, const Eigen::Vector2d& p) {
  return steady::pow(A, s)(p);
}

}  // namespace

// §7.1: B = Rot 90, C = Translate(6, 0).
TEST(EarKnown, RotationThenTranslationMidPose) {
  const Affine2 B = Affine2::rotation(kPi / 2);
  const Affine2 C = Affine2::translation({6, 0});
  const Affine2 A = C * B.inverse();
  const Affine2 X = steady::pow(A, 0.5);
  const double h = 1 / std::sqrt(2.0);
  EXPECT_TRUE(near(X, A2(M2(h, h, -h, h), 3, 3 * std::sqrt(2.0) - 3), 1e-15));
  EXPECT_TRUE(near(X * X * B, C, 1e-15));
  // The SAM passes through X B at t = 1/2.
  EXPECT_TRUE(near(steady::sam(B, 0.5, C), X * B, 1e-15));
}

// Erratum E8: the fixed point of [R(-90) | (6, 0)] is (3, -3) (the paper's A.4 sign is wrong),
// and it stays fixed along the whole SAM.
TEST(EarKnown, E8FixedPointSign) {
  const Affine2 A = A2(R2(-kPi / 2), 6, 0);
  const Eigen::Vector2d q(3, -3);
  EXPECT_TRUE(matNear(A(q), q, 1e-14));
  for (double s : {-1.5, 0.25, 0.5, 2.0}) EXPECT_TRUE(matNear(flow(A, s, q), q, 1e-13)) << s;
  const auto lg = steady::log(A);
  EXPECT_TRUE(matNear(lg.velocity(q), Eigen::Vector2d::Zero(), 1e-14));
  EXPECT_EQ(lg.kase.translation, TranslationCase::FixedPoint);
}

// §7.2 and E7: the half turn -2 1 has the documented counter-clockwise log, and the clockwise
// convention on request.
TEST(EarKnown, HalfTurnMinusTwoIdentity) {
  const Affine2 A = A2(-2 * Eigen::Matrix2d::Identity());
  const auto lg = steady::log(A);
  EXPECT_EQ(lg.kase.linear, LinearCase::HalfTurn);
  EXPECT_TRUE(matNear(lg.M, M2(kLn2, -kPi, kPi, kLn2), 1e-15));
  EXPECT_TRUE(near(steady::pow(A, 1.0), A, 1e-15));
  // Square root: sqrt2 R(+90) (counter-clockwise) or sqrt2 R(-90) (clockwise).
  EXPECT_TRUE(near(steady::pow(A, 0.5), A2(std::sqrt(2.0) * R2(kPi / 2)), 1e-15));
  steady::EarOptions cw;
  cw.half_turn = steady::HalfTurn::Clockwise;
  EXPECT_TRUE(matNear(steady::log(A, cw).M, M2(kLn2, kPi, -kPi, kLn2), 1e-15));
  EXPECT_TRUE(near(steady::pow(A, 0.5, cw), A2(std::sqrt(2.0) * R2(-kPi / 2)), 1e-15));
}

// A rotation by pi computed with cos/sin carries a 1e-16 residue: it must still be a half turn
// (Eigen's logm returns ~0 here).
TEST(EarKnown, HalfTurnFromTrigonometry) {
  const Affine2 A = A2(R2(kPi), 1, 2);
  const auto lg = steady::log(A);
  EXPECT_EQ(lg.kase.linear, LinearCase::HalfTurn);
  EXPECT_TRUE(near(steady::pow(A, 1.0), A, 1e-15));
  const Affine2 h = steady::pow(A, 0.5);
  EXPECT_TRUE(near(h * h, A, 1e-15));
  // Half turn about the fixed point (0.5, 1): the square root is a quarter turn about it.
  EXPECT_TRUE(matNear(h.linear(), R2(kPi / 2), 1e-15));
  EXPECT_TRUE(matNear(h(Eigen::Vector2d(0.5, 1)), Eigen::Vector2d(0.5, 1), 1e-15));
}

// §7.3 and E1/E2: diag(2, 3) (a12 = 0: the paper's formulas divide by zero).
TEST(EarKnown, E2DiagonalNoNaN) {
  const auto lg = steady::log(A2(M2(2, 0, 0, 3)));
  EXPECT_TRUE(matNear(lg.M, M2(kLn2, 0, 0, kLn3), 1e-15));
  EXPECT_EQ(lg.kase.linear, LinearCase::DistinctReal);
}

// E1/E6: upper triangular (c2 c3 = 0 makes the paper's eigenvector matrix singular):
// log [[a, b], [0, c]] = [[ln a, b (ln c - ln a)/(c - a)], [0, ln c]].
TEST(EarKnown, E6UpperTriangular) {
  const auto lg = steady::log(A2(M2(2, 1, 0, 3)));
  EXPECT_TRUE(matNear(lg.M, M2(kLn2, kLn3 - kLn2, 0, kLn3), 1e-15));
  const auto lt = steady::log(A2(M2(2, 0, 1, 3)));
  EXPECT_TRUE(matNear(lt.M, M2(kLn2, 0, kLn3 - kLn2, kLn3), 1e-15));
}

// §7.4, §7.5 and E3: rotations by 90 (r = 0: 0/0 in (15)) and 150 degrees (beyond 90: arctan
// gives the wrong branch).
TEST(EarKnown, E3RotationsBeyondRightAngle) {
  const auto l90 = steady::log(A2(2 * R2(kPi / 2)));
  EXPECT_TRUE(matNear(l90.M, kLn2 * Eigen::Matrix2d::Identity() + kPi / 2 * J2(), 1e-15));
  const auto l150 = steady::log(A2(2 * R2(5 * kPi / 6)));
  EXPECT_TRUE(matNear(l150.M, kLn2 * Eigen::Matrix2d::Identity() + 5 * kPi / 6 * J2(), 1e-15));
  EXPECT_EQ(l150.kase.linear, LinearCase::ComplexPair);
  const auto lm = steady::log(A2(2 * R2(-5 * kPi / 6)));
  EXPECT_TRUE(matNear(lm.M, kLn2 * Eigen::Matrix2d::Identity() - 5 * kPi / 6 * J2(), 1e-15));
}

// §7.6 and E4: double eigenvalue 2 (scalar and Jordan): log = ln2 1 + (L - 2 1)/2.
TEST(EarKnown, E4DoubleEigenvalue) {
  for (const Eigen::Matrix2d& L : {M2(2, 0, 0, 2), M2(2, 1, 0, 2)}) {
    const auto lg = steady::log(A2(L));
    const Eigen::Matrix2d want = kLn2 * Eigen::Matrix2d::Identity() + (L - 2 * Eigen::Matrix2d::Identity()) / 2;
    EXPECT_TRUE(matNear(lg.M, want, 1e-15));
    EXPECT_EQ(lg.kase.linear, LinearCase::DoubleEigenvalue);
  }
}

// E5: two close positive eigenvalues (sqrt d << r).
TEST(EarKnown, E5CloseEigenvalues) {
  // 1 + 1e-10 is stored as 1 + e with e = 1.000000082740371e-10 (exactly representable offset).
  const double e = (1 + 1e-10) - 1;
  const auto lg = steady::log(A2(M2(1, 0, 0, 1 + e)));
  EXPECT_NEAR(lg.M(1, 1), std::log1p(e), 1e-16 * e);
  EXPECT_EQ(lg.M(0, 0), 0.0);
  // log [[a, b], [0, c]] with c = a (1 + f): off-diagonal b log1p(f) / (a f).
  const double c = 3 * (1 + 1e-9), f = (c - 3) / 3;  // c - 3 is exact
  const auto lj = steady::log(A2(M2(3, 5, 0, c)));
  EXPECT_NEAR(lj.M(0, 1), 5 * std::log1p(f) / (3 * f), 1e-15);
}

// §7.7 and E9: the shear with a translation along the generalized eigenvector moves on a
// parabola, and its homogeneous log is [[0, 1, -1/2], [0, 0, 1]].
TEST(EarKnown, E9ShearParabola) {
  const Affine2 A = A2(M2(1, 1, 0, 1), 0, 1);
  const auto lg = steady::log(A);
  EXPECT_TRUE(matNear(lg.M, M2(0, 1, 0, 0), 1e-16));
  EXPECT_TRUE(matNear(lg.u, Eigen::Vector2d(-0.5, 1), 1e-16));
  EXPECT_EQ(lg.kase.translation, TranslationCase::Eigen1Defective);
  for (double s : {-2.0, -0.3, 0.5, 1.0, 1.7, 3.0})
    EXPECT_TRUE(matNear(flow(A, s, Eigen::Vector2d::Zero()), Eigen::Vector2d(s * (s - 1) / 2, s), 1e-14)) << s;
}

// E10: L = [[1, 1], [0, 2]], t = (0, 1). log = [[0, ln2, ln2 - 1], [0, ln2, ln2]] and the velocity
// field M p + u is the time derivative of the trajectory everywhere.
TEST(EarKnown, E10VelocityFieldWithEigenvalueOne) {
  const Affine2 A = A2(M2(1, 1, 0, 2), 0, 1);
  const auto lg = steady::log(A);
  EXPECT_TRUE(matNear(lg.M, M2(0, kLn2, 0, kLn2), 1e-15));
  EXPECT_TRUE(matNear(lg.u, Eigen::Vector2d(kLn2 - 1, kLn2), 1e-15));
  EXPECT_EQ(lg.kase.translation, TranslationCase::Eigen1Semisimple);
  const Eigen::Vector2d p(0.3, -0.7);
  for (double s : {0.0, 0.4, 1.3}) {
    const double h = 1e-5;
    const Eigen::Vector2d v = (flow(A, s + h, p) - flow(A, s - h, p)) / (2 * h);
    EXPECT_TRUE(matNear(v, lg.velocity(flow(A, s, p)), 1e-9)) << s;
  }
}

// §7.8: diag(1, 2) with t = (3, 5): A^s(x, y) = (x + 3s, 2^s (y + 5) - 5).
TEST(EarKnown, MixedTranslationEigenvalueOne) {
  const Affine2 A = A2(M2(1, 0, 0, 2), 3, 5);
  const Eigen::Vector2d p(0.25, -1.5);
  for (double s : {-1.0, 0.3, 0.5, 2.5})
    EXPECT_TRUE(matNear(flow(A, s, p), Eigen::Vector2d(p.x() + 3 * s, std::pow(2.0, s) * (p.y() + 5) - 5), 1e-13));
}

// §7.9: no SAM, with typed errors.
TEST(EarKnown, NoSamCases) {
  for (const Eigen::Matrix2d& L : {M2(-1, 0, 0, -2), M2(-1, 1, 0, -1)}) {
    try {
      steady::log(A2(L));
      ADD_FAILURE() << "no error for\n" << L;
    } catch (const steady::Error& e) {
      EXPECT_EQ(e.code(), steady::ErrorCode::NoRealLog) << e.what();
      EXPECT_NE(std::string(e.what()).find("intermediate pose"), std::string::npos);
    }
    EXPECT_FALSE(steady::realLogExists(A2(L)));
  }
  EXPECT_THROW(steady::log(A3(Eigen::Vector3d(3, -1, -2).asDiagonal())), steady::Error);
  const auto ex = steady::realLogExists(A3(Eigen::Vector3d(3, -1, -2).asDiagonal()));
  EXPECT_FALSE(ex.exists);
  EXPECT_EQ(ex.reason, steady::ErrorCode::NoRealLog);
}

// §7.10: 3D half turn: diag(2 R(180), 3)^(1/2) = diag(sqrt2 R(90), sqrt3) (counter-clockwise
// about +z), and the clockwise convention on request.
TEST(EarKnown, HalfTurn3D) {
  const Affine3 A = A3(Eigen::Vector3d(-2, -2, 3).asDiagonal());
  Eigen::Matrix3d want = Eigen::Matrix3d::Zero();
  want.topLeftCorner<2, 2>() = std::sqrt(2.0) * R2(kPi / 2);
  want(2, 2) = std::sqrt(3.0);
  const auto lg = steady::log(A);
  EXPECT_EQ(lg.kase.linear, LinearCase::HalfTurn);
  EXPECT_TRUE(matNear(steady::pow(A, 0.5).linear(), want, 1e-15));
  steady::EarOptions cw;
  cw.half_turn = steady::HalfTurn::Clockwise;
  want.topLeftCorner<2, 2>() = std::sqrt(2.0) * R2(-kPi / 2);
  EXPECT_TRUE(matNear(steady::pow(A, 0.5, cw).linear(), want, 1e-15));
  // diag(-2, -2, 1): Eigen returns a wrong real log here.
  const Affine3 B = A3(Eigen::Vector3d(-2, -2, 1).asDiagonal(), Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(near(steady::pow(B, 1.0), B, 1e-15));
  const Affine3 hb = steady::pow(B, 0.5);
  EXPECT_TRUE(near(hb * hb, B, 1e-15));
}

// A half turn about a tilted axis, from an exact rotation matrix: the axis sign convention
// (largest coordinate positive) decides the direction of the square root.
TEST(EarKnown, HalfTurnAboutTiltedAxis) {
  const Eigen::Vector3d axis = Eigen::Vector3d(-1, 2, 0.5).normalized();
  const Affine3 A = Affine3::rotation(axis, kPi);
  const Affine3 h = steady::pow(A, 0.5);
  // The canonical axis has its largest coordinate (y) positive: +axis here.
  EXPECT_TRUE(matNear(h.linear(), Affine3::rotation(axis, kPi / 2).linear(), 1e-15));
  EXPECT_TRUE(near(h * h, A, 1e-15));
}

// §7.12: golden spiral. Similarity with scale phi and a quarter turn about q:
// |A^t p - q| = phi^t |p - q| for all t.
TEST(EarKnown, GoldenSpiral) {
  const double phi = (1 + std::sqrt(5.0)) / 2;
  const Eigen::Vector2d q(1, -2);
  const Eigen::Matrix2d L = phi * R2(kPi / 2);
  const Affine2 A(L, q - L * q);
  const Eigen::Vector2d p(4, 1);
  for (double t = -2; t <= 3; t += 0.25)
    EXPECT_NEAR((flow(A, t, p) - q).norm(), std::pow(phi, t) * (p - q).norm(), 1e-13 * std::pow(phi, t)) << t;
}

// --- 3D cases of §3 ----------------------------------------------------------------------------

namespace {
// L = V diag-or-block V^-1 with a known log V Lg V^-1.
struct Known3 {
  Eigen::Matrix3d L, logL;
};
Known3 conjugated(const Eigen::Matrix3d& core, const Eigen::Matrix3d& coreLog) {
  const Eigen::Matrix3d V = M3({1, 0.3, -0.2, 0.1, 1, 0.4, -0.3, 0.2, 1});
  const Eigen::Matrix3d Vi = V.inverse();
  return {V * core * Vi, V * coreLog * Vi};
}
Eigen::Matrix3d block(const Eigen::Matrix2d& b, double z) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  m.topLeftCorner<2, 2>() = b;
  m(2, 2) = z;
  return m;
}
}  // namespace

TEST(EarKnown3D, RealPlusComplexPair) {
  const Known3 k = conjugated(block(1.5 * R2(2.0), 0.5), block(std::log(1.5) * Eigen::Matrix2d::Identity() + 2.0 * J2(), std::log(0.5)));
  const auto lg = steady::log(A3(k.L));
  EXPECT_EQ(lg.kase.linear, LinearCase::ComplexPair);
  EXPECT_TRUE(matNear(lg.M, k.logL, 1e-14));
}

TEST(EarKnown3D, ThreePositiveReals) {
  const Known3 k = conjugated(Eigen::Vector3d(0.5, 2, 5).asDiagonal(),
                              Eigen::Vector3d(std::log(0.5), kLn2, std::log(5.0)).asDiagonal());
  const auto lg = steady::log(A3(k.L));
  EXPECT_EQ(lg.kase.linear, LinearCase::DistinctReal);
  EXPECT_TRUE(matNear(lg.M, k.logL, 1e-14));
}

TEST(EarKnown3D, DoubleEigenvalueScalarAndJordan) {
  // Scalar block 2 1 with a third eigenvalue 5.
  const Known3 s = conjugated(Eigen::Vector3d(2, 2, 5).asDiagonal(),
                              Eigen::Vector3d(kLn2, kLn2, std::log(5.0)).asDiagonal());
  auto lg = steady::log(A3(s.L));
  EXPECT_EQ(lg.kase.linear, LinearCase::DoubleEigenvalue);
  EXPECT_TRUE(matNear(lg.M, s.logL, 1e-14));
  // Jordan block [[2, 1], [0, 2]] with a third eigenvalue 0.5.
  const Known3 j = conjugated(block(M2(2, 1, 0, 2), 0.5), block(M2(kLn2, 0.5, 0, kLn2), std::log(0.5)));
  lg = steady::log(A3(j.L));
  EXPECT_EQ(lg.kase.linear, LinearCase::DoubleEigenvalue);
  EXPECT_TRUE(matNear(lg.M, j.logL, 1e-14));
}

TEST(EarKnown3D, TripleEigenvalueScalingAndShears) {
  // Uniform scaling.
  auto lg = steady::log(A3(3 * Eigen::Matrix3d::Identity()));
  EXPECT_EQ(lg.kase.linear, LinearCase::TripleEigenvalue);
  EXPECT_TRUE(matNear(lg.M, kLn3 * Eigen::Matrix3d::Identity(), 1e-15));
  // One-step nilpotent shear (N^2 = 0) and two-step (N^3 = 0, N^2 != 0):
  // log(2 (1 + N)) = ln2 + N - N^2/2.
  for (const Eigen::Matrix3d& N : {M3({0, 0.7, 0, 0, 0, 0, 0, 0, 0}), M3({0, 1, 0.5, 0, 0, -2, 0, 0, 0})}) {
    const Known3 k = conjugated(2 * (Eigen::Matrix3d::Identity() + N), kLn2 * Eigen::Matrix3d::Identity() + N - N * N / 2);
    lg = steady::log(A3(k.L));
    EXPECT_EQ(lg.kase.linear, LinearCase::TripleEigenvalue);
    EXPECT_TRUE(matNear(lg.M, k.logL, 1e-14));
    // Powers: 2^t (1 + tN + t(t-1)/2 N^2).
    for (double t : {-1.0, 0.5, 2.5}) {
      const Eigen::Matrix3d want = std::pow(2.0, t) * (Eigen::Matrix3d::Identity() + t * N + t * (t - 1) / 2 * N * N);
      const Known3 kw = conjugated(want, want);
      EXPECT_TRUE(matNear(steady::pow(A3(k.L), t).linear(), kw.L, 1e-13)) << t;
    }
  }
}

TEST(EarKnown3D, ScrewIsometry) {
  // Screw about the axis through c with direction z: turn theta, advance d.
  const double theta = 2.5, d = 1.75;
  const Eigen::Vector3d c(1, -1, 0);
  const Affine3 R = Affine3::rotation(Eigen::Vector3d::UnitZ(), theta);
  const Affine3 A = Affine3::translation(c + Eigen::Vector3d(0, 0, d)) * R * Affine3::translation(-c);
  const auto lg = steady::log(A);
  EXPECT_EQ(lg.kase.linear, LinearCase::ComplexPair);
  EXPECT_EQ(lg.kase.translation, TranslationCase::Eigen1Semisimple);
  for (double s : {-0.5, 0.3, 0.5, 1.0, 2.0}) {
    const Affine3 want = Affine3::translation(c + Eigen::Vector3d(0, 0, s * d)) *
                         Affine3::rotation(Eigen::Vector3d::UnitZ(), s * theta) * Affine3::translation(-c);
    EXPECT_TRUE(near(steady::pow(A, s), want, 1e-14)) << s;
  }
}

TEST(EarKnown3D, TranslationCases) {
  // Pure translation: straight line.
  const Affine3 T = Affine3::translation({1, 2, 3});
  auto lg = steady::log(T);
  EXPECT_EQ(lg.kase.translation, TranslationCase::PureTranslation);
  EXPECT_TRUE(near(steady::pow(T, 0.3), Affine3::translation({0.3, 0.6, 0.9}), 1e-15));
  // Eigenvalue 1 semisimple with kernel dimension 2: diag(1, 1, 2) with t = (1, 2, 3).
  const Affine3 S = A3(Eigen::Vector3d(1, 1, 2).asDiagonal(), Eigen::Vector3d(1, 2, 3));
  lg = steady::log(S);
  EXPECT_EQ(lg.kase.translation, TranslationCase::Eigen1Semisimple);
  const Affine3 S5 = steady::pow(S, 0.5);
  EXPECT_TRUE(matNear(S5.translation(), Eigen::Vector3d(0.5, 1, 3 * (std::sqrt(2.0) - 1)), 1e-15));
  // Eigenvalue 1 defective inside a triple eigenvalue: unipotent shear with translation.
  const Affine3 U = A3(M3({1, 1, 0, 0, 1, 1, 0, 0, 1}), Eigen::Vector3d(0, 0, 1));
  lg = steady::log(U);
  EXPECT_EQ(lg.kase.translation, TranslationCase::Eigen1Defective);
  // Trajectory of the origin: z = s, y = s(s-1)/2, x = s(s-1)(s-2)/6.
  for (double s : {-1.0, 0.5, 2.0, 3.0}) {
    const Eigen::Vector3d p = steady::pow(U, s)(Eigen::Vector3d::Zero());
    EXPECT_TRUE(matNear(p, Eigen::Vector3d(s * (s - 1) * (s - 2) / 6, s * (s - 1) / 2, s), 1e-14)) << s;
  }
  // Eigenvalue 1 defective in a 2D block, third eigenvalue 2.
  const Affine3 V = A3(M3({1, 1, 0, 0, 1, 0, 0, 0, 2}), Eigen::Vector3d(0, 1, 1));
  lg = steady::log(V);
  EXPECT_EQ(lg.kase.translation, TranslationCase::Eigen1Defective);
  for (double s : {-1.0, 0.5, 2.0}) {
    const Eigen::Vector3d p = steady::pow(V, s)(Eigen::Vector3d::Zero());
    EXPECT_TRUE(matNear(p, Eigen::Vector3d(s * (s - 1) / 2, s, std::pow(2.0, s) - 1), 1e-14)) << s;
  }
  // No eigenvalue 1: unique fixed point.
  const Affine3 F = A3(Eigen::Vector3d(2, 3, 0.5).asDiagonal(), Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(steady::log(F).kase.translation, TranslationCase::FixedPoint);
}

TEST(EarKnown3D, NegativeJordanBlockHasNoSam) {
  const Affine3 A = A3(block(M2(-1, 1, 0, -1), 2));
  const auto ex = steady::realLogExists(A);
  EXPECT_FALSE(ex.exists);
  EXPECT_EQ(ex.reason, steady::ErrorCode::NoRealLog);
  EXPECT_NE(ex.message.find("Jordan"), std::string::npos) << ex.message;
}

// Span::end() is the end key pose exactly as given, where relative() * start() carries the
// inverse's rounding: after a pose that keeps z, the identity came back with a z row of
// (0, 0, 1 - 1.1e-16), which lifted a sweep's end cap off the plane its faces slide in (a sweep
// fuzz input, tests/fuzz/corpus/sweep/plate_keeps_z_and_back).
TEST(EarKnown3D, SpanEndIsTheKeyPoseAsGiven) {
  Eigen::Matrix3d L;
  L << -0.0625, -6.125, -1, 0.5, 0, 0, 0, 0, 1;
  const Affine3 P(L, Eigen::Vector3d(3.0625, 0, 0));
  const steady::Span3 back = steady::Span3::between(P, Affine3());
  EXPECT_EQ(back.end().matrix(), Affine3().matrix());
  EXPECT_NE((back.relative() * back.start()).matrix(), Affine3().matrix())
      << "the product is exact here now: this test no longer shows why end() exists";
  EXPECT_EQ(steady::Span3::between(Affine3(), P).end().matrix(), P.matrix());
  EXPECT_EQ(steady::Span3(P).end().matrix(), P.matrix());
}
