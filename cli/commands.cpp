// pow, sam and demo: read the arguments, call the EAR, build the JSON answer.

#include "commands.hpp"

#include "affinity_io.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <filesystem>
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

}  // namespace steady_cli
