// Affine value type: composition, inverse, points/vectors/normals, constructors, fitting.

#include "check.hpp"

#include <steady/core/affine.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

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
