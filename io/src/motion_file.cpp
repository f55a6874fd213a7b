// Motion files (JSON): a strict parser that names the JSON path of every fault.

#include <steady/io/motion_file.hpp>

#include <steady/core/error.hpp>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <set>
#include <sstream>
#include <utility>

namespace steady::io {

namespace {

using Json = nlohmann::json;

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x + 0.0);
  return buf;
}

std::string kindOf(const Json& j) {
  switch (j.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::object: return "an object";
    case Json::value_t::array: return "an array";
    case Json::value_t::string: return "a string (" + j.dump() + ")";
    case Json::value_t::boolean: return std::string("a boolean (") + (j.get<bool>() ? "true" : "false") + ")";
    case Json::value_t::binary: return "binary data";
    case Json::value_t::discarded: return "nothing";
    default: return "a number (" + j.dump() + ")";
  }
}

std::string member(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
std::string element(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

// Error reporting: "<source>: <path>: <message>".
class Parser {
 public:
  explicit Parser(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw Error(ErrorCode::InvalidFile, source_ + ": " + (path.empty() ? std::string("(top level)") : path) + ": " + message);
  }

  // nlohmann::json's parser keeps the last of repeated member names and reports numbers too
  // large for a double without a position; this callback tracks the JSON path being parsed so
  // that both are reported with their path.
  Json parse(const std::string& text) {
    struct Frame {
      bool array = false;
      std::size_t index = 0;
      std::string key, path;
      std::set<std::string> keys;
    };
    std::vector<Frame> stack;
    const auto current = [&stack]() -> std::string {  // path of the value being parsed
      if (stack.empty()) return "";
      const Frame& f = stack.back();
      return f.array ? element(f.path, f.index) : member(f.path, f.key);
    };
    const auto finished = [&stack]() {
      if (!stack.empty() && stack.back().array) ++stack.back().index;
    };
    const Json::parser_callback_t callback = [&](int, Json::parse_event_t event, Json& parsed) {
      switch (event) {
        case Json::parse_event_t::object_start:
        case Json::parse_event_t::array_start: {
          Frame f;
          f.array = event == Json::parse_event_t::array_start;
          f.path = current();
          stack.push_back(std::move(f));
          break;
        }
        case Json::parse_event_t::key: {
          Frame& f = stack.back();
          f.key = parsed.get<std::string>();
          if (!f.keys.insert(f.key).second)
            fail(member(f.path, f.key), "member \"" + f.key + "\" appears twice in the same object; keep one");
          break;
        }
        case Json::parse_event_t::object_end:
        case Json::parse_event_t::array_end:
          stack.pop_back();
          finished();
          break;
        case Json::parse_event_t::value:
          finished();
          break;
      }
      return true;
    };
    try {
      return Json::parse(text, callback);
    } catch (const Json::parse_error& e) {
      // Drop the "[json.exception.parse_error.101] " prefix; keep "parse error at line L, column C: ...".
      std::string what = e.what();
      const auto close = what.find("] ");
      if (what.rfind("[json.exception.", 0) == 0 && close != std::string::npos) what = what.substr(close + 2);
      throw Error(ErrorCode::InvalidFile, source_ + ": malformed JSON: " + what);
    } catch (const Json::out_of_range& e) {  // 406: a number beyond the double range
      std::string what = e.what();
      const auto close = what.find("] ");
      if (what.rfind("[json.exception.", 0) == 0 && close != std::string::npos) what = what.substr(close + 2);
      fail(current(), "not a finite number (" + what + ")");
    }
  }

  // The members of an object, each of them known.
  void knownMembers(const Json& j, const std::string& path, std::initializer_list<const char*> names,
                    const std::string& what) const {
    for (const auto& item : j.items()) {
      bool known = false;
      for (const char* n : names) known = known || item.key() == n;
      if (!known) {
        std::string list;
        for (const char* n : names) list += (list.empty() ? "\"" : ", \"") + std::string(n) + "\"";
        fail(member(path, item.key()), "unknown member \"" + item.key() + "\"; the members of " + what + " are " + list +
                                           " (unknown names are errors, so that a misspelt option does not pass unnoticed)");
      }
    }
  }

  double number(const Json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "not a finite number: got " + kindOf(j) + (j.is_null() ? " (JSON has no NaN or infinity)" : ""));
    const double x = j.get<double>();
    if (!std::isfinite(x)) fail(path, "not a finite number");
    return x;
  }

  int integer(const Json& j, const std::string& path, int lo, int hi) const {
    const double x = number(j, path);
    if (x != std::floor(x)) fail(path, num(x) + " is not an integer");
    if (x < lo || x > hi) fail(path, num(x) + " is outside " + std::to_string(lo) + " .. " + std::to_string(hi));
    return static_cast<int>(x);
  }

  std::string string(const Json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "expected a string, got " + kindOf(j));
    return j.get<std::string>();
  }

  Eigen::Vector3d vector3(const Json& j, const std::string& path, const char* what) const {
    if (!j.is_array() || j.size() != 3)
      fail(path, std::string("expected ") + what + ", an array of 3 numbers, got " +
                     (j.is_array() ? "an array of " + std::to_string(j.size()) : kindOf(j)));
    return {number(j[0], element(path, 0)), number(j[1], element(path, 1)), number(j[2], element(path, 2))};
  }

  // --- poses ---

  steady::Affine3 poseFromRows(const Json& j, const std::string& path) const {
    const std::size_t rows = j.size();
    if (rows != 3 && rows != 4)
      fail(path, "expected 3 rows (the 3x4 matrix [L | t]) or 4 (a 4x4 homogeneous matrix), got " + std::to_string(rows));
    Eigen::Matrix4d h = Eigen::Matrix4d::Identity();
    for (std::size_t r = 0; r < rows; ++r) {
      const Json& row = j[r];
      if (!row.is_array())
        fail(path, "row " + std::to_string(r) + " is " + kindOf(row) + ", expected an array of 4 numbers");
      if (row.size() != 4)
        fail(path, "row " + std::to_string(r) + " has " + std::to_string(row.size()) + " entries, expected 4 (" +
                       (rows == 3 ? "the 3x4 matrix [L | t] row by row" : "a 4x4 homogeneous matrix") + ")");
      for (std::size_t c = 0; c < 4; ++c)
        h(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = number(row[c], element(element(path, r), c));
    }
    if (rows == 4 && !(h(3, 0) == 0 && h(3, 1) == 0 && h(3, 2) == 0 && h(3, 3) == 1))
      fail(element(path, 3), "the last row of a homogeneous matrix must be [0, 0, 0, 1], got [" + num(h(3, 0)) + ", " +
                                 num(h(3, 1)) + ", " + num(h(3, 2)) + ", " + num(h(3, 3)) +
                                 "]: a projective map is not an affinity");
    return steady::Affine3(h.topLeftCorner<3, 3>(), h.topRightCorner<3, 1>());
  }

  steady::Affine3 poseFromParts(const Json& j, const std::string& path) const {
    knownMembers(j, path, {"translation", "axis", "angle_deg", "scale"}, "a pose object");
    Eigen::Vector3d translation = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::Zero(), scale = Eigen::Vector3d::Ones();
    double angle_deg = 0.0;
    if (j.contains("translation")) translation = vector3(j["translation"], member(path, "translation"), "a translation");
    if (j.contains("axis")) axis = vector3(j["axis"], member(path, "axis"), "a rotation axis");
    if (j.contains("angle_deg")) angle_deg = number(j["angle_deg"], member(path, "angle_deg"));
    if (j.contains("scale")) {
      const Json& s = j["scale"];
      const std::string sp = member(path, "scale");
      if (s.is_array()) {
        scale = vector3(s, sp, "a scale");
        for (std::size_t k = 0; k < 3; ++k)
          if (!(scale(static_cast<Eigen::Index>(k)) > 0))
            fail(element(sp, k), num(scale(static_cast<Eigen::Index>(k))) +
                                     " is not positive: scale factors must be > 0 (a negative one mirrors the body, 0 flattens it)");
      } else {
        const double s1 = number(s, sp);
        if (!(s1 > 0))
          fail(sp, num(s1) + " is not positive: a scale must be > 0 (a negative one mirrors the body, 0 flattens it)");
        scale.setConstant(s1);
      }
    }
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    if (angle_deg != 0.0) {
      const double n = axis.norm();
      if (!(n > 0))
        fail(j.contains("axis") ? member(path, "axis") : path,
             "angle_deg is " + num(angle_deg) + " but " +
                 (j.contains("axis") ? std::string("the axis is zero") : std::string("there is no \"axis\"")) +
                 "; give a nonzero rotation axis");
      if (!std::isfinite(n)) fail(member(path, "axis"), "the axis is too long to normalise; use a shorter one");
      R = steady::Affine3::rotationDegrees(axis / n, angle_deg).linear();
    }
    // pose = T * R * S: scale in body coordinates, rotate about the body origin, translate.
    return steady::Affine3(R * scale.asDiagonal(), translation);
  }

  steady::Affine3 pose(const Json& j, const std::string& path) const {
    steady::Affine3 P;
    if (j.is_array()) P = poseFromRows(j, path);
    else if (j.is_object()) P = poseFromParts(j, path);
    else
      fail(path, "expected a 3x4 array of rows [[r00, r01, r02, tx], ...], a 4x4 homogeneous array or an object "
                 "{\"translation\", \"axis\", \"angle_deg\", \"scale\"}, got " + kindOf(j));
    if (!P.isFinite()) fail(path, "the pose has entries beyond the double range");
    const double det = P.determinant();
    if (!(det > 0)) {
      if (det < 0)
        fail(path, "det L = " + num(det) + " <= 0: the pose mirrors the body (a reflection), and no motion reaches a "
                   "mirror image; check the sign of a scale or the order of the axes");
      fail(path, "det L = " + num(det) + " <= 0: the pose is singular (it flattens the body); every pose must be invertible");
    }
    try {
      (void)P.inverse();
    } catch (const Error&) {
      fail(path, "det L = " + num(det) + ": the pose is numerically singular (it flattens the body to nearly nothing); "
                 "every pose must be invertible");
    }
    return P;
  }

  // --- the file ---

  MotionFile motion(const Json& root) const {
    if (!root.is_object())
      fail("", "expected a JSON object {\"keyframes\": [...], \"interpolation\": ...}, got " + kindOf(root));
    knownMembers(root, "", {"keyframes", "interpolation", "rounds", "no_sam", "tolerance", "spans", "description"},
                 "a motion file");
    MotionFile out;

    if (root.contains("description")) (void)string(root["description"], "description");

    if (root.contains("interpolation")) {
      const std::string name = string(root["interpolation"], "interpolation");
      if (name == "polysam") out.interpolation = steady::Interpolation::PolySam;
      else if (name == "bezier") out.interpolation = steady::Interpolation::Bezier;
      else if (name == "biarc") out.interpolation = steady::Interpolation::BiArc;
      else if (name == "subdivide") out.interpolation = steady::Interpolation::Subdivide;
      else
        fail("interpolation", "unknown interpolation \"" + name +
                                  "\"; the interpolations are \"polysam\", \"bezier\", \"biarc\" and \"subdivide\"");
    }
    if (root.contains("rounds")) out.rounds = integer(root["rounds"], "rounds", 0, 8);
    if (root.contains("no_sam")) {
      const std::string policy = string(root["no_sam"], "no_sam");
      if (policy == "fail") out.options.no_sam = steady::NoSamPolicy::Fail;
      else if (policy == "split") out.options.no_sam = steady::NoSamPolicy::Split;
      else fail("no_sam", "unknown policy \"" + policy + "\"; it is \"fail\" or \"split\"");
    }
    if (root.contains("tolerance") && root.contains("spans"))
      fail("spans", "give \"tolerance\" or \"spans\", not both (a fixed span count does not control the tolerance)");
    if (root.contains("tolerance")) {
      const double tol = number(root["tolerance"], "tolerance");
      if (!(tol > 0)) fail("tolerance", num(tol) + " is not positive; the pose tolerance is relative to the body size, e.g. 1e-3");
      out.approximation.tolerance = tol;
    }
    if (root.contains("spans"))
      out.approximation.spans = integer(root["spans"], "spans", 1, out.approximation.max_spans);

    if (!root.contains("keyframes"))
      fail("keyframes", "missing: a motion file needs \"keyframes\": [{\"t\": 0, \"pose\": ...}, {\"t\": 1, \"pose\": ...}, ...]");
    const Json& keys = root["keyframes"];
    if (!keys.is_array()) fail("keyframes", "expected an array of keys {\"t\": ..., \"pose\": ...}, got " + kindOf(keys));
    const std::size_t n = keys.size();
    if (n < 2) fail("keyframes", std::to_string(n) + " key(s): a motion needs at least 2");

    bool first_has_t = false;
    for (std::size_t i = 0; i < n; ++i) {
      const Json& key = keys[i];
      const std::string path = element("keyframes", i);
      if (!key.is_object()) fail(path, "expected an object {\"t\": ..., \"pose\": ...}, got " + kindOf(key));
      knownMembers(key, path, {"t", "pose"}, "a key");
      const bool has_t = key.contains("t");
      if (i == 0) first_has_t = has_t;
      if (has_t != first_has_t)
        fail(has_t ? member(path, "t") : path,
             std::string(has_t ? "a time is given here but not in keyframes[0]"
                               : "no \"t\" here but keyframes[0] has one") +
                 "; give \"t\" in every key or in none (then key i is at t = i / (n - 1))");
      steady::Keyframe<3> k;
      k.t = has_t ? number(key["t"], member(path, "t")) : static_cast<double>(i) / static_cast<double>(n - 1);
      if (i > 0 && !(k.t > out.keys.back().t))
        fail(has_t ? member(path, "t") : path,
             num(k.t) + " is not after keyframes[" + std::to_string(i - 1) + "].t = " + num(out.keys.back().t) +
                 ": key times must increase strictly");
      if (!key.contains("pose")) fail(member(path, "pose"), "missing: every key needs a pose");
      k.pose = pose(key["pose"], member(path, "pose"));
      out.keys.push_back(k);
    }

    // Key counts of the kinds (checked again by KeyframeMotion, but without the path).
    if (out.interpolation == steady::Interpolation::BiArc && (n < 3 || n % 2 == 0))
      fail("keyframes", std::to_string(n) + " keys: a \"biarc\" motion needs an odd number of keys, at least 3 "
                                             "(bi-arcs through keys 0-1-2, 2-3-4, ...); add or drop a key");
    if (out.interpolation == steady::Interpolation::Subdivide && out.rounds > 0 && n < 3)
      fail("keyframes", "2 keys: \"subdivide\" with rounds > 0 needs at least 3 keys (with 2 it is the polySAM)");
    return out;
  }

 private:
  std::string source_;
};

}  // namespace

steady::KeyframeMotion<3> MotionFile::motion() const {
  return steady::KeyframeMotion<3>(keys, interpolation, rounds, options);
}

MotionFile parseMotion(const std::string& text, const std::string& source_name) {
  Parser parser(source_name);
  return parser.motion(parser.parse(text));
}

MotionFile readMotionFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw Error(ErrorCode::Io, "cannot read the motion file '" + path + "': it is a directory");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw Error(ErrorCode::Io, "cannot read the motion file '" + path + "': " +
                                   (err ? std::strerror(err) : "cannot open the file") + "; check the path");
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(ErrorCode::Io, "error while reading the motion file '" + path + "'");
  return parseMotion(text.str(), path);
}

}  // namespace steady::io
