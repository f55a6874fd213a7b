// Invariants of the EAR on seeded random affinities (ear-math.md §7.11) and continuity of the
// results across every internal formula switch.

#include "check.hpp"
#include "support/random_affine.hpp"

#include <steady/core/ear.hpp>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <gtest/gtest.h>

#include <cmath>

using steady::Affine2;
using steady::Affine3;
using steady::testing::near;
using steady::testing::relativeDistance;
using steady::testing::uniform;

namespace {

template <class T>
class Invariants : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(Invariants, Dims);

constexpr int kCount = 400;

}  // namespace

TYPED_TEST(Invariants, SemigroupRootsInverseDeterminant) {
  constexpr int D = TypeParam::value;
  std::mt19937_64 rng(1234 + D);
  for (int i = 0; i < kCount; ++i) {
    const auto A = steady::testing::randomWellPosedAffine<D>(rng);
    const steady::Span<D> span(A);
    const double s = uniform(rng, -2, 2), t = uniform(rng, -2, 2);
    // Semigroup A^s A^t = A^(s+t).
    EXPECT_TRUE(near(span.power(s) * span.power(t), span.power(s + t), 2e-14)) << i;
    // Roots: (A^(1/n))^n = A.
    const int n = 1 + static_cast<int>(rng() % 7);
    const auto r = steady::root(A, n);
    auto acc = r;
    for (int k = 1; k < n; ++k) acc = acc * r;
    EXPECT_TRUE(near(acc, A, 2e-14)) << i << " n=" << n;
    // Inverse: A^(-t) = (A^t)^-1.
    EXPECT_TRUE(near(span.power(-t), span.power(t).inverse(), 2e-14)) << i;
    // det L^t = (det L)^t. A normwise error e of L^t moves det by at most D cond(L^t) e
    // relatively; e <= 2e-15 here.
    const typename steady::Affine<D>::Linear Lt = span.power(t).linear();
    Eigen::JacobiSVD<typename steady::Affine<D>::Linear> svd(Lt);
    const double cond = svd.singularValues()(0) / svd.singularValues()(D - 1);
    EXPECT_NEAR(Lt.determinant(), std::pow(A.determinant(), t),
                D * cond * 2e-15 * std::pow(A.determinant(), t)) << i;
    // t = 0 and t = 1 are the identity and A.
    EXPECT_TRUE(near(span.power(0.0), steady::Affine<D>(), 0)) << i;
    EXPECT_TRUE(near(span.power(1.0), A, 5e-15)) << i;
  }
}

TYPED_TEST(Invariants, AffineInvarianceAndReversibility) {
  constexpr int D = TypeParam::value;
  std::mt19937_64 rng(99 + D);
  for (int i = 0; i < kCount; ++i) {
    const auto FA = steady::testing::randomWellPosedAffine<D>(rng);
    const auto FB = steady::testing::randomWellPosedAffine<D>(rng);
    const auto T = steady::testing::randomWellPosedAffine<D>(rng);
    if (!steady::samExists(FA, FB)) continue;
    const double t = uniform(rng, -1, 2);
    const auto S = steady::sam(FA, t, FB);
    const double scale = 1 + FA.matrix().norm() + FB.matrix().norm();
    auto closeTo = [&](const steady::Affine<D>& a, const steady::Affine<D>& b, double tol) {
      return (a.matrix() - b.matrix()).norm() <= tol * scale * (1 + T.matrix().norm());
    };
    // Left invariance SAM(T FA, t, T FB) = T SAM(FA, t, FB).
    EXPECT_TRUE(closeTo(steady::sam(T * FA, t, T * FB), T * S, 1e-12)) << i;
    // Right invariance SAM(FA T, t, FB T) = SAM(FA, t, FB) T.
    EXPECT_TRUE(closeTo(steady::sam(FA * T, t, FB * T), S * T, 1e-12)) << i;
    // Reversibility SAM(FA, t, FB) = SAM(FB, 1 - t, FA).
    EXPECT_TRUE(closeTo(steady::sam(FB, 1 - t, FA), S, 1e-12)) << i;
  }
}

// A rigid motion's SAM is the screw motion (equal to dual-quaternion ScLERP): built here
// independently from Eigen's angle-axis of R and the screw decomposition of t.
TEST(InvariantsRigid, IsometryIsScrewMotion) {
  std::mt19937_64 rng(5);
  for (int i = 0; i < kCount; ++i) {
    Eigen::Vector3d axis(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    axis.normalize();
    const double angle = uniform(rng, -3.0, 3.0);
    const Eigen::Vector3d t(uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5));
    const Affine3 A(Eigen::AngleAxisd(angle, axis).toRotationMatrix(), t);
    const Eigen::AngleAxisd aa(A.linear());
    const Eigen::Vector3d w = aa.axis();
    const double d = w.dot(t);
    const Eigen::Vector3d tp = t - d * w;
    // Axis point c with (1 - R) c = tp, c orthogonal to w (well posed for angle != 0).
    const Eigen::Matrix3d Mfix = Eigen::Matrix3d::Identity() - A.linear() + w * w.transpose();
    const Eigen::Vector3d c = Mfix.partialPivLu().solve(tp);
    const steady::Span3 span(A);
    for (double s : {-0.7, 0.25, 0.5, 1.3}) {
      const Affine3 screw = Affine3::translation(c + s * d * w) *
                            Affine3::rotation(w, s * aa.angle()) * Affine3::translation(-c);
      const Affine3 got = span.power(s);
      EXPECT_TRUE(near(got, screw, 1e-13)) << i << " s=" << s;
      EXPECT_LE((got.linear().transpose() * got.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    }
  }
}

TEST(InvariantsRigid, SimilarityAndVolumePreservationKept) {
  std::mt19937_64 rng(6);
  for (int i = 0; i < kCount; ++i) {
    Eigen::Vector3d axis(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const double k = std::exp(uniform(rng, -1, 1));
    const Eigen::Matrix3d R = Eigen::AngleAxisd(uniform(rng, -3, 3), axis.normalized()).toRotationMatrix();
    const Affine3 sim(k * R, Eigen::Vector3d(uniform(rng, -2, 2), 0, 1));
    const double t = uniform(rng, -2, 2);
    const Eigen::Matrix3d Lt = steady::pow(sim, t).linear();
    const double kt = std::pow(k, t);
    EXPECT_LE((Lt.transpose() * Lt - kt * kt * Eigen::Matrix3d::Identity()).norm(), 1e-13 * kt * kt) << i;
    // Volume preserving: a random det-1 affinity keeps det 1.
    const auto B = steady::testing::randomWellPosedAffine<3>(rng);
    const Affine3 unimodular(B.linear() / std::cbrt(B.determinant()), B.translation());
    EXPECT_NEAR(steady::pow(unimodular, t).determinant(), 1.0, 1e-13) << i;
  }
}

// Smoothness: along t -> A^t the second differences stay below h^2 |X|^2 |A^t| (X = [M u; 0 0],
// homogeneous Frobenius norms), so no internal switch of formulas leaves a visible jump. The
// switches themselves are checked to rounding level in test_kernels.cpp.
TYPED_TEST(Invariants, PowerIsSmoothInT) {
  constexpr int D = TypeParam::value;
  std::mt19937_64 rng(77 + D);
  for (int i = 0; i < 60; ++i) {
    const auto A = steady::testing::randomWellPosedAffine<D>(rng);
    const steady::Span<D> span(A);
    const double x2 = std::pow(span.log().homogeneous().norm(), 2);
    const double h = 1.0 / 512;
    double worst = 0;
    for (int k = -1536; k <= 1536; ++k) {
      const double t = k * h;
      const typename steady::Affine<D>::Homogeneous d2 = span.power(t + h).homogeneous() - 2 * span.power(t).homogeneous() +
                      span.power(t - h).homogeneous();
      const double bound = h * h * x2 * span.power(t).homogeneous().norm() * 1.01 + 1e-13;
      worst = std::max(worst, d2.norm() / bound);
    }
    EXPECT_LE(worst, 1.0) << i;
  }
}

// Continuity across the borders of the labelled cases: a family crossing each border gives
// results that move by no more than the input does (times a modest factor).
TEST(InvariantsContinuity, AcrossCaseBorders2D) {
  auto logOf = [](const Eigen::Matrix2d& L, const Eigen::Vector2d& t) {
    const auto lg = steady::log(Affine2(L, t));
    Eigen::Matrix<double, 2, 3> m;
    m << lg.M, lg.u;
    return m;
  };
  const Eigen::Vector2d t(0.7, -1.1);
  for (int k = 4; k <= 15; ++k) {
    const double e = std::pow(10.0, -k);
    Eigen::Matrix2d Lp, Lm;
    // Complex pair <-> double eigenvalue <-> two real eigenvalues.
    Lp << 2, 1, e, 2;
    Lm << 2, 1, -e, 2;
    EXPECT_LE((logOf(Lp, t) - logOf(Lm, t)).norm(), 10 * e + 1e-15) << k;
    // Eigenvalue 1 crossing (fixed point <-> eigen1 <-> fixed point).
    Lp << 1 + e, 0.5, 0, 2;
    Lm << 1 - e, 0.5, 0, 2;
    EXPECT_LE((logOf(Lp, t) - logOf(Lm, t)).norm(), 10 * e + 1e-15) << k;
    // Double eigenvalue 1 (shear) <-> near-shear with close eigenvalues.
    Lp << 1 + e, 1, 0, 1 - e;
    Lm << 1, 1, 0, 1;
    EXPECT_LE((logOf(Lp, t) - logOf(Lm, t)).norm(), 10 * e + 1e-15) << k;
  }
}

TEST(InvariantsContinuity, AcrossTripleSeriesBorder3D) {
  // Eigenvalue spread swept through the 2% switch between the series form and the split form.
  const Eigen::Vector3d t(1, -2, 0.5);
  Eigen::Matrix3d V;
  V << 1, 0.4, 0.1, -0.2, 1, 0.3, 0.1, -0.5, 1;
  const Eigen::Matrix3d Vi = V.inverse();
  for (double spread = 0.015; spread <= 0.025; spread += 0.0005) {
    const Eigen::Matrix3d L = V * Eigen::Vector3d(1 + spread, 1, 1 - spread).asDiagonal() * Vi;
    const auto lg = steady::log(Affine3(L, t));
    const Eigen::Matrix3d want = V * Eigen::Vector3d(std::log1p(spread), 0, std::log1p(-spread)).asDiagonal() * Vi;
    EXPECT_LE((lg.M - want).norm(), 1e-15 * 20) << spread;
    const auto p = steady::pow(Affine3(L, t), 0.37);
    EXPECT_LE((p.linear() - V * Eigen::Vector3d(std::pow(1 + spread, 0.37), 1, std::pow(1 - spread, 0.37)).asDiagonal() * Vi).norm(), 1e-14) << spread;
    // Translation: v = M p + u reproduces the derivative of the trajectory at t = 0.
    const Eigen::Vector3d q(0.3, 0.2, -0.1);
    const double h = 1e-6;
    const Eigen::Vector3d v = (steady::pow(Affine3(L, t), h)(q) - steady::pow(Affine3(L, t), -h)(q)) / (2 * h);
    EXPECT_LE((v - lg.velocity(q)).norm(), 1e-8) << spread;
  }
}

// Large exponents: a small rotation lies in the series form (triple eigenvalue within 2%); at
// t = 1e4 its series would need hundreds of terms (it once returned entries of 1e38), so the
// span squares A^(t/2^k) instead. The error may grow like t times the input's rounding.
TEST(InvariantsLargeT, SeriesFormUsesSquaring) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3).normalized();
  for (double angle : {0.01, 1.0}) {
    const Affine3 A(Eigen::AngleAxisd(angle, axis).toRotationMatrix(), Eigen::Vector3d(0.1, 0.2, 0.3));
    const steady::Span3 span(A);
    for (double t : {1e2, 1e4, -1e4}) {
      const Affine3 P = span.power(t);
      const Eigen::Matrix3d R = Eigen::AngleAxisd(angle * t, axis).toRotationMatrix();
      EXPECT_LE((P.linear() - R).norm(), 1e-16 * std::abs(t) * 64) << angle << " " << t;
      EXPECT_LE((P.linear().transpose() * P.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-16 * std::abs(t) * 64);
      // The axis component of the translation advances linearly: (t * d) along the axis.
      EXPECT_NEAR(axis.dot(P.translation()), t * axis.dot(A.translation()), 1e-15 * std::abs(t) * 64);
    }
  }
}

// phi(M)^-1 for a 2D block with real eigenvalues far apart, inverted eigenvalue by eigenvalue:
// diag(x, 1) with t = (1, 1) has u = (ln x / (x - 1), 1). Through the determinant of phi(M) the
// second coordinate lost about log10(x) digits (9e-13 at 1e6, 1.4e-10 at 1e8); the first keeps
// the representation's own loss, about 1e-16 x / ln x.
TEST(EarInvariants, PhiInverseOfFarApartEigenvalues) {
  for (double x : {10.0, 1e3, 1e6, 1e8, 0.1, 1e-3, 1e-6}) {
    const steady::Affine2 A(Eigen::Vector2d(x, 1).asDiagonal(), Eigen::Vector2d(1, 1));
    const steady::AffineLog2 lg = steady::log(A);
    const double u1 = std::log(x) / (x - 1);
    const double scale = std::max(x, 1 / x);
    EXPECT_NEAR(lg.u(1), 1.0, 4e-15) << x;
    EXPECT_NEAR(lg.u(0), u1, 4e-16 * scale / std::abs(std::log(x)) * std::abs(u1) + 1e-15) << x;
    EXPECT_NEAR(lg.M(1, 1), 0.0, 1e-15 * std::abs(std::log(x))) << x;
  }
}

// A rotation scaled by k < 1 (a pose that shrinks): log = ln k 1 + theta [n]x. The 2D block's
// determinant came from the offsets L - 1, which cancel for small k: the log was off by 5.8e-11
// at k = 1e-3 and 3.6e-9 at 1e-4 (3D). From the entries it is within about u / k, times the
// conditioning theta / sin theta of a rotation's log (21 at theta = 3: rounding R's entries
// alone moves it by 6.7e-15 at k = 1).
TEST(EarInvariants, ShrinkingRotationsKeepTheirDigits) {
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, 3).normalized();
  Eigen::Matrix3d K;
  K << 0, -n.z(), n.y(), n.z(), 0, -n.x(), -n.y(), n.x(), 0;
  for (double k : {0.5, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5}) {
    for (double theta : {0.3, 2.0, 3.0}) {
      const double bound = 4e-16 / k * theta / std::sin(theta);
      const Eigen::Matrix3d L = k * Eigen::AngleAxisd(theta, n).toRotationMatrix();
      const Eigen::Matrix3d M = std::log(k) * Eigen::Matrix3d::Identity() + theta * K;
      EXPECT_LE((steady::log(steady::Affine3(L, Eigen::Vector3d(1, 2, 3))).M - M).norm(), bound) << k << " " << theta;
      Eigen::Matrix2d L2, M2;
      L2 << k * std::cos(theta), -k * std::sin(theta), k * std::sin(theta), k * std::cos(theta);
      M2 << std::log(k), -theta, theta, std::log(k);
      EXPECT_LE((steady::log(steady::Affine2(L2, Eigen::Vector2d(1, 2))).M - M2).norm(), bound) << k << " " << theta;
    }
  }
}
