// Bad input: every failure is a typed steady::Error whose message names the cause and a remedy;
// the existence queries answer the same without throwing.

#include <steady/core/ear.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using steady::Affine2;
using steady::Affine3;
using steady::ErrorCode;

namespace {

template <class F>
void expectCode(F&& f, ErrorCode code, const char* must_mention) {
  try {
    f();
    ADD_FAILURE() << "no error, expected " << steady::to_string(code);
  } catch (const steady::Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_NE(std::string(e.what()).find(must_mention), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(EarErrors, NaNTest) {
  Affine3 A;
  A.linear()(1, 2) = std::nan("");
  expectCode([&] { steady::log(A); }, ErrorCode::NonFinite, "NaN");
  Affine2 B;
  B.translation()(0) = std::numeric_limits<double>::infinity();
  expectCode([&] { steady::pow(B, 0.5); }, ErrorCode::NonFinite, "infinite");
  expectCode([&] { steady::pow(Affine3(), std::nan("")); }, ErrorCode::NonFinite, "not finite");
  EXPECT_EQ(steady::realLogExists(A).reason, ErrorCode::NonFinite);
}

TEST(EarErrors, ReflectionTest) {
  expectCode([] { steady::log(Affine3(Eigen::Vector3d(-1, 1, 1).asDiagonal(), Eigen::Vector3d::Zero())); },
             ErrorCode::NotOrientationPreserving, "mirror");
  expectCode([] { steady::log(Affine2(Eigen::Vector2d(1, -3).asDiagonal(), Eigen::Vector2d::Zero())); },
             ErrorCode::NotOrientationPreserving, "handedness");
}

TEST(EarErrors, SingularTest) {
  Eigen::Matrix3d L;
  L << 1, 2, 3, 2, 4, 6, 0, 0, 1;
  expectCode([&] { steady::log(Affine3(L, Eigen::Vector3d::Zero())); }, ErrorCode::Singular, "singular");
  expectCode([] { steady::log(Affine2(Eigen::Matrix2d::Zero(), Eigen::Vector2d::Zero())); }, ErrorCode::Singular,
             "singular");
  // A singular start pose for a SAM.
  const Affine3 B(Eigen::Vector3d(1, 1, 0).asDiagonal(), Eigen::Vector3d::Zero());
  expectCode([&] { steady::sam(B, 0.5, Affine3()); }, ErrorCode::Singular, "singular");
  EXPECT_EQ(steady::samExists(B, Affine3()).reason, ErrorCode::Singular);
}

TEST(EarErrors, NoSamTest) {
  // Distinct negative eigenvalues (2D and inside 3D) and a negative Jordan block.
  expectCode([] { steady::log(Affine2(Eigen::Vector2d(-1, -2).asDiagonal(), Eigen::Vector2d::Zero())); },
             ErrorCode::NoRealLog, "intermediate pose");
  Eigen::Matrix3d J;
  J << -1, 1, 0, 0, -1, 0, 0, 0, 2;
  expectCode([&] { steady::log(Affine3(J, Eigen::Vector3d(1, 2, 3))); }, ErrorCode::NoRealLog, "Jordan");
  // SAM query between two poses whose relative motion is a rotation by pi combined with
  // unequal scalings: no SAM, and the query does not throw.
  const Affine3 B;
  const Affine3 C(Eigen::Vector3d(-1, -2, 2).asDiagonal(), Eigen::Vector3d::Zero());
  const auto ex = steady::samExists(B, C);
  EXPECT_FALSE(ex);
  EXPECT_EQ(ex.reason, ErrorCode::NoRealLog);
  EXPECT_FALSE(ex.message.empty());
  EXPECT_TRUE(steady::samExists(B, Affine3::rotation(Eigen::Vector3d::UnitZ(), 3.0)));
}

// Near a half turn: outside the snap radius a rotation by pi - 1e-12 is a rotation (principal
// log, no snapping), and a half turn with slightly unequal scales has no SAM.
TEST(EarErrors, HalfTurnNeighbours) {
  const double a = M_PI - 1e-12;
  Eigen::Matrix2d R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  const auto lg = steady::log(Affine2(R, Eigen::Vector2d::Zero()));
  EXPECT_EQ(lg.kase.linear, steady::LinearCase::ComplexPair);
  EXPECT_NEAR(lg.M(1, 0), a, 1e-12);
  EXPECT_NEAR(steady::log(Affine2(R.transpose(), Eigen::Vector2d::Zero())).M(1, 0), -a, 1e-12);
  expectCode([] { steady::log(Affine2(Eigen::Vector2d(-1, -1 - 1e-9).asDiagonal(), Eigen::Vector2d::Zero())); },
             ErrorCode::NoRealLog, "negative eigenvalues");
}

TEST(EarErrors, ArgumentRanges) {
  expectCode([] { steady::root(Affine3(), 0); }, ErrorCode::InvalidArgument, "at least 1");
  expectCode([] { steady::regularPattern(Affine3(), Affine3(), 0); }, ErrorCode::InvalidArgument, "at least 1");
  const auto pattern = steady::regularPattern(Affine3(), Affine3::translation({4, 0, 0}), 4);
  ASSERT_EQ(pattern.size(), 5u);
  EXPECT_NEAR(pattern[1].translation().x(), 1.0, 1e-15);
  EXPECT_NEAR(pattern[4].translation().x(), 4.0, 1e-15);
}
