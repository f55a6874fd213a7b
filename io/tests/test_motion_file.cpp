// steady::io motion files: the accepted forms, and one test per fault with its JSON path.

#include <steady/io/motion_file.hpp>

#include <steady/core/error.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

using steady::Error;
using steady::ErrorCode;
using steady::io::MotionFile;
using steady::io::parseMotion;

namespace {

const char* const kId = "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]";

std::string twoKeys(const std::string& pose0, const std::string& pose1, const std::string& extra = "") {
  return std::string(R"({"keyframes": [{"t": 0, "pose": )") + pose0 + R"(}, {"t": 1, "pose": )" + pose1 + "}]" + extra + "}";
}

void expectNearPose(const steady::Affine3& got, const steady::Affine3& want, double tol = 1e-14) {
  EXPECT_LT((got.matrix() - want.matrix()).cwiseAbs().maxCoeff(), tol) << "got\n" << got.matrix() << "\nwant\n" << want.matrix();
}

TEST(MotionFile, MatrixPosesWithTimes) {
  const MotionFile m = parseMotion(
      R"({"keyframes": [{"t": -1, "pose": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]},
                        {"t": 3, "pose": [[2, 0, 0, 1], [0, 3, 0, 2], [0, 0, 4, 3]]}],
          "interpolation": "polysam"})",
      "m.json");
  ASSERT_EQ(m.keys.size(), 2u);
  EXPECT_EQ(m.keys[0].t, -1.0);
  EXPECT_EQ(m.keys[1].t, 3.0);
  EXPECT_EQ(m.interpolation, steady::Interpolation::PolySam);
  EXPECT_EQ(m.keys[1].pose.linear().diagonal(), Eigen::Vector3d(2, 3, 4));
  EXPECT_EQ(m.keys[1].pose.translation(), Eigen::Vector3d(1, 2, 3));
  // Defaults.
  EXPECT_EQ(m.rounds, 3);
  EXPECT_EQ(m.options.no_sam, steady::NoSamPolicy::Fail);
  EXPECT_EQ(m.approximation.tolerance, 1e-3);
  EXPECT_EQ(m.approximation.spans, 0);
}

TEST(MotionFile, InterpolationDefaultsToPolySamAndTimesToUnitSpacing) {
  const MotionFile m = parseMotion(std::string(R"({"keyframes": [{"pose": )") + kId + R"(}, {"pose": )" + kId +
                                       R"(}, {"pose": {"translation": [1, 0, 0]}}, {"pose": {}}]})",
                                   "m.json");
  EXPECT_EQ(m.interpolation, steady::Interpolation::PolySam);
  ASSERT_EQ(m.keys.size(), 4u);
  EXPECT_EQ(m.keys[0].t, 0.0);
  EXPECT_DOUBLE_EQ(m.keys[1].t, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(m.keys[2].t, 2.0 / 3.0);
  EXPECT_EQ(m.keys[3].t, 1.0);
}

TEST(MotionFile, AxisAnglePoseEqualsMatrixForm) {
  // T * R * S: scale first, then rotate about the axis through the body origin, then translate.
  const MotionFile a = parseMotion(
      twoKeys(kId, R"({"translation": [1, 2, 3], "axis": [0, 0, 5], "angle_deg": 90, "scale": [2, 3, 4]})"), "a.json");
  const MotionFile b = parseMotion(twoKeys(kId, "[[0, -3, 0, 1], [2, 0, 0, 2], [0, 0, 4, 3]]"), "b.json");
  expectNearPose(a.keys[1].pose, b.keys[1].pose);
  const steady::Affine3 want = steady::Affine3::translation({1, 2, 3}) * steady::Affine3::rotation({0, 0, 1}, M_PI / 2) *
                               steady::Affine3::scaling({2, 3, 4});
  expectNearPose(a.keys[1].pose, want);
}

// "angle_deg" is taken in degrees, so quarter and half turns about a coordinate axis are exact:
// data/motions/screw.json's half turn about z must be diag(-1, -1, 1), not sin(pi) = 1.2e-16
// off it (the noise that tilted the bracket's end cap off the plane of its start cap).
TEST(MotionFile, QuarterAndHalfTurnsInDegreesAreExact) {
  const MotionFile half = parseMotion(twoKeys(kId, R"({"translation": [0, 0, 2], "axis": [0, 0, 1], "angle_deg": 180})"), "h.json");
  EXPECT_EQ(half.keys[1].pose.matrix(), (Eigen::Matrix<double, 3, 4>() << -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 2).finished());
  const MotionFile quarter = parseMotion(twoKeys(kId, R"({"axis": [3, 0, 0], "angle_deg": -270, "scale": 1.5})"), "q.json");
  EXPECT_EQ(quarter.keys[1].pose.matrix(), (Eigen::Matrix<double, 3, 4>() << 1.5, 0, 0, 0, 0, 0, -1.5, 0, 0, 1.5, 0, 0).finished());
}

TEST(MotionFile, PoseObjectDefaultsAndUniformScale) {
  const MotionFile m = parseMotion(twoKeys("{}", R"({"scale": 2, "axis": [1, 0, 0]})"), "m.json");
  expectNearPose(m.keys[0].pose, steady::Affine3());
  expectNearPose(m.keys[1].pose, steady::Affine3::scaling(2.0));
  const MotionFile r = parseMotion(twoKeys("{}", R"({"axis": [1, 1, 1], "angle_deg": 120})"), "m.json");
  // A third of a turn about (1, 1, 1) permutes the axes: x -> y -> z.
  expectNearPose(r.keys[1].pose, steady::Affine3(
                                     (Eigen::Matrix3d() << 0, 0, 1, 1, 0, 0, 0, 1, 0).finished(), Eigen::Vector3d::Zero()),
                 1e-15);
}

TEST(MotionFile, HomogeneousPose) {
  const MotionFile m = parseMotion(twoKeys(kId, "[[1, 0, 0, 5], [0, 1, 0, 6], [0, 0, 1, 7], [0, 0, 0, 1]]"), "m.json");
  EXPECT_EQ(m.keys[1].pose.translation(), Eigen::Vector3d(5, 6, 7));
}

TEST(MotionFile, OptionalMembers) {
  MotionFile m = parseMotion(twoKeys(kId, kId, R"(, "interpolation": "subdivide", "rounds": 0, "no_sam": "split",
                                                  "tolerance": 1e-4, "description": "x")"),
                             "m.json");
  EXPECT_EQ(m.interpolation, steady::Interpolation::Subdivide);
  EXPECT_EQ(m.rounds, 0);
  EXPECT_EQ(m.options.no_sam, steady::NoSamPolicy::Split);
  EXPECT_EQ(m.approximation.tolerance, 1e-4);
  m = parseMotion(twoKeys(kId, kId, R"(, "interpolation": "bezier", "spans": 16, "rounds": 8.0)"), "m.json");
  EXPECT_EQ(m.interpolation, steady::Interpolation::Bezier);
  EXPECT_EQ(m.approximation.spans, 16);
  EXPECT_EQ(m.rounds, 8);
}

TEST(MotionFile, MotionIsTheKeyframeMotion) {
  const MotionFile m = parseMotion(twoKeys(kId, R"({"translation": [6, 0, 0]})"), "m.json");
  const steady::KeyframeMotion3 motion = m.motion();
  EXPECT_EQ(motion.interpolation(), steady::Interpolation::PolySam);
  expectNearPose(motion.pose(0.5), steady::Affine3::translation({3, 0, 0}));
}

TEST(MotionFile, BundledExamples) {
  const std::string dir = std::string(STEADY_DATA_DIR) + "/motions/";
  const MotionFile screw = steady::io::readMotionFile(dir + "screw.json");
  ASSERT_EQ(screw.keys.size(), 2u);
  EXPECT_EQ(screw.interpolation, steady::Interpolation::PolySam);
  const steady::KeyframeMotion3 s = screw.motion();
  // Half way: a quarter turn about z and half the advance.
  expectNearPose(s.pose(0.5), steady::Affine3::translation({0, 0, 1}) * steady::Affine3::rotation({0, 0, 1}, M_PI / 2), 1e-13);
  expectNearPose(s.pose(1.0), screw.keys[1].pose, 1e-13);

  const MotionFile keys = steady::io::readMotionFile(dir + "keys.json");
  EXPECT_GE(keys.keys.size(), 4u);
  EXPECT_EQ(keys.interpolation, steady::Interpolation::BiArc);
  const steady::KeyframeMotion3 k = keys.motion();
  for (const auto& key : keys.keys) expectNearPose(k.pose(key.t), key.pose, 1e-12);
}

TEST(MotionFile, ReadMissingFileIsIo) {
  try {
    steady::io::readMotionFile("/no/such/motion.json");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Io);
    EXPECT_NE(std::string(e.what()).find("/no/such/motion.json"), std::string::npos) << e.what();
  }
}

TEST(MotionFile, ReadFileNamesItInErrors) {
  const std::string path = (std::filesystem::temp_directory_path() / "steady_io_test_bad_motion.json").string();
  {
    std::ofstream out(path);
    out << R"({"keyframes": [{"t": 0, "pose": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]}]})";
  }
  try {
    steady::io::readMotionFile(path);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidFile);
    EXPECT_EQ(std::string(e.what()).rfind(path + ": keyframes: ", 0), 0u) << e.what();
  }
  std::filesystem::remove(path);
}

// --- faults: each is Error(InvalidFile) with "m.json: <path>: <message>" ---

struct Fault {
  const char* name;
  std::string text;
  std::string message_start;  // after "m.json: "
};

class MotionFileFault : public ::testing::TestWithParam<Fault> {};

TEST_P(MotionFileFault, NamesTheJsonPath) {
  const Fault& f = GetParam();
  try {
    (void)parseMotion(f.text, "m.json");
    FAIL() << "no error for " << f.text;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidFile) << e.what();
    const std::string want = "m.json: " + f.message_start;
    EXPECT_EQ(std::string(e.what()).substr(0, want.size()), want) << e.what();
  }
}

const std::string kRow = "[1, 0, 0, 0]";

INSTANTIATE_TEST_SUITE_P(
    Paths, MotionFileFault,
    ::testing::Values(
        Fault{"malformed", "{\"keyframes\": [,]}", "malformed JSON: parse error at line 1, column 16"},
        Fault{"empty", "", "malformed JSON: parse error at line 1, column 1"},
        Fault{"root_array", "[]", "(top level): expected a JSON object"},
        Fault{"missing_keyframes", R"({"interpolation": "polysam"})", "keyframes: missing"},
        Fault{"keyframes_not_array", R"({"keyframes": {}})", "keyframes: expected an array"},
        Fault{"one_key", std::string(R"({"keyframes": [{"pose": )") + kId + "}]}", "keyframes: 1 key(s): a motion needs at least 2"},
        Fault{"key_not_object", std::string(R"({"keyframes": [{"pose": )") + kId + "}, 3]}",
              "keyframes[1]: expected an object {\"t\": ..., \"pose\": ...}, got a number (3)"},
        Fault{"pose_missing", R"({"keyframes": [{"t": 0, "pose": {}}, {"t": 1}]})", "keyframes[1].pose: missing"},
        Fault{"pose_2x4", twoKeys("[[1, 0, 0, 0], [0, 1, 0, 0]]", kId),
              "keyframes[0].pose: expected 3 rows (the 3x4 matrix [L | t]) or 4 (a 4x4 homogeneous matrix), got 2"},
        Fault{"pose_short_row", twoKeys(kId, "[[1, 0, 0, 0], [0, 1, 0], [0, 0, 1, 0]]"),
              "keyframes[1].pose: row 1 has 3 entries, expected 4"},
        Fault{"pose_row_not_array", twoKeys(kId, "[[1, 0, 0, 0], 5, [0, 0, 1, 0]]"),
              "keyframes[1].pose: row 1 is a number (5), expected an array of 4 numbers"},
        Fault{"pose_string", twoKeys(kId, "\"identity\""), "keyframes[1].pose: expected a 3x4 array of rows"},
        Fault{"det_negative", twoKeys(kId, "[[-1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]"), "keyframes[1].pose: det L = -1 <= 0"},
        Fault{"det_zero", twoKeys(kId, "[[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0]]"), "keyframes[1].pose: det L = 0 <= 0"},
        Fault{"numerically_singular", twoKeys(kId, "[[1, 1, 0, 0], [1, 1.0000000000000002, 0, 0], [0, 0, 1, 0]]"),
              "keyframes[1].pose: det L = 2.22045e-16: the pose is numerically singular"},
        Fault{"null_entry", twoKeys("[[1, 0, 0, null], [0, 1, 0, 0], [0, 0, 1, 0]]", kId),
              "keyframes[0].pose[0][3]: not a finite number: got null"},
        Fault{"string_nan", twoKeys(kId, "[[1, 0, 0, 0], [0, 1, 0, \"NaN\"], [0, 0, 1, 0]]"),
              "keyframes[1].pose[1][3]: not a finite number: got a string (\"NaN\")"},
        Fault{"overflow", twoKeys("[[1, 0, 0, 0], [0, 1, 1e999, 0], [0, 0, 1, 0]]", kId),
              "keyframes[0].pose[1][2]: not a finite number"},
        Fault{"overflow_in_object", twoKeys(kId, R"({"translation": [0, -1e400, 0]})"),
              "keyframes[1].pose.translation[1]: not a finite number"},
        Fault{"projective", twoKeys(kId, "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]"),
              "keyframes[1].pose[3]: the last row of a homogeneous matrix must be [0, 0, 0, 1]"},
        Fault{"homogeneous_short_row", twoKeys(kId, "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1]]"),
              "keyframes[1].pose: row 3 has 3 entries, expected 4"},
        Fault{"times_equal", R"({"keyframes": [{"t": 0, "pose": {}}, {"t": 0.5, "pose": {}}, {"t": 0.5, "pose": {}}]})",
              "keyframes[2].t: 0.5 is not after keyframes[1].t = 0.5: key times must increase strictly"},
        Fault{"times_decreasing", R"({"keyframes": [{"t": 1, "pose": {}}, {"t": 0, "pose": {}}]})",
              "keyframes[1].t: 0 is not after keyframes[0].t = 1"},
        Fault{"time_null", R"({"keyframes": [{"t": 0, "pose": {}}, {"t": null, "pose": {}}]})",
              "keyframes[1].t: not a finite number: got null"},
        Fault{"time_missing_in_one", R"({"keyframes": [{"t": 0, "pose": {}}, {"pose": {}}]})",
              "keyframes[1]: no \"t\" here but keyframes[0] has one"},
        Fault{"time_only_in_later", R"({"keyframes": [{"pose": {}}, {"t": 1, "pose": {}}]})",
              "keyframes[1].t: a time is given here but not in keyframes[0]"},
        Fault{"unknown_interpolation", twoKeys(kId, kId, R"(, "interpolation": "linear")"),
              "interpolation: unknown interpolation \"linear\"; the interpolations are \"polysam\", \"bezier\", \"biarc\" and "
              "\"subdivide\""},
        Fault{"interpolation_not_string", twoKeys(kId, kId, R"(, "interpolation": 1)"), "interpolation: expected a string"},
        Fault{"unknown_top_member", twoKeys(kId, kId, R"(, "interpolaton": "bezier")"),
              "interpolaton: unknown member \"interpolaton\"; the members of a motion file are"},
        Fault{"unknown_key_member", R"({"keyframes": [{"time": 0, "pose": {}}, {"pose": {}}]})",
              "keyframes[0].time: unknown member \"time\"; the members of a key are \"t\", \"pose\""},
        Fault{"unknown_pose_member", twoKeys("{}", R"({"axis": [0, 0, 1], "angle": 90})"),
              "keyframes[1].pose.angle: unknown member \"angle\"; the members of a pose object are \"translation\", \"axis\", "
              "\"angle_deg\", \"scale\""},
        Fault{"duplicate_member", R"({"keyframes": [{"t": 0, "t": 1, "pose": {}}, {"pose": {}}]})",
              "keyframes[0].t: member \"t\" appears twice"},
        Fault{"zero_axis", twoKeys("{}", R"({"axis": [0, 0, 0], "angle_deg": 90})"),
              "keyframes[1].pose.axis: angle_deg is 90 but the axis is zero"},
        Fault{"angle_without_axis", twoKeys("{}", R"({"angle_deg": 45})"),
              "keyframes[1].pose: angle_deg is 45 but there is no \"axis\""},
        Fault{"axis_two_numbers", twoKeys("{}", R"({"axis": [0, 1], "angle_deg": 45})"),
              "keyframes[1].pose.axis: expected a rotation axis, an array of 3 numbers, got an array of 2"},
        Fault{"negative_scale", twoKeys("{}", R"({"scale": [1, -1, 1]})"), "keyframes[1].pose.scale[1]: -1 is not positive"},
        Fault{"zero_scale", twoKeys("{}", R"({"scale": 0})"), "keyframes[1].pose.scale: 0 is not positive"},
        Fault{"rounds_range", twoKeys(kId, kId, R"(, "rounds": 9)"), "rounds: 9 is outside 0 .. 8"},
        Fault{"rounds_fraction", twoKeys(kId, kId, R"(, "rounds": 2.5)"), "rounds: 2.5 is not an integer"},
        Fault{"no_sam_value", twoKeys(kId, kId, R"(, "no_sam": "ignore")"), "no_sam: unknown policy \"ignore\""},
        Fault{"tolerance_zero", twoKeys(kId, kId, R"(, "tolerance": 0)"), "tolerance: 0 is not positive"},
        Fault{"spans_zero", twoKeys(kId, kId, R"(, "spans": 0)"), "spans: 0 is outside 1 .. 65536"},
        Fault{"tolerance_and_spans", twoKeys(kId, kId, R"(, "spans": 4, "tolerance": 0.01)"),
              "spans: give \"tolerance\" or \"spans\", not both"},
        Fault{"biarc_even", R"({"keyframes": [{"pose": {}}, {"pose": {}}, {"pose": {}}, {"pose": {}}], "interpolation": "biarc"})",
              "keyframes: 4 keys: a \"biarc\" motion needs an odd number of keys"},
        Fault{"subdivide_two_keys", twoKeys(kId, kId, R"(, "interpolation": "subdivide")"),
              "keyframes: 2 keys: \"subdivide\" with rounds > 0 needs at least 3 keys"},
        Fault{"description_not_string", twoKeys(kId, kId, R"(, "description": 5)"), "description: expected a string"}),
    [](const ::testing::TestParamInfo<Fault>& p) { return std::string(p.param.name); });

TEST(MotionFile, MathFaultsComeFromMotion) {
  // Two keys without a SAM between them (a rotation by more than a half turn is fine, but
  // diag(-1, -2, 1) has two distinct negative eigenvalues): the file is well formed, the
  // motion is not.
  const MotionFile m = parseMotion(twoKeys(kId, "[[-1, 0, 0, 0], [0, -2, 0, 0], [0, 0, 1, 0]]"), "m.json");
  try {
    (void)m.motion();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::NoRealLog) << e.what();
  }
  MotionFile split = m;
  split.options.no_sam = steady::NoSamPolicy::Split;
  EXPECT_NO_THROW((void)split.motion());
}

}  // namespace
