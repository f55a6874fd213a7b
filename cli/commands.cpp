// pow, sam, demo, motion sample, pattern, collide and sweep: read the arguments, call the
// library, build the JSON answer.

#include "commands.hpp"

#include "affinity_io.hpp"

#include <steady/collide/collide.hpp>
#include <steady/core/motion.hpp>
#include <steady/io/mesh.hpp>
#include <steady/io/motion_file.hpp>
#include <steady/sweep/envelope.hpp>
#include <steady/sweep/repair.hpp>

#include <Eigen/Dense>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
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
// or inline JSON starting with '{'. `option` names the option in messages.
LoadedMotion loadMotion(const std::string& argument, const std::string& option = "--motion") {
  std::string text = trimmed(argument);
  if (text.empty()) throw UsageError("usage", option + ": empty; give a motion file (JSON, see io/README.md)");
  if (text[0] == '{') return {steady::io::parseMotion(text, option + " (inline JSON)"), "inline JSON"};
  if (text[0] == '@') text = text.substr(1);
  if (text.empty()) throw UsageError("usage", option + ": missing file name after '@'");
  if (text == "-") {
    const std::string input((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
    if (std::cin.bad()) throw steady::Error(steady::ErrorCode::Io, option + ": cannot read standard input");
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

// --- collide -----------------------------------------------------------------------------------

// Whether a --motion argument reads standard input.
bool readsStdin(const std::string& argument) {
  const std::string text = trimmed(argument);
  return text == "-" || text == "@-";
}

// A mesh for the contact queries, with the name used in messages and summaries.
struct CollideBody {
  steady::io::TriangleMesh mesh;
  std::string path;
};

// The checks the contact queries make on a mesh (steady::StaticScene and the two-body queries
// throw DegenerateInput, NonFinite or InvalidArgument; collide/src/collide.cpp, checkMesh, with
// the same zero-area test), made here first so that a mesh collide cannot use is reported with
// its file as bad input (exit status 2), not as a math error. readMesh() has rejected files
// without triangles, non-finite coordinates and corner indices out of range already; these
// checks are kept as a safety net.
CollideBody readCollideMesh(const std::string& path, const std::string& option) {
  CollideBody body{steady::io::readMesh(path), path};
  const auto& V = body.mesh.vertices;
  const auto& F = body.mesh.faces;
  const std::string where = option + " '" + path + "': ";
  if (V.empty() || F.empty())
    throw UsageError(steady::to_string(steady::ErrorCode::DegenerateInput), where + "the mesh has no triangle");
  for (std::size_t i = 0; i < V.size(); ++i)
    if (!V[i].allFinite())
      throw UsageError(steady::to_string(steady::ErrorCode::NonFinite),
                       where + "vertex " + std::to_string(i) + " is not finite");
  for (std::size_t f = 0; f < F.size(); ++f) {
    for (const int k : F[f])
      if (k < 0 || static_cast<std::size_t>(k) >= V.size())
        throw UsageError(steady::to_string(steady::ErrorCode::InvalidFile),
                         where + "triangle " + std::to_string(f) + " refers to vertex " + std::to_string(k) +
                             ", but there are " + std::to_string(V.size()) + " vertices");
    const Eigen::Vector3d e1 = V[static_cast<std::size_t>(F[f][1])] - V[static_cast<std::size_t>(F[f][0])];
    const Eigen::Vector3d e2 = V[static_cast<std::size_t>(F[f][2])] - V[static_cast<std::size_t>(F[f][0])];
    if (!(e1.cross(e2).norm() > 1e-14 * (e1.squaredNorm() + e2.squaredNorm())))
      throw UsageError(steady::to_string(steady::ErrorCode::DegenerateInput),
                       where + "triangle " + std::to_string(f) + " (vertices " + std::to_string(F[f][0]) + ", " +
                           std::to_string(F[f][1]) + ", " + std::to_string(F[f][2]) +
                           ") has zero area (collinear or repeated corners); contact needs a plane for every "
                           "triangle: remove it or repair the mesh");
  }
  return body;
}

// The motion of a file as SAM spans for a body: exact for polysam and subdivide, within the
// file's tolerance (relative to the body's box diagonal) for the curved kinds.
steady::Motion3 spansOf(const steady::KeyframeMotion3& motion, const LoadedMotion& loaded, const CollideBody& body) {
  return withContext("the motion of " + loaded.source + ": ", [&] {
    return motion.toMotion(steady::Box<3>::of(body.mesh.vertices), loaded.file.approximation);
  });
}

Json vectorJson(const Eigen::Vector3d& v) {
  Json a = Json::array();
  for (int i = 0; i < 3; ++i) a.push_back(outputNumber(v(i)));
  return a;
}

// A feature: a vertex or face index, or [i, j] for an edge.
Json featureJson(const std::array<int, 2>& f) {
  if (f[1] < 0) return Json(f[0]);
  return Json::array({f[0], f[1]});
}

Json contactJson(const steady::Contact& c) {
  Json out = Json::object();
  out["t"] = outputNumber(c.t);
  out["t_latest"] = outputNumber(c.t_latest);
  out["span"] = c.span;
  out["span_time"] = outputNumber(c.span_time);
  Json features = Json::object();
  features["type"] = steady::to_string(c.type);
  features["moving"] = featureJson(c.a);
  features["static"] = featureJson(c.b);
  out["features"] = std::move(features);
  out["point"] = vectorJson(c.point);
  out["normal"] = vectorJson(c.normal);
  out["crossing"] = c.crossing;
  out["certain"] = c.certain;
  return out;
}

void addClearance(Json& out, const steady::Clearance& c) {
  out["clearance"] = outputNumber(c.upper);
  out["clearance_bounds"] = Json::array({outputNumber(c.lower), outputNumber(c.upper)});
  out["clearance_t"] = outputNumber(c.t);
  Json closest = Json::object();
  closest["moving"] = vectorJson(c.point_a);
  closest["static"] = vectorJson(c.point_b);
  out["closest"] = std::move(closest);
}

std::string triangles(const CollideBody& body) {
  const std::size_t n = body.mesh.faces.size();
  return std::to_string(n) + (n == 1 ? " triangle" : " triangles");
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

CollideOutput collideCommand(const CollideRequest& request) {
  const bool two_moving = !request.against_motion.empty();
  if (two_moving && readsStdin(request.motion) && readsStdin(request.against_motion))
    throw UsageError("usage", "--motion and --against-motion cannot both read standard input");
  // Files first (unreadable input is exit status 2), then the math of the motions.
  const LoadedMotion loaded = loadMotion(request.motion);
  std::optional<LoadedMotion> loaded_b;
  if (two_moving) loaded_b = loadMotion(request.against_motion, "--against-motion");
  const CollideBody a = readCollideMesh(request.moving, "MOVING");
  const CollideBody b = readCollideMesh(request.against, "--against");
  const steady::KeyframeMotion3 keys_a = buildMotion(loaded);
  std::optional<steady::KeyframeMotion3> keys_b;
  if (two_moving) keys_b.emplace(buildMotion(*loaded_b));
  double t0 = keys_a.beginTime(), t1 = keys_a.endTime();
  if (keys_b) {
    t0 = std::max(t0, keys_b->beginTime());
    t1 = std::min(t1, keys_b->endTime());
    if (!(t1 > t0))
      throw UsageError("usage", "--against-motion: the motions share no time: " + loaded.source + " runs over t " +
                                    num(keys_a.beginTime()) + " .. " + num(keys_a.endTime()) + ", " +
                                    loaded_b->source + " over t " + num(keys_b->beginTime()) + " .. " +
                                    num(keys_b->endTime()));
  }
  const steady::Motion3 motion_a = spansOf(keys_a, loaded, a);
  std::optional<steady::Motion3> motion_b;
  if (keys_b) motion_b.emplace(spansOf(*keys_b, *loaded_b, b));

  const auto& Va = a.mesh.vertices;
  const auto& Fa = a.mesh.faces;
  const auto& Vb = b.mesh.vertices;
  const auto& Fb = b.mesh.faces;
  std::optional<steady::StaticScene> scene;
  if (!two_moving) scene.emplace(Vb, Fb);
  auto contacts = [&]() -> std::vector<steady::Contact> {
    if (scene) return scene->contacts(Va, Fa, motion_a);
    return steady::contacts({Va, Fa, motion_a}, {Vb, Fb, *motion_b});
  };
  auto first = [&]() -> std::optional<steady::Contact> {
    if (scene) return scene->firstContact(Va, Fa, motion_a);
    return steady::firstContact({Va, Fa, motion_a}, {Vb, Fb, *motion_b});
  };
  auto clearance = [&]() -> steady::Clearance {
    if (scene) return scene->clearance(Va, Fa, motion_a);
    return steady::clearance({Va, Fa, motion_a}, {Vb, Fb, *motion_b});
  };

  std::vector<steady::Contact> found;
  if (request.all) {
    found = contacts();
  } else if (auto c = first()) {
    found.push_back(*c);
  }
  std::optional<steady::Clearance> gap;
  if (found.empty()) gap = clearance();

  Json out = Json::object();
  out["contact"] = !found.empty();
  if (request.all) {
    Json list = Json::array();
    for (const auto& c : found) list.push_back(contactJson(c));
    out["contacts"] = std::move(list);
  } else if (!found.empty()) {
    const Json first_contact = contactJson(found.front());
    for (const auto& item : first_contact.items()) out[item.key()] = item.value();
  }
  if (gap) addClearance(out, *gap);

  const std::string between = " between " + a.path + " (" + triangles(a) + ") along " + loaded.source + " and " +
                              b.path + " (" + triangles(b) + (two_moving ? ") along " + loaded_b->source : ", static)");
  std::string summary = "steady collide: ";
  if (gap) {
    summary += "no contact" + between + " over t " + num(t0) + " .. " + num(t1) + "; clearance " + num(gap->upper) +
               " at t = " + num(gap->t) + " (the minimum lies in [" + num(gap->lower) + ", " + num(gap->upper) + "])";
  } else if (!request.all) {
    const steady::Contact& c = found.front();
    summary += "first contact at t = " + num(c.t) + " (" + steady::to_string(c.type) + ", span " +
               std::to_string(c.span) + ")" + between;
  } else {
    summary += std::to_string(found.size()) + (found.size() == 1 ? " contact" : " contacts") + " from t = " +
               num(found.front().t) + " to " + num(found.back().t) + between;
  }
  return {formatJson(out), summary};
}

// --- sweep -------------------------------------------------------------------------------------

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Before any work: the directory of an output file exists and is writable, and the path is
// not a directory, so that a long sweep does not end in a write error.
void checkOutputPath(const std::string& path, const std::string& what) {
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string name = "cannot write " + what + " '" + path + "': ";
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw OutputError(name + "the directory '" + dir.string() + "' does not exist (nothing was computed or written)");
  if (fs::is_directory(target, ec)) throw OutputError(name + "it is a directory (nothing was computed or written)");
  if (::access(dir.c_str(), W_OK) != 0) {
    const int err = errno;
    throw OutputError(name + "the directory '" + dir.string() + "' is not writable: " + std::strerror(err) +
                      " (nothing was computed or written)");
  }
}

std::atomic<unsigned> pending_counter{0};

// A text file written in full to a new temporary file next to `path` (flushed to disk) and
// renamed to `path` by commit(); removed if it is never committed.
class PendingFile {
 public:
  PendingFile(const std::string& path, const std::string& text, const std::string& what)
      : path_(path), what_(what) {
    const fs::path target(path);
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    int fd = -1;
    for (int attempt = 0; fd < 0 && attempt < 100; ++attempt) {
      temp_ = (dir / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                      std::to_string(pending_counter++)))
                  .string();
      fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd < 0 && errno != EEXIST) fail(errno, "creating a file next to");
    }
    if (fd < 0) fail(EEXIST, "finding a free temporary name next to");
    live_ = true;
    std::size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        const int err = n < 0 ? errno : EIO;
        ::close(fd);
        fail(err, "writing");
      }
      done += static_cast<std::size_t>(n);
    }
    if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
      const int err = errno;
      ::close(fd);
      fail(err, "flushing");
    }
    if (::close(fd) != 0) fail(errno, "closing");
  }
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;
  ~PendingFile() {
    if (live_) ::unlink(temp_.c_str());
  }
  void commit() {
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail(errno, "renaming the finished file to");
    live_ = false;
  }

 private:
  [[noreturn]] void fail(int err, const std::string& doing) {
    if (live_) ::unlink(temp_.c_str());
    live_ = false;
    throw OutputError("cannot write " + what_ + " '" + path_ + "': error while " + doing + " it: " +
                      std::strerror(err) + " (nothing was written)");
  }

  std::string path_, what_, temp_;
  bool live_ = false;
};

// SIGINT and SIGTERM while `steady sweep` runs (see sweepCommand in commands.hpp): the handler
// sets the sweep's cancel flag (a lock-free atomic: safe in a handler) and gives the signal its
// default action back, so that a second one ends the process at once.
std::atomic<bool> sweep_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler stores to sweep_interrupted");
volatile std::sig_atomic_t sweep_signal = 0;
extern "C" void onSweepSignal(int sig) {
  sweep_signal = sig;
  sweep_interrupted.store(true);
  std::signal(sig, SIG_DFL);
}
// Installs the handler for SIGINT and SIGTERM; the actions before it come back at the end.
class SignalScope {
 public:
  SignalScope() {
    sweep_interrupted.store(false);
    sweep_signal = 0;
    struct sigaction action {};
    action.sa_handler = onSweepSignal;
    sigemptyset(&action.sa_mask);
    for (int k = 0; k < 2; ++k) ::sigaction(kSignals[k], &action, &before_[k]);
  }
  ~SignalScope() {
    for (int k = 0; k < 2; ++k) ::sigaction(kSignals[k], &before_[k], nullptr);
  }
  SignalScope(const SignalScope&) = delete;
  SignalScope& operator=(const SignalScope&) = delete;
  // Throws Interrupted when a signal came; `stage` names where the run was.
  static void check(const std::string& stage) {
    if (!sweep_interrupted.load()) return;
    const int sig = sweep_signal;
    throw Interrupted(sig, std::string("the sweep was interrupted by ") + (sig == SIGTERM ? "SIGTERM" : "SIGINT") +
                               " " + stage + "; nothing was written");
  }

 private:
  static constexpr int kSignals[2] = {SIGINT, SIGTERM};
  struct sigaction before_[2];
};

// A progress bar on standard error, drawn only when asked for (a terminal) and once the run
// has taken a second; erased before the summary.
class ProgressBar {
 public:
  ProgressBar(bool enabled, Clock::time_point start) : enabled_(enabled), start_(start) {}
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  ~ProgressBar() { clear(); }

  void update(const steady::sweep::SweepProgress& p) {
    if (!enabled_) return;
    const double elapsed = secondsSince(start_);
    if (elapsed < 1.0) return;
    static const char* const stages[] = {"cycle", "intersect", "label", "output"};
    int stage = 0;
    for (int i = 0; i < 4; ++i)
      if (std::strcmp(p.stage, stages[i]) == 0) stage = i;
    const double f = std::clamp(p.fraction, 0.0, 1.0);
    constexpr int kWidth = 24;
    const int filled = static_cast<int>(std::lround(f * kWidth));
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.append(static_cast<std::size_t>(kWidth - filled), '.');
    std::fprintf(stderr, "\rsteady sweep: stage %d/4 %-9s [%s] %3d%%  %.0f s ", stage + 1, p.stage, bar.c_str(),
                 static_cast<int>(std::lround(100 * f)), elapsed);
    std::fflush(stderr);
    drawn_ = true;
  }

  void clear() {
    if (!drawn_) return;
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
    drawn_ = false;
  }

 private:
  bool enabled_;
  Clock::time_point start_;
  bool drawn_ = false;
};

std::string count(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

Json repairJson(const steady::sweep::RepairReport& r) {
  Json j = Json::object();
  j["summary"] = steady::sweep::describe(r);
  j["changed"] = r.changed();
  j["vertices_in"] = r.vertices_in;
  j["faces_in"] = r.faces_in;
  j["vertices_out"] = r.vertices_out;
  j["faces_out"] = r.faces_out;
  j["duplicate_vertices_merged"] = r.duplicate_vertices_merged;
  j["degenerate_faces_removed"] = r.degenerate_faces_removed;
  j["duplicate_faces_removed"] = r.duplicate_faces_removed;
  j["opposite_faces_removed"] = r.opposite_faces_removed;
  j["isolated_vertices_removed"] = r.isolated_vertices_removed;
  j["faces_flipped"] = r.faces_flipped;
  j["vertices_duplicated"] = r.vertices_duplicated;
  j["non_manifold_edges"] = r.non_manifold_edges;
  j["non_manifold_vertices"] = r.non_manifold_vertices;
  j["holes_filled"] = r.holes_filled;
  j["hole_faces_added"] = r.hole_faces_added;
  j["holes"] = r.holes;
  j["boundary_edges"] = r.boundary_edges;
  j["degenerate_faces"] = r.degenerate_faces;
  j["components"] = r.components;
  j["closed"] = r.closed;
  j["oriented_outward"] = r.oriented_outward;
  return j;
}

Json checkJson(const steady::sweep::MeshCheck& c, bool checked) {
  Json j = Json::object();
  j["closed"] = c.closed;
  j["manifold"] = c.manifold;
  j["oriented"] = c.oriented;
  j["self_intersections"] = checked ? Json(c.self_intersections) : Json(nullptr);
  j["degenerate_faces"] = c.degenerate_faces;
  j["shells"] = c.shells;
  j["volume"] = outputNumber(c.volume);
  j["area"] = outputNumber(c.area);
  return j;
}

std::string checkSummary(const steady::sweep::MeshCheck& c, bool checked) {
  std::string s = std::string(c.closed ? "closed" : "OPEN") + ", " + (c.manifold ? "manifold" : "NOT MANIFOLD") + ", " +
                  (c.oriented ? "oriented" : "NOT ORIENTED") + ", ";
  if (c.degenerate_faces > 0) s += std::to_string(c.degenerate_faces) + " ZERO-AREA faces, ";
  if (!checked) return s + "self-intersections not checked";
  if (c.self_intersections == 0) return s + "no self-intersection";
  return s + std::to_string(c.self_intersections) + " SELF-INTERSECTING face pairs";
}

// The summary's warnings when some vertex or face centroid of the walls kept at mouths that could
// not be closed, or of an inner shell, is not certified within the tolerance of the true boundary
// (Envelope::kept_wall_uncertified, kept_wall_faces_uncertified, cavity_uncertified,
// cavity_faces_uncertified), or a mouth filling was taken with a
// probe that is not (Envelope::deep_fillings_taken); empty otherwise.
std::string uncertifiedWarning(const steady::sweep::Envelope& e) {
  auto bound = [](double b) { return std::isfinite(b) ? num(b) : std::string("over 8 x tolerance"); };
  std::string out;
  if (!e.kept_wall_uncertified.empty())
    out += "; warning: " + count(e.kept_wall_uncertified.size(), "vertex", "vertices") +
           " of walls kept at mouths that could not be closed not certified within the tolerance of the true "
           "boundary (bound " + bound(e.kept_wall_depth_bound) + "; indices in the report's kept_wall_uncertified)";
  if (!e.kept_wall_faces_uncertified.empty())
    out += "; warning: " + count(e.kept_wall_faces_uncertified.size(), "face", "faces") +
           " at walls kept at mouths that could not be closed with a centroid not certified within the tolerance "
           "of the true boundary (bound " + bound(e.kept_wall_depth_bound) +
           "; indices in the report's kept_wall_faces_uncertified)";
  if (!e.cavity_uncertified.empty())
    out += "; warning: " + count(e.cavity_uncertified.size(), "vertex", "vertices") +
           " of inner shells (cavities) not certified within the tolerance of the true boundary (bound " +
           bound(e.cavity_depth_bound) + "; indices in the report's cavity_uncertified)";
  if (!e.cavity_faces_uncertified.empty())
    out += "; warning: " + count(e.cavity_faces_uncertified.size(), "face", "faces") +
           " of inner shells (cavities) with a centroid not certified within the tolerance of the true boundary "
           "(bound " + bound(e.cavity_depth_bound) + "; indices in the report's cavity_faces_uncertified)";
  if (e.deep_fillings_taken > 0)
    out += "; warning: " + count(e.deep_fillings_taken, "mouth filling", "mouth fillings") +
           " taken with a probe not certified within the tolerance of the true boundary (bound " +
           bound(e.filling_depth_bound) + "; the report's deep_fillings_taken)";
  return out;
}

// " on N of M spans" when a re-sweep refined some of a motion's spans (Envelope::spans_refined).
std::string refinedSpansNote(const steady::sweep::Envelope& envelope) {
  if (envelope.spans < 2 || envelope.spans_refined == 0) return {};
  return " on " + std::to_string(envelope.spans_refined) + " of " + std::to_string(envelope.spans) + " spans";
}

}  // namespace

SweepOutput sweepCommand(const SweepRequest& request) {
  const Clock::time_point start = Clock::now();

  // Arguments first, then the output paths: nothing is computed for a run that cannot finish.
  double relative = 1e-3;
  if (!trimmed(request.tolerance).empty()) {
    relative = readNumber(request.tolerance, "--tolerance");
    if (!(relative > 0 && relative < 1))
      throw UsageError("usage", "--tolerance: " + trimmed(request.tolerance) +
                                    " is not in (0, 1); it is relative to the body's bounding-box diagonal "
                                    "(default 1e-3)");
  }
  steady::io::MeshFormat format{};
  try {
    format = steady::io::meshFormatOf(request.output);
  } catch (const steady::Error& e) {
    throw UsageError("usage", std::string("--output: ") + e.what());
  }
  if (request.binary && format != steady::io::MeshFormat::Ply && format != steady::io::MeshFormat::Stl)
    throw UsageError("usage", "--binary: binary output is available for .ply and .stl only, not for '" +
                                  request.output + "'");
  const bool report_file = !request.report.empty() && request.report != "-";
  if (report_file) {
    std::error_code e1, e2;
    const fs::path a = fs::weakly_canonical(request.report, e1), b = fs::weakly_canonical(request.output, e2);
    if (request.report == request.output || (!e1 && !e2 && a == b))
      throw UsageError("usage", "--report: '" + request.report + "' is also the --output mesh; give another file");
  }
  checkOutputPath(request.output, "the envelope");
  if (report_file) checkOutputPath(request.report, "the report");

  // Input: files (exit status 2), the body, then the math of the motion (3).
  Clock::time_point t = Clock::now();
  const LoadedMotion loaded = loadMotion(request.motion);
  steady::io::TriangleMesh mesh = steady::io::readMesh(request.body);
  const double read_time = secondsSince(t);
  const std::size_t file_vertices = mesh.vertices.size(), file_faces = mesh.faces.size();

  t = Clock::now();
  std::optional<steady::sweep::RepairReport> repaired;
  if (request.repair || request.fill_holes) {
    steady::sweep::RepairOptions repair_options;
    repair_options.fill_holes = request.fill_holes;
    try {
      repaired = steady::sweep::repairMesh(mesh.vertices, mesh.faces, repair_options);
    } catch (const steady::Error& e) {
      throw UsageError(steady::to_string(e.code()), request.body + ": " + e.what());
    }
  }
  const double repair_time = secondsSince(t);

  t = Clock::now();
  std::optional<steady::sweep::Body> body;
  try {
    body.emplace(mesh.vertices, mesh.faces);
  } catch (const steady::Error& e) {
    std::string hint;
    if (repaired) {
      hint = " (after --repair: " + steady::sweep::describe(*repaired);
      if (!repaired->closed && !request.fill_holes) hint += "; --fill-holes fills holes";
      hint += ")";
    } else if (e.code() != steady::ErrorCode::NonFinite) {
      hint = " (--repair fixes what it safely can: duplicate vertices, faces with a repeated vertex, duplicate "
             "faces, orientation; --fill-holes also fills holes)";
    }
    throw UsageError(steady::to_string(e.code()), request.body + ": " + e.what() + hint);
  }
  const double body_time = secondsSince(t);

  t = Clock::now();
  const steady::KeyframeMotion3 keys = buildMotion(loaded);
  const steady::Motion3 motion = withContext("the motion of " + loaded.source + ": ", [&] {
    return keys.toMotion(body->box(), loaded.file.approximation);
  });
  const double motion_time = secondsSince(t);

  // The sweep.
  steady::sweep::SweepOptions options;
  options.relative_tolerance = relative;
  options.check = request.check;
  options.threads = request.threads;
  options.refinements = request.refinements;
  ProgressBar bar(request.progress, start);
  std::string stage = "cycle";  // (the last stage reported, for the message of an interruption)
  options.progress = [&bar, &stage](const steady::sweep::SweepProgress& p) {
    stage = p.stage;
    bar.update(p);
  };
  const SignalScope signals;  // (until the files are written)
  options.cancel = &sweep_interrupted;
  steady::sweep::Envelope envelope;
  try {
    envelope = withContext("the sweep: ", [&] { return steady::sweep::sweptEnvelope(*body, motion, options); });
  } catch (const steady::Error& e) {
    bar.clear();
    if (e.code() == steady::ErrorCode::Cancelled) SignalScope::check("in its " + stage + " stage");
    throw;
  }
  bar.clear();

  // The report (complete before anything is written; the time of the writing is not in it).
  const double diagonal = body->box().diagonal();
  Json report = Json::object();
  report["volume"] = outputNumber(envelope.volume);
  report["area"] = outputNumber(envelope.area);
  report["vertices"] = envelope.vertices.size();
  report["faces"] = envelope.triangles.size();
  Json tolerance = Json::object();
  tolerance["absolute"] = outputNumber(envelope.tolerance);
  tolerance["relative"] = outputNumber(relative);
  tolerance["tessellation"] = outputNumber(envelope.tessellation_tolerance);
  tolerance["body_diagonal"] = outputNumber(diagonal);
  report["tolerance"] = std::move(tolerance);
  report["resweeps"] = envelope.resweeps;
  report["spans_refined"] = envelope.spans_refined;
  report["spans"] = envelope.spans;
  report["spans_repeated"] = envelope.spans_repeated;
  report["cycle_triangles"] = envelope.cycle_triangles;
  report["intersecting_pairs"] = envelope.intersecting_pairs;
  report["arrangement_triangles"] = envelope.arrangement_triangles;
  report["cycle_open_edges"] = envelope.cycle_open_edges;
  report["coincident_merged"] = envelope.coincident_merged;
  report["coincident_cancelled"] = envelope.coincident_cancelled;
  report["patches"] = envelope.patches;
  report["ray_retries"] = envelope.ray_retries;
  report["patches_by_ray"] = envelope.patches_by_ray;
  report["label_mismatches"] = envelope.label_mismatches;
  report["thin_cavities_removed"] = envelope.thin_cavities_removed;
  report["thin_solids_removed"] = envelope.thin_solids_removed;
  report["buried_patches_removed"] = envelope.buried_patches_removed;
  report["crack_faces_removed"] = envelope.crack_faces_removed;
  report["buried_patches_kept"] = envelope.buried_patches_kept;
  report["crack_faces_kept"] = envelope.crack_faces_kept;
  report["kept_wall_vertices"] = envelope.kept_wall_vertices;
  report["kept_wall_depth_bound"] = outputNumber(envelope.kept_wall_depth_bound);  // (null: infinite)
  report["kept_wall_uncertified"] = envelope.kept_wall_uncertified;
  report["kept_wall_faces_uncertified"] = envelope.kept_wall_faces_uncertified;
  report["cavity_vertices"] = envelope.cavity_vertices;
  report["cavity_depth_bound"] = outputNumber(envelope.cavity_depth_bound);  // (null: infinite)
  report["cavity_uncertified"] = envelope.cavity_uncertified;
  report["cavity_faces_uncertified"] = envelope.cavity_faces_uncertified;
  report["uncertified_vertices_moved"] = envelope.uncertified_vertices_moved;
  report["pocket_mouths_filled"] = envelope.pocket_mouths_filled;
  report["deep_fillings_taken"] = envelope.deep_fillings_taken;
  report["fillings_refined"] = envelope.fillings_refined;
  report["filling_depth_bound"] = outputNumber(envelope.filling_depth_bound);  // (null: infinite)
  report["mouth_flaps_removed"] = envelope.mouth_flaps_removed;
  report["mouth_rim_faces_removed"] = envelope.mouth_rim_faces_removed;
  report["buried_dents_filled"] = envelope.buried_dents_filled;
  report["rounding_merged"] = envelope.rounding_merged;
  report["rounding_slivers_flipped"] = envelope.rounding_slivers_flipped;
  report["pinched_vertices_split"] = envelope.pinched_vertices_split;
  report["pinches_touching"] = envelope.pinches_touching;
  report["check"] = checkJson(envelope.check, request.check);
  Json timings = Json::object();
  timings["read"] = outputNumber(read_time);
  timings["repair"] = outputNumber(repair_time);
  timings["body"] = outputNumber(body_time);
  timings["motion"] = outputNumber(motion_time);
  timings["cycle"] = outputNumber(envelope.timings.cycle);
  timings["intersect"] = outputNumber(envelope.timings.intersect);
  timings["label"] = outputNumber(envelope.timings.label);
  timings["output"] = outputNumber(envelope.timings.output);
  timings["check"] = outputNumber(envelope.timings.check);
  timings["sweep"] = outputNumber(envelope.timings.total);
  const double total = secondsSince(start);
  timings["total"] = outputNumber(total);
  report["timings_s"] = std::move(timings);
  Json body_json = Json::object();
  body_json["file"] = request.body;
  body_json["vertices"] = body->vertices().size();
  body_json["faces"] = body->faces().size();
  body_json["volume"] = outputNumber(body->signedVolume());
  body_json["area"] = outputNumber(body->area());
  body_json["diagonal"] = outputNumber(diagonal);
  report["body"] = std::move(body_json);
  report["repair"] = repaired ? repairJson(*repaired) : Json(nullptr);
  Json motion_json = Json::object();
  motion_json["source"] = loaded.source;
  motion_json["interpolation"] = steady::to_string(keys.interpolation());
  motion_json["t"] = Json::array({outputNumber(keys.beginTime()), outputNumber(keys.endTime())});
  motion_json["spans"] = motion.spanCount();
  motion_json["approximation_error"] = outputNumber(motion.approximationError());
  report["motion"] = std::move(motion_json);
  Json output_json = Json::object();
  output_json["file"] = request.output;
  output_json["binary"] = request.binary;
  report["output"] = std::move(output_json);
  const std::string report_text = formatJson(report);

  // The files: the report waits next to its place until the envelope is written.
  SignalScope::check("after the sweep, before its files were written");
  std::optional<PendingFile> pending;
  if (report_file) pending.emplace(request.report, report_text, "the report");
  steady::io::TriangleMesh out;
  out.vertices = envelope.vertices;
  out.faces = envelope.triangles;
  steady::io::MeshWriteOptions write_options;
  write_options.binary = request.binary;
  try {
    steady::io::writeMesh(request.output, out, write_options);
  } catch (const steady::Error& e) {
    if (e.code() == steady::ErrorCode::Io) throw OutputError(e.what());
    throw;
  }
  if (pending) {
    try {
      pending->commit();
    } catch (const OutputError&) {
      ::unlink(request.output.c_str());  // all or nothing
      throw;
    }
  }

  SweepOutput result;
  if (request.report == "-") result.json = report_text;
  result.defective = !steady::sweep::passedCheck(envelope);
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.2f s", secondsSince(start));
  result.summary =
      "steady sweep: " + request.body + " (" + count(file_vertices, "vertex", "vertices") + ", " +
      count(file_faces, "triangle", "triangles") +
      (repaired ? "; repaired: " + steady::sweep::describe(*repaired) : std::string()) + ") along " +
      loaded.source + " (" + steady::to_string(keys.interpolation()) + ", " +
      count(motion.spanCount(), "span", "spans") + ", t " + num(keys.beginTime()) + " .. " + num(keys.endTime()) +
      "): envelope of " + count(envelope.vertices.size(), "vertex", "vertices") + ", " +
      count(envelope.triangles.size(), "triangle", "triangles") + ", volume " + num(envelope.volume) + ", area " +
      num(envelope.area) + " (tolerance " + num(envelope.tolerance) + " = " + num(relative) +
      " x body diagonal) written to " + request.output + (request.binary ? " (binary)" : "") + " in " + seconds +
      (envelope.resweeps > 0 ? " after " + count(envelope.resweeps, "re-sweep", "re-sweeps") +
                                   " (tessellation tolerance " + num(envelope.tessellation_tolerance) +
                                   refinedSpansNote(envelope) + ")"
                             : std::string()) +
      "; check: " + checkSummary(envelope.check, request.check) +
      uncertifiedWarning(envelope);
  return result;
}

}  // namespace steady_cli
