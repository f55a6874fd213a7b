// Affine value type: composition, inverse, points/vectors/normals, constructors, fitting.

#include "check.hpp"

#include <steady/core/affine.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using steady::Affine2;
using steady::Affine3;
using steady::testing::matNear;
using steady::testing::near;

TEST(Affine, CompositionIsFunctionComposition) {
  const Affine3 a = Affine3::rotation(Eigen::Vector3d(1, 2, 3), 0.7) * Affine3::translation({1, 0, -2});
  const Affine3 b = Affine3::scaling(Eigen::Vector3d(2, 0.5, 1.5)) * Affine3::translation({0.3, 0.1, 0});
  const Eigen::Vector3d p(0.2, -1, 4);
  EXPECT_TRUE(matNear((a * b)(p), a(b(p)), 1e-14));
}

TEST(Affine, InverseAndNormals) {
  const Affine3 a(Eigen::Matrix3d{{2, 1, 0}, {0, 1, 0.5}, {0.1, 0, 3}}, Eigen::Vector3d(1, -2, 0.5));
  EXPECT_TRUE(near(a * a.inverse(), Affine3(), 1e-15));
  // A normal stays orthogonal to mapped tangent vectors.
  const Eigen::Vector3d n(0, 0, 1), t1(1, 0, 0), t2(0, 1, 0);
  const Eigen::Vector3d nn = a.applyNormal(n);
  EXPECT_NEAR(nn.dot(a.applyVector(t1)), 0, 1e-14);
  EXPECT_NEAR(nn.dot(a.applyVector(t2)), 0, 1e-14);
  EXPECT_GT(nn.dot(a.applyVector(n)), 0);  // orientation kept (det > 0)
}

TEST(Affine, SingularInverseIsTypedError) {
  const Affine3 a(Eigen::Matrix3d{{1, 2, 3}, {2, 4, 6}, {0, 0, 1}}, Eigen::Vector3d::Zero());
  try {
    a.inverse();
    FAIL();
  } catch (const steady::Error& e) {
    EXPECT_EQ(e.code(), steady::ErrorCode::Singular);
  }
  const Affine3 nan(Eigen::Matrix3d::Identity() * std::nan(""), Eigen::Vector3d::Zero());
  EXPECT_THROW(nan.inverse(), steady::Error);
}

TEST(Affine, HomogeneousRoundTripAndProjectiveRejected) {
  const Affine2 a = Affine2::rotation(0.3) * Affine2::translation({1, 2});
  EXPECT_TRUE(near(Affine2::fromHomogeneous(a.homogeneous()), a, 0));
  EXPECT_TRUE(near(Affine2::fromMatrix(a.matrix()), a, 0));
  Eigen::Matrix3d h = a.homogeneous();
  h(2, 0) = 0.1;
  try {
    Affine2::fromHomogeneous(h);
    FAIL();
  } catch (const steady::Error& e) {
    EXPECT_EQ(e.code(), steady::ErrorCode::InvalidArgument);
  }
}

TEST(Affine, PrimitiveConstructors) {
  const Affine3 r = Affine3::rotation(Eigen::Vector3d::UnitZ(), M_PI / 2);
  EXPECT_TRUE(matNear(r(Eigen::Vector3d(1, 0, 0)), Eigen::Vector3d(0, 1, 0), 1e-15));
  const Affine2 r2 = Affine2::rotation(M_PI / 2);
  EXPECT_TRUE(matNear(r2(Eigen::Vector2d(1, 0)), Eigen::Vector2d(0, 1), 1e-15));
  const Affine3 sh = Affine3::shear(Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 2.0);
  EXPECT_TRUE(matNear(sh(Eigen::Vector3d(0, 1, 0)), Eigen::Vector3d(2, 1, 0), 0));
  EXPECT_NEAR(sh.determinant(), 1.0, 1e-15);
  EXPECT_THROW(Affine3::shear(Eigen::Vector3d::UnitX(), Eigen::Vector3d(1, 1, 0), 1.0), steady::Error);
  EXPECT_THROW(Affine3::rotation(Eigen::Vector3d::Zero(), 1.0), steady::Error);
  EXPECT_THROW(Affine3::rotation(1.0), steady::Error);
}

// Angles in degrees land exactly on the quarter turns: a half turn about z is diag(-1, -1, 1)
// with no 1.2e-16 = sin(pi) off the axis (the sweep's caps at a span's end are posed by such
// key poses; with the noise the bracket's face through the screw axis left a void sliver 3e-17
// thick whose walls crossed after rounding).
TEST(Affine, RotationInDegreesIsExactAtQuarterTurns) {
  const Eigen::Matrix2d quarter2 = (Eigen::Matrix2d() << 0, -1, 1, 0).finished();
  Eigen::Matrix2d want2 = Eigen::Matrix2d::Identity();
  for (int k = 0; k <= 12; ++k, want2 = quarter2 * want2) {
    EXPECT_EQ(Affine2::rotationDegrees(90.0 * k).linear(), want2) << k;
    EXPECT_EQ(Affine2::rotationDegrees(-90.0 * k).linear(), want2.transpose()) << k;
  }
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector3d a = Eigen::Vector3d::Unit(axis);
    // The exact quarter turn about e_axis: e_{axis+1} -> e_{axis+2} -> -e_{axis+1}.
    Eigen::Matrix3d quarter = Eigen::Matrix3d::Zero();
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    quarter(axis, axis) = 1;
    quarter(j, i) = 1;
    quarter(i, j) = -1;
    Eigen::Matrix3d want = Eigen::Matrix3d::Identity();
    for (int k = 0; k <= 12; ++k, want = quarter * want) {
      EXPECT_EQ(Affine3::rotationDegrees(a, 90.0 * k).linear(), want) << axis << " " << k;
      EXPECT_EQ(Affine3::rotationDegrees(-2.5 * a, -90.0 * k).linear(), want) << axis << " " << k;
      EXPECT_EQ(Affine3::rotationDegrees(a, 90.0 * k + 3600.0).linear(), want) << axis << " " << k;
    }
  }
  EXPECT_EQ(Affine3::rotationDegrees(Eigen::Vector3d::UnitZ(), 180).linear(), Eigen::Vector3d(-1, -1, 1).asDiagonal().toDenseMatrix());
}

// Away from the quarter turns the degree form is the radian one up to rounding, on both sides
// of every quadrant border (the reduction switches at +-45 degrees: no jump there), and about a
// coordinate axis both keep that axis's row and column exactly those of the identity.
TEST(Affine, RotationInDegreesAgreesWithRadiansAndKeepsItsAxisExact) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> angle(-1000, 1000), coord(-1, 1);
  std::vector<double> degrees;
  for (int k = -8; k <= 8; ++k)
    for (const double d : {-1e-9, -1e-13, 0.0, 1e-13, 1e-9}) degrees.push_back(45.0 + 90.0 * k + d);
  for (int n = 0; n < 2000; ++n) degrees.push_back(angle(rng));
  constexpr double kRadiansPerDegree = M_PI / 180.0;
  for (const double deg : degrees) {
    const Eigen::Vector3d axis(coord(rng), coord(rng), coord(rng));
    // cos and sin of deg * pi / 180 in radians carry the product's rounding, up to
    // |deg| * 2^-53 * pi / 180 ~ 2e-16 at 1000 degrees; the degree form's is below 1e-16.
    const double tol = 4e-16 + std::abs(deg) * kRadiansPerDegree * 2.3e-16;
    EXPECT_TRUE(matNear(Affine3::rotationDegrees(axis, deg).linear(), Affine3::rotation(axis, deg * kRadiansPerDegree).linear(), tol))
        << deg;
    EXPECT_TRUE(matNear(Affine2::rotationDegrees(deg).linear(), Affine2::rotation(deg * kRadiansPerDegree).linear(), tol)) << deg;
    // Orthonormal to a few units of rounding (the axis' normalisation, three products per
    // entry): over 200,000 such draws both this form and Eigen's AngleAxis reach 1.8e-15.
    const Eigen::Matrix3d R = Affine3::rotationDegrees(axis, deg).linear();
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 4e-15) << deg;
    EXPECT_NEAR(R.determinant(), 1.0, 4e-15) << deg;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
      for (const Eigen::Matrix3d& Q :
           {Affine3::rotationDegrees(e, deg).linear(), Affine3::rotation(e, deg * kRadiansPerDegree).linear()}) {
        EXPECT_EQ(Q.row(k), e.transpose()) << deg << " about " << k;
        EXPECT_EQ(Q.col(k), e) << deg << " about " << k;
      }
    }
  }
  for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    for (const auto& make : {+[](double d) { return Affine3::rotationDegrees(Eigen::Vector3d::UnitX(), d); },
                             +[](double d) { return Affine3::rotation(Eigen::Vector3d::UnitX(), d); }}) {
      try {
        make(bad);
        ADD_FAILURE() << "no error for angle " << bad;
      } catch (const steady::Error& e) {
        EXPECT_EQ(e.code(), steady::ErrorCode::NonFinite);
      }
    }
    EXPECT_THROW(Affine2::rotationDegrees(bad), steady::Error);
  }
}

TEST(Affine, FromPointPairsExactAndLeastSquares) {
  const Affine3 truth(Eigen::Matrix3d{{1.2, 0.1, 0}, {-0.3, 0.9, 0.2}, {0, 0.4, 1.1}}, Eigen::Vector3d(3, -1, 2));
  std::vector<Eigen::Vector3d> from = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, to;
  for (const auto& p : from) to.push_back(truth(p));
  EXPECT_TRUE(near(steady::affineFromPoints<3>(from, to), truth, 1e-14));
  // Least squares: exact data plus symmetric noise that averages out is recovered closely.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0, 1e-3);
  from.clear();
  to.clear();
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d p(noise(rng) * 1e3, noise(rng) * 1e3, noise(rng) * 1e3);
    from.push_back(p);
    to.push_back(truth(p) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  }
  EXPECT_TRUE(near(steady::affineFromPoints<3>(from, to), truth, 1e-3));
  // Coplanar sources are degenerate.
  const std::vector<Eigen::Vector3d> flat = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  try {
    steady::affineFromPoints<3>(flat, flat);
    FAIL();
  } catch (const steady::Error& e) {
    EXPECT_EQ(e.code(), steady::ErrorCode::DegenerateInput);
  }
  EXPECT_THROW(steady::affineFromPoints<3>(flat, {flat[0]}), steady::Error);
}

TEST(Affine, FrameFromPoints) {
  const std::vector<Eigen::Vector3d> s = {{1, 1, 1}, {2, 1, 1}, {1, 3, 1}, {1, 1, 4}};
  const Affine3 f = steady::frameFromPoints<3>(s);
  EXPECT_TRUE(matNear(f.linear(), Eigen::Vector3d(1, 2, 3).asDiagonal().toDenseMatrix(), 0));
  EXPECT_TRUE(matNear(f.translation(), s[0], 0));
}
