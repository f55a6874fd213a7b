// pow, sam, demo, motion sample and pattern: read the arguments, call the library, build the
// JSON answer.

#include "commands.hpp"

#include "affinity_io.hpp"

#include <steady/core/motion.hpp>
#include <steady/io/mesh.hpp>
#include <steady/io/motion_file.hpp>

#include <Eigen/Dense>

#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <system_error>
#include <vector>

#ifndef STEADY_DATA_DIR
#define STEADY_DATA_DIR ""
#endif

namespace steady_cli {

namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

template <int D>
Json logJson(const steady::AffineLog<D>& lg) {
  Json m = Json::array();
  for (int r = 0; r < D; ++r) {
    Json row = Json::array();
    for (int c = 0; c < D; ++c) row.push_back(outputNumber(lg.M(r, c)));
    m.push_back(std::move(row));
  }
  Json u = Json::array();
  for (int r = 0; r < D; ++r) u.push_back(outputNumber(lg.u(r)));
  Json out = Json::object();
  out["M"] = std::move(m);
  out["u"] = std::move(u);
  return out;
}

// Huge exponents overflow double precision: report that instead of printing null/inf.
template <int D>
void requireFinite(const steady::Affine<D>& a, const std::string& what) {
  if (!a.isFinite())
    throw steady::Error(steady::ErrorCode::NonFinite,
                        what + " overflows double precision (entries beyond 1.8e308); use a smaller |t|");
}

template <int D>
std::string pow(const std::string& affinity, double t, const steady::EarOptions& options) {
  const steady::Affine<D> A = readAffinity<D>(affinity, "--affinity");
  if (!std::isfinite(t)) throw steady::Error(steady::ErrorCode::NonFinite, "the exponent t is not finite");
  const steady::Span<D> span(A, options);  // one log, reused for the power
  const steady::Affine<D> At = span.power(t);
  requireFinite(At, "A^t");
  Json out = Json::object();
  out["case"] = steady::to_string(span.log().kase);
  out["result"] = matrixJson(At);
  out["log"] = logJson(span.log());
  return formatJson(out);
}

// Rethrows a math error with the name of the object it concerns.
template <class F>
auto withContext(const std::string& context, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const steady::Error& e) {
    throw steady::Error(e.code(), context + e.what());
  }
}

template <int D>
Json samJson(const steady::Affine<D>& B, const steady::Affine<D>& C, std::optional<double> t,
             std::optional<int> steps, const steady::EarOptions& options, steady::AffineLog<D>* log_out) {
  withContext("the start pose B: ", [&] { return B.inverse(); });
  const steady::Span<D> span =
      withContext("the relative motion C B^-1: ", [&] { return steady::Span<D>::between(B, C, options); });
  Json out = Json::object();
  out["case"] = steady::to_string(span.log().kase);
  if (t) {
    const steady::Affine<D> pose = steady::sam(B, *t, C, options);
    requireFinite(pose, "the pose at t");
    out["pose"] = matrixJson(pose);
  } else {
    const std::vector<steady::Affine<D>> poses = steady::regularPattern(B, C, *steps, options);
    Json arr = Json::array();
    for (const auto& p : poses) {
      requireFinite(p, "a pose of the pattern");
      arr.push_back(matrixJson(p));
    }
    out["poses"] = std::move(arr);
  }
  out["log"] = logJson(span.log());
  if (log_out) *log_out = span.log();
  return out;
}

template <int D>
std::string sam(const std::string& from, const std::string& to, std::optional<double> t,
                std::optional<int> steps, const steady::EarOptions& options) {
  // Read both poses before any math, so that a typo is reported as such.
  const steady::Affine<D> B = readAffinity<D>(from, "--from");
  const steady::Affine<D> C = readAffinity<D>(to, "--to");
  return formatJson(samJson<D>(B, C, t, steps, options, nullptr));
}

// --- demo ------------------------------------------------------------------------------------

struct PoseFiles {
  fs::path start, end;
};

// DIR/poses/{start,end}.json, or DIR/{start,end}.json when DIR is the poses folder itself.
std::optional<PoseFiles> posesIn(const fs::path& dir) {
  for (const fs::path& d : {dir / "poses", dir}) {
    std::error_code ec;
    if (fs::is_regular_file(d / "start.json", ec) && fs::is_regular_file(d / "end.json", ec))
      return PoseFiles{d / "start.json", d / "end.json"};
  }
  return std::nullopt;
}

PoseFiles findDemoPoses(const std::string& data_dir) {
  if (!data_dir.empty()) {
    if (auto f = posesIn(data_dir)) return *f;
    throw UsageError("usage", "--data: no poses/start.json and poses/end.json in '" + data_dir +
                                  "' (nor start.json and end.json)");
  }
  // The checkout when run from the repository root, an installed copy next to the binary,
  // then the source tree the binary was built from.
  std::vector<fs::path> candidates{fs::path("data")};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share" / "steady");
  if (std::string(STEADY_DATA_DIR).size() > 0) candidates.push_back(fs::path(STEADY_DATA_DIR));
  std::string looked;
  for (const auto& c : candidates) {
    if (auto f = posesIn(c)) return *f;
    looked += (looked.empty() ? "" : ", ") + c.string();
  }
  throw UsageError("usage", "demo: cannot find the bundled poses (poses/start.json, poses/end.json); looked in " +
                                looked + "; pass --data DIR with the data/ folder of the steady sources");
}

std::string num(double x) {
  if (std::abs(x) < 5e-13) x = 0;  // no "-0" or "1e-17" in the summary
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

std::string vec(const Eigen::Vector3d& v) { return "(" + num(v(0)) + ", " + num(v(1)) + ", " + num(v(2)) + ")"; }

// One line about the motion t -> A^t with log [M | u]: its case, rotation axis and angle,
// fixed point, volume change.
std::string describe(const steady::AffineLog3& lg, int steps) {
  using steady::LinearCase;
  using steady::TranslationCase;
  std::string s = "case " + steady::to_string(lg.kase);
  const Eigen::Matrix3d& M = lg.M;
  const Eigen::Vector3d& u = lg.u;
  if (lg.kase.linear == LinearCase::ComplexPair || lg.kase.linear == LinearCase::HalfTurn) {
    const Eigen::EigenSolver<Eigen::Matrix3d> es(M);
    int k = 0;  // the real eigenvalue: the one with the smallest imaginary part
    for (int i = 1; i < 3; ++i)
      if (std::abs(es.eigenvalues()(i).imag()) < std::abs(es.eigenvalues()(k).imag())) k = i;
    const int j = (k + 1) % 3;
    const double turn = std::abs(es.eigenvalues()(j).imag());  // radians over t in [0, 1]
    const double mu = es.eigenvalues()(k).real();
    Eigen::Vector3d a = es.eigenvectors().col(k).real().normalized();
    int big = 0;
    for (int i = 1; i < 3; ++i)
      if (std::abs(a(i)) > std::abs(a(big))) big = i;
    if (a(big) < 0) a = -a;
    // The axis: the points whose velocity M p + u is along a; p is its point nearest the origin.
    Eigen::Matrix4d K = Eigen::Matrix4d::Zero();
    K.topLeftCorner<3, 3>() = M;
    K.topRightCorner<3, 1>() = a;
    K.bottomLeftCorner<1, 3>() = a.transpose();
    Eigen::Vector4d rhs;
    rhs << -u, 0.0;
    const Eigen::Vector4d x = K.fullPivLu().solve(rhs);
    const double deg = turn * 180.0 / kPi;
    s += "; turns " + num(deg) + " deg (" + num(deg / steps) + " per step) about the axis through " +
         vec(x.head<3>()) + " along " + vec(a) + ", which it stretches by " + num(std::exp(mu));
    if (lg.kase.translation != TranslationCase::FixedPoint) s += " while sliding " + num(-x(3)) + " along it";
  }
  if (lg.kase.translation == TranslationCase::FixedPoint) {
    const Eigen::Vector3d q = M.fullPivLu().solve(-u);
    s += "; fixed point " + vec(q);
  } else if (lg.kase.translation == TranslationCase::PureTranslation) {
    s += "; translation by " + vec(u);
  }
  s += "; volume x" + num(std::exp(M.trace()));
  return s;
}

// --- motion files ------------------------------------------------------------------------------

std::string trimmed(const std::string& s) {
  const char* blanks = " \t\r\n\f\v";
  const auto b = s.find_first_not_of(blanks);
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(blanks) - b + 1);
}

struct LoadedMotion {
  steady::io::MotionFile file;
  std::string source;  // as named in messages
};

// A --motion argument: a path, "-" (standard input), "@path" / "@-" like an affinity argument,
// or inline JSON starting with '{'.
LoadedMotion loadMotion(const std::string& argument) {
  std::string text = trimmed(argument);
  if (text.empty()) throw UsageError("usage", "--motion: empty; give a motion file (JSON, see io/README.md)");
  if (text[0] == '{') return {steady::io::parseMotion(text, "--motion (inline JSON)"), "inline JSON"};
  if (text[0] == '@') text = text.substr(1);
  if (text.empty()) throw UsageError("usage", "--motion: missing file name after '@'");
  if (text == "-") {
    const std::string input((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
    if (std::cin.bad()) throw steady::Error(steady::ErrorCode::Io, "--motion: cannot read standard input");
    return {steady::io::parseMotion(input, "<stdin>"), "standard input"};
  }
  return {steady::io::readMotionFile(text), text};
}

// The motion of a file, with the file named in math errors.
steady::KeyframeMotion3 buildMotion(const LoadedMotion& m) {
  return withContext("the motion of " + m.source + ": ", [&] { return m.file.motion(); });
}

// n times from the first to the last key time, both included (n = 1: the first).
std::vector<double> sampleTimes(const steady::KeyframeMotion3& motion, int n) {
  const double t0 = motion.beginTime(), t1 = motion.endTime();
  std::vector<double> times(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) times[static_cast<std::size_t>(i)] = n == 1 ? t0 : t0 + (t1 - t0) * i / (n - 1);
  if (n > 1) times.back() = t1;
  return times;
}

steady::Affine3 poseAt(const steady::KeyframeMotion3& motion, double t) {
  const steady::Affine3 p = withContext("the pose at t = " + num(t) + ": ", [&] { return motion.pose(t); });
  requireFinite(p, "the pose at t = " + num(t));
  return p;
}

}  // namespace

std::string powCommand(const std::string& affinity, double t, int dim, const steady::EarOptions& options) {
  return dim == 2 ? pow<2>(affinity, t, options) : pow<3>(affinity, t, options);
}

std::string samCommand(const std::string& from, const std::string& to, std::optional<double> t,
                       std::optional<int> steps, int dim, const steady::EarOptions& options) {
  return dim == 2 ? sam<2>(from, to, t, steps, options) : sam<3>(from, to, t, steps, options);
}

DemoOutput demoCommand(const std::string& data_dir, int steps) {
  const PoseFiles files = findDemoPoses(data_dir);
  const std::string from = files.start.string();
  const std::string to = files.end.string();
  const steady::Affine3 B = readAffinity<3>("@" + from, "demo start pose");
  const steady::Affine3 C = readAffinity<3>("@" + to, "demo end pose");
  steady::AffineLog3 lg;
  DemoOutput out;
  out.json = formatJson(samJson<3>(B, C, std::nullopt, steps, steady::EarOptions{}, &lg));
  out.summary = "steady demo: " + std::to_string(steps) + " steps (" + std::to_string(steps + 1) +
                " poses) from " + from + " to " + to + ": " + describe(lg, steps);
  return out;
}

std::string motionSampleCommand(const std::string& motion, int count) {
  if (count < 2) throw UsageError("usage", "--count: at least 2 poses (the first and the last key time)");
  const LoadedMotion loaded = loadMotion(motion);
  const steady::KeyframeMotion3 m = buildMotion(loaded);
  Json poses = Json::array();
  for (const double t : sampleTimes(m, count)) {
    Json item = Json::object();
    item["t"] = outputNumber(t);
    item["pose"] = matrixJson(poseAt(m, t));
    poses.push_back(std::move(item));
  }
  Json out = Json::object();
  out["interpolation"] = steady::to_string(m.interpolation());
  out["poses"] = std::move(poses);
  return formatJson(out);
}

std::string patternCommand(const std::string& motion, int copies, const std::string& mesh,
                           const std::string& output, bool binary) {
  if (copies < 1) throw UsageError("usage", "--copies: at least 1");
  // Everything about the output that can be wrong is reported before any work.
  steady::io::MeshFormat format{};
  try {
    format = steady::io::meshFormatOf(output);
  } catch (const steady::Error& e) {
    throw UsageError("usage", std::string("--output: ") + e.what());
  }
  if (binary && format != steady::io::MeshFormat::Ply && format != steady::io::MeshFormat::Stl)
    throw UsageError("usage", "--binary: binary output is available for .ply and .stl only, not for '" + output + "'");

  const LoadedMotion loaded = loadMotion(motion);
  const steady::io::TriangleMesh body = steady::io::readMesh(mesh);
  const steady::KeyframeMotion3 m = buildMotion(loaded);
  if (body.vertices.size() > static_cast<std::size_t>(INT_MAX) / static_cast<std::size_t>(copies))
    throw UsageError("usage", "--copies: " + std::to_string(copies) + " copies of " + std::to_string(body.vertices.size()) +
                                  " vertices exceed the " + std::to_string(INT_MAX) + " vertices a mesh can index");

  steady::io::TriangleMesh out;
  out.vertices.reserve(body.vertices.size() * static_cast<std::size_t>(copies));
  out.faces.reserve(body.faces.size() * static_cast<std::size_t>(copies));
  for (const double t : sampleTimes(m, copies)) steady::io::append(out, steady::io::transformed(body, poseAt(m, t)));

  steady::io::MeshWriteOptions options;
  options.binary = binary;
  try {
    steady::io::writeMesh(output, out, options);
  } catch (const steady::Error& e) {
    if (e.code() == steady::ErrorCode::Io) throw OutputError(e.what());
    throw;
  }
  return "steady pattern: " + std::to_string(copies) + (copies == 1 ? " copy" : " copies") + " of " + mesh + " (" +
         std::to_string(body.vertices.size()) + " vertices, " + std::to_string(body.faces.size()) + " triangles) along " +
         loaded.source + " (" + steady::to_string(m.interpolation()) + ", t " + num(m.beginTime()) + " .. " +
         num(m.endTime()) + "): " + std::to_string(out.vertices.size()) + " vertices, " +
         std::to_string(out.faces.size()) + " triangles written to " + output +
         (binary ? " (binary)" : "");
}

}  // namespace steady_cli
