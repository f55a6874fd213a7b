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

// The range of the closed forms (found by tests/fuzz/fuzz_ear.cpp): beyond it intermediate
// values overflowed and the log came out as NaN, labelled with a wrong case.
TEST(EarErrors, RangeTest) {
  Eigen::Matrix3d big = Eigen::Matrix3d::Identity();
  big(0, 0) = 5.989737383445046e+129;  // was: NaN log labelled "triple eigenvalue"
  expectCode([&] { steady::log(Affine3(big, Eigen::Vector3d::Zero())); }, ErrorCode::InvalidArgument, "1e30");
  expectCode([] { steady::log(Affine3(Eigen::Matrix3d::Identity() * 1e300, Eigen::Vector3d::Zero())); },
             ErrorCode::InvalidArgument, "other units");  // was: "singular", a wrong cause
  expectCode([] { steady::log(Affine2(Eigen::Matrix2d::Identity(), Eigen::Vector2d(2e30, 0))); },
             ErrorCode::InvalidArgument, "1e30");
  expectCode([] { steady::log(Affine3(Eigen::Vector3d(1, 1e-31, 1).asDiagonal(), Eigen::Vector3d::Zero())); },
             ErrorCode::Singular, "below 1e-30");
  // Just inside: a uniform scaling by 1e30 (|M| = 69).
  const steady::AffineLog3 lg = steady::log(Affine3(Eigen::Matrix3d::Identity() * 1e30, Eigen::Vector3d(1, 2, 3)));
  EXPECT_NEAR(lg.M(0, 0), std::log(1e30), 1e-13);
  EXPECT_NEAR(lg.u(2), 3 * std::log(1e30) / (1e30 - 1), 1e-13 * std::abs(lg.u(2)));
  // Shrinking by more than 1e6: the offsets L - 1 would have lost most digits (1e-20 I was
  // "no positive real eigenvalue", 1e-10 R a log off by 2e-3).
  expectCode([] { steady::log(Affine3(Eigen::Matrix3d::Identity() * 1e-20, Eigen::Vector3d::Zero())); },
             ErrorCode::InvalidArgument, "shrinks");
  expectCode([] { steady::log(Affine2(Eigen::Matrix2d::Identity() * 1e-7, Eigen::Vector2d::Zero())); },
             ErrorCode::InvalidArgument, "below 1e-6");
  EXPECT_EQ(steady::realLogExists(Affine3(big, Eigen::Vector3d::Zero())).reason, ErrorCode::InvalidArgument);
}

// Eigenvalue moduli more than 1e8 apart: the translation part would lose most of its digits
// (diag(2.6e24, 1) gave an infinite u), so the log refuses, in 2D and 3D, and says why.
TEST(EarErrors, StretchRatioTest) {
  expectCode([] { steady::log(Affine2(Eigen::Vector2d(2.5538464940203343e+24, 1).asDiagonal(), Eigen::Vector2d::Zero())); },
             ErrorCode::InvalidArgument, "stretches");
  expectCode([] { steady::log(Affine3(Eigen::Vector3d(1, 1e-9, 1).asDiagonal(), Eigen::Vector3d(1, 1, 1))); },
             ErrorCode::InvalidArgument, "intermediate poses");
  Eigen::Matrix3d near;  // diag(1.6e29, 1.6e29, 1) with tiny off-diagonal entries (fuzzing)
  near << 1.6124169011692078e+29, 1.1827954764425037e-125, 3.0993949621915817e-05, 2.8594869170447748e-304,
      1.6124169011692078e+29, -2.3536706995205933e-185, 0, 0, 1;
  expectCode([&] { steady::log(Affine3(near, Eigen::Vector3d(1, 0, 0))); }, ErrorCode::InvalidArgument, "stretches");
  // A ratio of 1e7 is inside, and the answer is accurate (see PhiInverseOfFarApartEigenvalues).
  EXPECT_NO_THROW(steady::log(Affine3(Eigen::Vector3d(1e7, 1, 1).asDiagonal(), Eigen::Vector3d(1, 1, 1))));
  EXPECT_FALSE(steady::realLogExists(Affine2(Eigen::Vector2d(1e9, 1).asDiagonal(), Eigen::Vector2d::Zero())));
}

// A complex pair next to the negative axis with a large nilpotent part (within rounding of a
// negative Jordan block): the log exists but its entries are about 1e153 and u overflowed to
// NaN; it is refused, consistently with the existence query.
TEST(EarErrors, OverflowingLogTest) {
  Eigen::Matrix2d L;
  const double a = -1.8325506472120096e-06;
  L << a, a, 4.4021010722009483e-313, a;
  const Affine2 A(L, Eigen::Vector2d(a, a));
  expectCode([&] { steady::log(A); }, ErrorCode::InvalidArgument, "overflows");
  expectCode([&] { steady::Span2 s(A); }, ErrorCode::InvalidArgument, "overflows");
  EXPECT_EQ(steady::realLogExists(A).reason, ErrorCode::InvalidArgument);
}
