// Motions made of SAM spans, and the constructions of the SAM paper (§5.3, §7) on top of the EAR.
#include <steady/core/motion.hpp>

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

namespace steady {

namespace {

std::string num(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

// A pose must be finite, invertible and orientation preserving; `what` names it in the error.
template <int D>
void checkPose(const Affine<D>& P, const std::string& what) {
  if (!P.isFinite()) throw Error(ErrorCode::NonFinite, what + " has NaN or infinite entries");
  const double det = P.determinant();
  if (det < 0)
    throw Error(ErrorCode::NotOrientationPreserving,
                what + " has det L = " + num(det) +
                    " < 0: it mirrors the body, and no motion can reach a mirror image; check "
                    "the axis order or the sign of a scale");
  try {
    (void)P.inverse();
  } catch (const Error& e) {
    throw Error(e.code(), what + ": " + e.what());
  }
}

template <int D>
void checkTimes(const std::vector<Keyframe<D>>& keys) {
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (!std::isfinite(keys[i].t))
      throw Error(ErrorCode::NonFinite, "key " + std::to_string(i) + " has a non-finite time");
    if (i > 0 && !(keys[i].t > keys[i - 1].t))
      throw Error(ErrorCode::InvalidArgument,
                  "key " + std::to_string(i) + " has time " + num(keys[i].t) +
                      ", not after key " + std::to_string(i - 1) + "'s time " +
                      num(keys[i - 1].t) + ": key times must increase strictly");
  }
}

template <int D>
void checkKeys(const std::vector<Keyframe<D>>& keys, std::size_t min_count, const char* what) {
  if (keys.size() < min_count)
    throw Error(ErrorCode::InvalidArgument, std::string(what) + " needs at least " +
                                                std::to_string(min_count) + " key poses, got " +
                                                std::to_string(keys.size()));
  checkTimes(keys);
  for (std::size_t i = 0; i < keys.size(); ++i) checkPose(keys[i].pose, "key " + std::to_string(i));
}

// Homogeneous matrix of an affinity as a plain (D+1)x(D+1) Eigen matrix.
template <int D>
typename Affine<D>::Homogeneous hom(const Affine<D>& A) {
  return A.homogeneous();
}

// Largest distance between the images of `points` under two poses.
template <int D>
double poseDistance(const Affine<D>& P, const Affine<D>& Q,
                    const std::vector<typename Affine<D>::Vector>& points) {
  double d = 0.0;
  for (const auto& c : points) d = std::max(d, (P.applyPoint(c) - Q.applyPoint(c)).norm());
  return d;
}

}  // namespace

// --- Box -------------------------------------------------------------------------------------

template <int D>
Box<D> Box<D>::of(const std::vector<Vector>& points) {
  if (points.empty()) throw Error(ErrorCode::DegenerateInput, "a bounding box needs at least one point");
  Box b;
  b.lo = b.hi = points.front();
  for (const Vector& p : points) {
    if (!p.allFinite()) throw Error(ErrorCode::NonFinite, "a point of the bounding box is not finite");
    b.lo = b.lo.cwiseMin(p);
    b.hi = b.hi.cwiseMax(p);
  }
  return b;
}

template <int D>
std::vector<typename Box<D>::Vector> Box<D>::corners() const {
  std::vector<Vector> out;
  out.reserve(1u << D);
  for (unsigned m = 0; m < (1u << D); ++m) {
    Vector c;
    for (int k = 0; k < D; ++k) c[k] = (m >> k) & 1u ? hi[k] : lo[k];
    out.push_back(c);
  }
  return out;
}

// --- Motion ----------------------------------------------------------------------------------

namespace {

// Appends the spans from pose B (time ta) to pose C (time tb), splitting at the midpoint of the
// polar Log-Exp interpolation while a part has no SAM.
template <int D>
void appendSplit(const Affine<D>& B, const Affine<D>& C, double ta, double tb, int depth,
                 const MotionOptions& options, std::vector<double>& times,
                 std::vector<Span<D>>& spans, std::vector<Affine<D>>& poses) {
  try {
    spans.push_back(Span<D>::between(B, C, options.ear));
  } catch (const Error& e) {
    if (e.code() != ErrorCode::NoRealLog || depth >= options.max_split_depth)
      throw Error(e.code(), std::string(e.what()) + " (after " + std::to_string(depth) +
                                " halvings of the polar fallback)");
    const Affine<D> mid = polarInterpolate(B, C, 0.5, options.ear);
    const double tm = 0.5 * (ta + tb);
    appendSplit(B, mid, ta, tm, depth + 1, options, times, spans, poses);
    appendSplit(mid, C, tm, tb, depth + 1, options, times, spans, poses);
    return;
  }
  times.push_back(tb);
  poses.push_back(C);
}

}  // namespace

template <int D>
Motion<D> Motion<D>::polySam(const std::vector<Keyframe<D>>& keys, const MotionOptions& options) {
  checkKeys(keys, 2, "a polySAM");
  Motion m;
  m.times_.push_back(keys.front().t);
  m.poses_.push_back(keys.front().pose);
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    const std::string name = "span " + std::to_string(i) + " (key " + std::to_string(i) + " -> " +
                             std::to_string(i + 1) + ", t " + num(keys[i].t) + " .. " +
                             num(keys[i + 1].t) + ")";
    try {
      m.spans_.push_back(Span<D>::between(keys[i].pose, keys[i + 1].pose, options.ear));
      m.times_.push_back(keys[i + 1].t);
      m.poses_.push_back(keys[i + 1].pose);
      m.fallback_.push_back(0);
    } catch (const Error& e) {
      if (e.code() != ErrorCode::NoRealLog || options.no_sam != NoSamPolicy::Split) {
        std::string hint;
        if (e.code() == ErrorCode::NoRealLog)
          hint = "; or set MotionOptions::no_sam = Split (\"no_sam\": \"split\" in a motion file) to "
                 "insert unsteady midpoints automatically";
        throw Error(e.code(), name + " has no SAM: " + e.what() + hint);
      }
      const std::size_t before = m.spans_.size();
      try {
        appendSplit(keys[i].pose, keys[i + 1].pose, keys[i].t, keys[i + 1].t, 0, options,
                    m.times_, m.spans_, m.poses_);
      } catch (const Error& e2) {
        throw Error(e2.code(), name + ": the fallback could not make it steady: " + e2.what());
      }
      m.fallback_.resize(m.spans_.size(), 0);
      for (std::size_t k = before; k < m.spans_.size(); ++k) m.fallback_[k] = 1;
    }
  }
  return m;
}

template <int D>
Motion<D> Motion<D>::polySam(const std::vector<Affine<D>>& poses, const MotionOptions& options) {
  if (poses.size() < 2)
    throw Error(ErrorCode::InvalidArgument,
                "a polySAM needs at least 2 key poses, got " + std::to_string(poses.size()));
  std::vector<Keyframe<D>> keys(poses.size());
  const double n = static_cast<double>(poses.size() - 1);
  for (std::size_t i = 0; i < poses.size(); ++i) keys[i] = {static_cast<double>(i) / n, poses[i]};
  return polySam(keys, options);
}

template <int D>
std::size_t Motion<D>::fallbackSpanCount() const {
  return static_cast<std::size_t>(std::count(fallback_.begin(), fallback_.end(), char(1)));
}

template <int D>
std::size_t Motion<D>::spanIndex(double t) const {
  // First interior key time greater than t; spans are numbered from the key that starts them.
  const auto it = std::upper_bound(times_.begin() + 1, times_.end() - 1, t);
  return static_cast<std::size_t>(it - (times_.begin() + 1));
}

template <int D>
Affine<D> Motion<D>::pose(double t) const {
  const std::size_t i = spanIndex(t);
  return spans_[i].pose((t - times_[i]) / (times_[i + 1] - times_[i]));
}

template <int D>
typename Motion<D>::Vector Motion<D>::velocity(double t, const Vector& p) const {
  const std::size_t i = spanIndex(t);
  return spans_[i].velocity(p) / (times_[i + 1] - times_[i]);
}

template <int D>
std::vector<Keyframe<D>> Motion<D>::keyframes() const {
  std::vector<Keyframe<D>> out(times_.size());
  for (std::size_t i = 0; i < times_.size(); ++i) out[i] = {times_[i], poses_[i]};
  return out;
}

template <int D>
std::vector<VelocityJump> Motion<D>::velocityJumps(const Box<D>& body) const {
  const auto corners = body.corners();
  std::vector<VelocityJump> out;
  for (std::size_t k = 1; k < spans_.size(); ++k) {
    const double d0 = times_[k] - times_[k - 1], d1 = times_[k + 1] - times_[k];
    VelocityJump j;
    j.joint = k;
    j.t = times_[k];
    double speed = 0.0;
    for (const Vector& c : corners) {
      const Vector x = poses_[k].applyPoint(c);
      const Vector v0 = spans_[k - 1].velocity(x) / d0, v1 = spans_[k].velocity(x) / d1;
      j.magnitude = std::max(j.magnitude, (v1 - v0).norm());
      speed = std::max({speed, v0.norm(), v1.norm()});
    }
    j.relative = speed > 0 ? j.magnitude / speed : 0.0;
    out.push_back(j);
  }
  return out;
}

// --- approximation of curved motions -----------------------------------------------------

namespace {

// Adaptive bisection state of approximate().
template <int D>
struct Approximator {
  const std::function<Affine<D>(double)>& curve;
  std::vector<typename Affine<D>::Vector> corners;
  double tolerance;  // absolute
  int max_spans;
  EarOptions ear;
  std::vector<double> times;
  std::vector<Span<D>> spans;
  std::vector<Affine<D>> poses;
  double error = 0.0;

  Affine<D> at(double t) const {
    const Affine<D> P = curve(t);
    checkPose(P, "the curve's pose at t = " + num(t));
    return P;
  }

  // Deviation of the SAM span from the curve over [a, b], or infinity when there is no SAM.
  double deviation(const Affine<D>& Pa, const Affine<D>& Pb, double a, double b,
                   std::optional<Span<D>>& out) const {
    try {
      out.emplace(Span<D>::between(Pa, Pb, ear));
    } catch (const Error& e) {
      if (e.code() != ErrorCode::NoRealLog) throw;
      out.reset();
      return std::numeric_limits<double>::infinity();
    }
    double dev = 0.0;
    for (double q : {0.25, 0.5, 0.75})
      dev = std::max(dev, poseDistance<D>(at(a + q * (b - a)), out->pose(q), corners));
    return dev;
  }

  void push(Span<D>&& s, double b, const Affine<D>& Pb, double dev) {
    if (static_cast<int>(spans.size()) >= max_spans)
      throw Error(ErrorCode::InvalidArgument,
                  "approximating the curved motion needs more than " + std::to_string(max_spans) +
                      " spans: the tolerance is too small, or the motion is not continuous");
    spans.push_back(std::move(s));
    times.push_back(b);
    poses.push_back(Pb);
    error = std::max(error, dev);
  }

  void adaptive(double a, double b, const Affine<D>& Pa, const Affine<D>& Pb, int depth) {
    std::optional<Span<D>> s;
    const double dev = deviation(Pa, Pb, a, b, s);
    if (dev <= tolerance) return push(std::move(*s), b, Pb, dev);
    if (depth >= 48)
      throw Error(ErrorCode::InvalidArgument,
                  "approximating the curved motion: no SAM span fits near t = " + num(a) +
                      " (deviation " + num(dev) + " against the tolerance " + num(tolerance) +
                      "); the motion is not continuous there, or its poses are so large that "
                      "their rounding exceeds the tolerance");
    const double m = 0.5 * (a + b);
    const Affine<D> Pm = at(m);
    adaptive(a, m, Pa, Pm, depth + 1);
    adaptive(m, b, Pm, Pb, depth + 1);
  }
};

}  // namespace

template <int D>
Motion<D> approximate(const std::function<Affine<D>(double)>& curve, double t0, double t1,
                      const Box<D>& body, const ApproximationOptions& approximation,
                      const MotionOptions& options) {
  if (!std::isfinite(t0) || !std::isfinite(t1) || !(t1 > t0))
    throw Error(ErrorCode::InvalidArgument,
                "approximate: the time interval must be finite with t1 > t0, got " + num(t0) +
                    " .. " + num(t1));
  if (!body.lo.allFinite() || !body.hi.allFinite())
    throw Error(ErrorCode::NonFinite, "approximate: the body box is not finite");
  const double diag = body.diagonal();
  if (approximation.spans <= 0 && !(approximation.tolerance > 0))
    throw Error(ErrorCode::InvalidArgument,
                "approximate: the tolerance must be positive, got " + num(approximation.tolerance));
  if (approximation.spans <= 0 && !(diag > 0))
    throw Error(ErrorCode::DegenerateInput,
                "approximate: the body box is a single point, so a relative tolerance means "
                "nothing; pass the box of the body, or a fixed span count");
  Approximator<D> ap{curve, body.corners(), approximation.tolerance * diag,
                     std::max(1, approximation.spans > 0 ? approximation.spans : approximation.max_spans),
                     options.ear, {}, {}, {}, 0.0};
  const Affine<D> P0 = ap.at(t0);
  ap.times.push_back(t0);
  ap.poses.push_back(P0);
  if (approximation.spans > 0) {
    Affine<D> Pa = P0;
    for (int i = 0; i < approximation.spans; ++i) {
      const double a = t0 + (t1 - t0) * i / approximation.spans;
      const double b = i + 1 == approximation.spans ? t1 : t0 + (t1 - t0) * (i + 1) / approximation.spans;
      const Affine<D> Pb = ap.at(b);
      std::optional<Span<D>> s;
      const double dev = ap.deviation(Pa, Pb, a, b, s);
      if (!std::isfinite(dev))
        throw Error(ErrorCode::NoRealLog,
                    "approximate: span " + std::to_string(i) + " (t " + num(a) + " .. " + num(b) +
                        ") has no SAM between its end poses; use more spans or a tolerance");
      ap.push(std::move(*s), b, Pb, dev);
      Pa = Pb;
    }
  } else {
    ap.adaptive(t0, t1, P0, ap.at(t1), 0);
  }
  Motion<D> m;
  m.times_ = std::move(ap.times);
  m.spans_ = std::move(ap.spans);
  m.poses_ = std::move(ap.poses);
  m.fallback_.assign(m.spans_.size(), 0);
  m.approximation_error_ = ap.error;
  return m;
}

// --- constructions -----------------------------------------------------------------------------

template <int D>
Affine<D> samFrom(const Affine<D>& X, const Affine<D>& A, double t, const Affine<D>& B,
                  const EarOptions& options) {
  return pow(B * A.inverse(), t, options) * X;
}

template <int D>
Affine<D> bezier(const std::vector<Affine<D>>& controls, double s, const EarOptions& options) {
  if (controls.size() < 2)
    throw Error(ErrorCode::InvalidArgument, "a Bézier motion needs at least 2 control poses, got " +
                                                std::to_string(controls.size()));
  std::vector<Affine<D>> level = controls;
  for (std::size_t n = level.size(); n > 1; --n)
    for (std::size_t i = 0; i + 1 < n; ++i) level[i] = sam(level[i], s, level[i + 1], options);
  return level.front();
}

template <int D>
Affine<D> biArcControl(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C,
                       const EarOptions& options) {
  return samFrom(sam(A, 0.75, B, options), C, 0.25, B, options);
}

template <int D>
BiArc<D> BiArc<D>::through(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C,
                           const EarOptions& options) {
  return {A, biArcControl(A, B, C, options), B, biArcControl(C, B, A, options), C};
}

template <int D>
Affine<D> BiArc<D>::pose(double s, const EarOptions& options) const {
  if (s <= 0.5) return bezier<D>({A, L, B}, 2 * s, options);
  return bezier<D>({B, R, C}, 2 * s - 1, options);
}

namespace {

// The four-point prediction helper of the subdivision: SAM(SAM(A, 5/8, B), C, 1/8, B).
template <int D>
Affine<D> predict(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C, const EarOptions& o) {
  return samFrom(sam(A, 0.625, B, o), C, 0.125, B, o);
}

template <int D>
std::vector<Affine<D>> subdivideOnce(const std::vector<Affine<D>>& P, const EarOptions& o) {
  const std::size_t n = P.size();
  std::vector<Affine<D>> FL(n), FR(n), Q(2 * n - 1);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    FL[i] = predict(P[i - 1], P[i], P[i + 1], o);
    FR[i] = predict(P[i + 1], P[i], P[i - 1], o);
  }
  for (std::size_t i = 0; i < n; ++i) Q[2 * i] = P[i];
  for (std::size_t i = 0; i + 1 < n; ++i) {
    if (i == 0)
      Q[1] = FL[1];
    else if (i + 2 == n)
      Q[2 * i + 1] = FR[i];
    else
      Q[2 * i + 1] = sam(FR[i], 0.5, FL[i + 1], o);
  }
  return Q;
}

void checkRounds(int rounds) {
  if (rounds < 0 || rounds > 16)
    throw Error(ErrorCode::InvalidArgument,
                "subdivision rounds must be in 0..16 (each doubles the poses), got " + std::to_string(rounds));
}

}  // namespace

template <int D>
std::vector<Affine<D>> subdivide(const std::vector<Affine<D>>& poses, int rounds,
                                 const EarOptions& options) {
  checkRounds(rounds);
  if (poses.size() < 3)
    throw Error(ErrorCode::InvalidArgument, "four-point subdivision needs at least 3 poses, got " +
                                                std::to_string(poses.size()));
  std::vector<Affine<D>> P = poses;
  for (int r = 0; r < rounds; ++r) P = subdivideOnce(P, options);
  return P;
}

template <int D>
std::vector<Keyframe<D>> subdivide(const std::vector<Keyframe<D>>& keys, int rounds,
                                   const EarOptions& options) {
  checkRounds(rounds);
  checkTimes(keys);
  std::vector<Affine<D>> poses(keys.size());
  std::vector<double> times(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    poses[i] = keys[i].pose;
    times[i] = keys[i].t;
  }
  poses = subdivide(poses, rounds, options);
  for (int r = 0; r < rounds; ++r) {
    std::vector<double> next(2 * times.size() - 1);
    for (std::size_t i = 0; i < times.size(); ++i) next[2 * i] = times[i];
    for (std::size_t i = 0; i + 1 < times.size(); ++i) next[2 * i + 1] = 0.5 * (times[i] + times[i + 1]);
    times = std::move(next);
  }
  std::vector<Keyframe<D>> out(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) out[i] = {times[i], poses[i]};
  return out;
}

template <int D>
SamPatch<D>::SamPatch(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C,
                      const Affine<D>& D4, const EarOptions& options)
    : bottom_(Span<D>::between(A, B, options)), top_(Span<D>::between(C, D4, options)), d_(D4),
      options_(options) {}

template <int D>
SamPatch<D> SamPatch<D>::corners(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C,
                                 const Affine<D>& D4, const EarOptions& options) {
  return SamPatch(A, B, C, D4, options);
}

template <int D>
SamPatch<D> SamPatch<D>::regular(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C,
                                 const EarOptions& options) {
  return SamPatch(A, B, C, B * A.inverse() * C, options);
}

template <int D>
Affine<D> SamPatch<D>::pose(double s, double u) const {
  return sam(bottom_.pose(s), u, top_.pose(s), options_);
}

template <int D>
std::vector<Affine<D>> SamPatch<D>::grid(int ns, int nu) const {
  if (ns < 1 || nu < 1)
    throw Error(ErrorCode::InvalidArgument, "a patch grid needs at least 1 step each way, got " +
                                                std::to_string(ns) + " x " + std::to_string(nu));
  std::vector<Affine<D>> out;
  out.reserve(static_cast<std::size_t>(ns + 1) * static_cast<std::size_t>(nu + 1));
  for (int j = 0; j <= nu; ++j)
    for (int i = 0; i <= ns; ++i) out.push_back(pose(static_cast<double>(i) / ns, static_cast<double>(j) / nu));
  return out;
}

// --- unsteady comparators ----------------------------------------------------------------------

template <int D>
Affine<D> polarInterpolate(const Affine<D>& B, const Affine<D>& C, double t, const EarOptions& options) {
  if (!std::isfinite(t)) throw Error(ErrorCode::NonFinite, "polarInterpolate: t is not finite");
  checkPose(B, "the start pose");
  checkPose(C, "the end pose");
  const Affine<D> A = C * B.inverse();
  using Linear = typename Affine<D>::Linear;
  // L = U diag(sigma) V^T = R S with R = U V^T (a rotation, as det L > 0) and S = V diag(sigma) V^T.
  const Eigen::JacobiSVD<Linear> svd(A.linear(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Linear R = svd.matrixU() * svd.matrixV().transpose();
  const auto sigma = svd.singularValues();
  typename Affine<D>::Vector st;
  for (int k = 0; k < D; ++k) st[k] = std::pow(sigma[k], t);
  const Linear St = svd.matrixV() * st.asDiagonal() * svd.matrixV().transpose();
  const Linear Rt = pow(Affine<D>(R, Affine<D>::Vector::Zero()), t, options).linear();
  return Affine<D>(Rt * St, t * A.translation()) * B;
}

template <int D>
Affine<D> exp(const AffineLog<D>& X) {
  if (!X.M.allFinite() || !X.u.allFinite()) throw Error(ErrorCode::NonFinite, "exp: the log has NaN or infinite entries");
  const typename Affine<D>::Homogeneous E = X.homogeneous().exp();
  return Affine<D>(E.template topLeftCorner<D, D>(), E.template topRightCorner<D, 1>());
}

template <int D>
Affine<D> alexaAdd(const Affine<D>& A, const Affine<D>& B, const EarOptions& options) {
  const AffineLog<D> a = log(A, options), b = log(B, options);
  AffineLog<D> s;
  s.M = a.M + b.M;
  s.u = a.u + b.u;
  return exp(s);
}

template <int D>
Affine<D> alexaBlend(const std::vector<Affine<D>>& poses, const std::vector<double>& weights,
                     const EarOptions& options) {
  if (poses.empty() || poses.size() != weights.size())
    throw Error(ErrorCode::InvalidArgument, "alexaBlend needs as many weights as poses (and at least one), got " +
                                                std::to_string(poses.size()) + " poses and " +
                                                std::to_string(weights.size()) + " weights");
  AffineLog<D> s;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!std::isfinite(weights[i])) throw Error(ErrorCode::NonFinite, "alexaBlend: weight " + std::to_string(i) + " is not finite");
    const AffineLog<D> l = log(poses[i], options);
    s.M += weights[i] * l.M;
    s.u += weights[i] * l.u;
  }
  return exp(s);
}

template <int D>
Affine<D> alexaInterpolate(const Affine<D>& B, const Affine<D>& C, double t, const EarOptions& options) {
  return alexaBlend<D>({B, C}, {1 - t, t}, options);
}

template <int D>
Affine<D> lerp(const Affine<D>& B, const Affine<D>& C, double t) {
  return Affine<D>((1 - t) * B.linear() + t * C.linear(), (1 - t) * B.translation() + t * C.translation());
}

// --- ARA -------------------------------------------------------------------------------------------

namespace {

void checkAra(const AraOptions& o) {
  if (o.time_samples < 1 || o.space_samples < 1 || !(o.step > 0) || !(o.step < 0.05))
    throw Error(ErrorCode::InvalidArgument,
                "ARA options: time_samples and space_samples must be >= 1 and step in (0, 0.05)");
}

template <int D>
std::vector<typename Affine<D>::Vector> gridPoints(const Box<D>& region, int n) {
  std::vector<typename Affine<D>::Vector> pts;
  int total = 1;
  for (int k = 0; k < D; ++k) total *= n;
  for (int idx = 0; idx < total; ++idx) {
    typename Affine<D>::Vector p;
    int r = idx;
    for (int k = 0; k < D; ++k) {
      const int i = r % n;
      r /= n;
      const double f = n == 1 ? 0.5 : static_cast<double>(i) / (n - 1);
      p[k] = region.lo[k] + f * (region.hi[k] - region.lo[k]);
    }
    pts.push_back(p);
  }
  return pts;
}

// Mean of |W'(tau) [p;1]| over the sample times of [0, 1] and the grid, for a motion a(tau)
// parameterised over [0, 1]. W = a^-1 a' by central differences with step h, W' with step 8h;
// sample times stay 9h away from the ends so that no stencil leaves [0, 1].
template <int D>
double araUnit(const std::function<Affine<D>(double)>& a, const std::vector<typename Affine<D>::Vector>& pts,
               const AraOptions& o) {
  using H = typename Affine<D>::Homogeneous;
  const double h = o.step, H8 = 8 * o.step, margin = 9 * o.step;
  auto W = [&](double tau) -> H {
    const H da = (hom(a(tau + h)) - hom(a(tau - h))) / (2 * h);
    return hom(a(tau).inverse()) * da;
  };
  double sum = 0.0;
  for (int k = 0; k < o.time_samples; ++k) {
    const double tau = margin + (1 - 2 * margin) * (k + 0.5) / o.time_samples;
    const H dW = (W(tau + H8) - W(tau - H8)) / (2 * H8);
    for (const auto& p : pts) sum += (dW.template topLeftCorner<D, D>() * p + dW.template topRightCorner<D, 1>()).norm();
  }
  return sum / (static_cast<double>(o.time_samples) * static_cast<double>(pts.size()));
}

template <int D>
double regionDiagonal(const Box<D>& region) {
  const double d = region.diagonal();
  if (!std::isfinite(d) || !(d > 0))
    throw Error(ErrorCode::DegenerateInput, "ARA: the region must be a finite box of positive size");
  return d;
}

}  // namespace

template <int D>
double ara(const std::function<Affine<D>(double)>& motion, double t0, double t1, const Box<D>& region,
           const AraOptions& options) {
  checkAra(options);
  const double diag = regionDiagonal(region);
  if (!std::isfinite(t0) || !std::isfinite(t1) || !(t1 > t0))
    throw Error(ErrorCode::InvalidArgument, "ARA: the time interval must be finite with t1 > t0");
  const std::function<Affine<D>(double)> unit = [&](double tau) { return motion(t0 + tau * (t1 - t0)); };
  return araUnit<D>(unit, gridPoints(region, options.space_samples), options) / diag;
}

template <int D>
double ara(const Motion<D>& motion, const Box<D>& region, const AraOptions& options) {
  checkAra(options);
  const double diag = regionDiagonal(region);
  const auto pts = gridPoints(region, options.space_samples);
  const double total = motion.endTime() - motion.beginTime();
  // In the motion's unit time, span i lasts delta_i = duration_i / total, and d/dtau of its
  // body-frame velocity is its own (unit-span) value divided by delta_i^2; each span weighs
  // delta_i in the mean.
  double sum = 0.0;
  for (std::size_t i = 0; i < motion.spanCount(); ++i) {
    const Span<D>& s = motion.span(i);
    const std::function<Affine<D>(double)> unit = [&](double tau) { return s.pose(tau); };
    const double delta = (motion.spanEnd(i) - motion.spanBegin(i)) / total;
    sum += araUnit<D>(unit, pts, options) / delta;
  }
  return sum / diag;
}

// --- KeyframeMotion ------------------------------------------------------------------------------

const char* to_string(Interpolation kind) noexcept {
  switch (kind) {
    case Interpolation::PolySam: return "polysam";
    case Interpolation::Bezier: return "bezier";
    case Interpolation::BiArc: return "biarc";
    case Interpolation::Subdivide: return "subdivide";
  }
  return "unknown";
}

template <int D>
KeyframeMotion<D>::KeyframeMotion(std::vector<Keyframe<D>> keys, Interpolation kind, int rounds,
                                  const MotionOptions& options)
    : keys_(std::move(keys)), kind_(kind), options_(options) {
  switch (kind_) {
    case Interpolation::PolySam:
      steady_.push_back(Motion<D>::polySam(keys_, options_));
      break;
    case Interpolation::Subdivide:
      if (rounds < 0 || rounds > 8)
        throw Error(ErrorCode::InvalidArgument, "subdivide: rounds must be in 0..8, got " + std::to_string(rounds));
      checkKeys(keys_, rounds > 0 ? 3 : 2, "a subdivided motion");
      steady_.push_back(Motion<D>::polySam(rounds > 0 ? subdivide(keys_, rounds, options_.ear) : keys_, options_));
      break;
    case Interpolation::Bezier:
      checkKeys(keys_, 2, "a Bézier motion");
      (void)bezier(std::vector<Affine<D>>{keys_.front().pose, keys_.back().pose}, 0.5, options_.ear);
      break;
    case Interpolation::BiArc:
      checkKeys(keys_, 3, "a bi-arc motion");
      if (keys_.size() % 2 == 0)
        throw Error(ErrorCode::InvalidArgument,
                    "a bi-arc motion needs an odd number of keys (bi-arcs through keys 0-1-2, "
                    "2-3-4, ...), got " + std::to_string(keys_.size()) + "; add or drop a key");
      for (std::size_t k = 0; k + 2 < keys_.size(); k += 2) {
        try {
          arcs_.push_back(BiArc<D>::through(keys_[k].pose, keys_[k + 1].pose, keys_[k + 2].pose, options_.ear));
        } catch (const Error& e) {
          throw Error(e.code(), "the bi-arc through keys " + std::to_string(k) + ", " +
                                    std::to_string(k + 1) + ", " + std::to_string(k + 2) + ": " + e.what());
        }
      }
      break;
  }
}

template <int D>
Affine<D> KeyframeMotion<D>::pose(double t) const {
  if (!std::isfinite(t)) throw Error(ErrorCode::NonFinite, "the time t is not finite");
  if (piecewiseSteady()) return steady_.front().pose(t);
  t = std::min(std::max(t, beginTime()), endTime());
  if (kind_ == Interpolation::Bezier) {
    std::vector<Affine<D>> controls(keys_.size());
    for (std::size_t i = 0; i < keys_.size(); ++i) controls[i] = keys_[i].pose;
    return bezier(controls, (t - beginTime()) / (endTime() - beginTime()), options_.ear);
  }
  // BiArc: the arc whose keys 2j..2j+2 hold t; keys map to s = 0, 1/2, 1.
  std::size_t j = 0;
  while (j + 1 < arcs_.size() && t > keys_[2 * j + 2].t) ++j;
  const double ta = keys_[2 * j].t, tb = keys_[2 * j + 1].t, tc = keys_[2 * j + 2].t;
  const double s = t <= tb ? 0.5 * (t - ta) / (tb - ta) : 0.5 + 0.5 * (t - tb) / (tc - tb);
  return arcs_[j].pose(s, options_.ear);
}

template <int D>
Motion<D> KeyframeMotion<D>::toMotion(const Box<D>& body, const ApproximationOptions& approximation) const {
  if (piecewiseSteady()) return steady_.front();
  const std::function<Affine<D>(double)> curve = [this](double t) { return pose(t); };
  if (kind_ == Interpolation::Bezier || approximation.spans > 0)
    return approximate<D>(curve, beginTime(), endTime(), body, approximation, options_);
  // Bi-arcs: approximate each smooth quadratic piece on its own so no span straddles a joint.
  Motion<D> out;
  for (std::size_t k = 0; k + 1 < keys_.size(); ++k) {
    Motion<D> part = approximate<D>(curve, keys_[k].t, keys_[k + 1].t, body, approximation, options_);
    if (k == 0) {
      out = std::move(part);
      continue;
    }
    out.times_.insert(out.times_.end(), part.times_.begin() + 1, part.times_.end());
    out.poses_.insert(out.poses_.end(), part.poses_.begin() + 1, part.poses_.end());
    out.spans_.insert(out.spans_.end(), part.spans_.begin(), part.spans_.end());
    out.fallback_.insert(out.fallback_.end(), part.fallback_.begin(), part.fallback_.end());
    out.approximation_error_ = std::max(out.approximation_error_, part.approximation_error_);
  }
  return out;
}

// --- instantiations ----------------------------------------------------------------------------

#define STEADY_MOTION_INSTANTIATE(D)                                                                     \
  template struct Box<D>;                                                                                \
  template class Motion<D>;                                                                              \
  template struct BiArc<D>;                                                                              \
  template class SamPatch<D>;                                                                            \
  template class KeyframeMotion<D>;                                                                      \
  template Motion<D> approximate<D>(const std::function<Affine<D>(double)>&, double, double,            \
                                    const Box<D>&, const ApproximationOptions&, const MotionOptions&);   \
  template Affine<D> samFrom<D>(const Affine<D>&, const Affine<D>&, double, const Affine<D>&,           \
                                const EarOptions&);                                                      \
  template Affine<D> bezier<D>(const std::vector<Affine<D>>&, double, const EarOptions&);                \
  template Affine<D> biArcControl<D>(const Affine<D>&, const Affine<D>&, const Affine<D>&,              \
                                     const EarOptions&);                                                 \
  template std::vector<Affine<D>> subdivide<D>(const std::vector<Affine<D>>&, int, const EarOptions&);   \
  template std::vector<Keyframe<D>> subdivide<D>(const std::vector<Keyframe<D>>&, int,                   \
                                                 const EarOptions&);                                     \
  template Affine<D> polarInterpolate<D>(const Affine<D>&, const Affine<D>&, double, const EarOptions&); \
  template Affine<D> exp<D>(const AffineLog<D>&);                                                        \
  template Affine<D> alexaAdd<D>(const Affine<D>&, const Affine<D>&, const EarOptions&);                 \
  template Affine<D> alexaBlend<D>(const std::vector<Affine<D>>&, const std::vector<double>&,           \
                                   const EarOptions&);                                                   \
  template Affine<D> alexaInterpolate<D>(const Affine<D>&, const Affine<D>&, double, const EarOptions&); \
  template Affine<D> lerp<D>(const Affine<D>&, const Affine<D>&, double);                                \
  template double ara<D>(const std::function<Affine<D>(double)>&, double, double, const Box<D>&,        \
                         const AraOptions&);                                                             \
  template double ara<D>(const Motion<D>&, const Box<D>&, const AraOptions&);

STEADY_MOTION_INSTANTIATE(2)
STEADY_MOTION_INSTANTIATE(3)

#undef STEADY_MOTION_INSTANTIATE

}  // namespace steady
