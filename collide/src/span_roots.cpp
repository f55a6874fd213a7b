// Contact functions along a SAM span (point/plane, edge/edge) and their derivative bounds, fed to
// the guaranteed isolation of isolate.hpp. See span_roots.hpp for the bounds and the rounding
// policy.
#include <steady/collide/span_roots.hpp>

#include "isolate.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <string>

namespace steady {

namespace {

constexpr int kCacheSteps = 128;  // cached powers at s = k / 128
constexpr double kUlp = 0x1.0p-52;

// Per-thread memo of the latest powers computed off the cache grid, keyed by the SpanRoots'
// identity and the exact bits of s (direct-mapped, 64 slots). The root solves of one candidate
// pair (and of the pairs of one interval) sample the same times again and again: the middle of
// [s0, s1], its halves, ... A hit holds exactly what span_.power(s) computed for the same s, so
// the memo changes no result; being per thread, it keeps the const members safe to call
// concurrently. Identity 0 marks an empty slot.
struct PowerMemo {
  std::uint64_t id;
  std::uint64_t bits;
  double m[12];  // L column-major, then t
  double lnorm, tnorm;
};
thread_local PowerMemo t_memo[64];

std::uint64_t nextSpanRootsId() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}


using detail::Bounds;
using detail::kBoundSlack;
using detail::phi1;
using detail::phi2;

void checkRange(double s0, double s1, const char* what) {
  if (!std::isfinite(s0) || !std::isfinite(s1))
    throw Error(ErrorCode::NonFinite, std::string(what) + ": the time range is not finite");
  if (!(s1 >= s0)) throw Error(ErrorCode::InvalidArgument, std::string(what) + ": the time range is reversed (s1 < s0)");
}

// g(s) = m . x(s) - h for x(s) = A^s x0.
struct PointPlaneFn {
  using Vector = Eigen::Vector3d;
  struct Sample {
    double g, gp, gpp, eps, epsd;
    double vn;  // |v(x(s))|
  };
  const SpanRoots& sr;
  const Eigen::Matrix3d& M;
  const Vector& u;
  Vector x0, m;
  double h, mn, wm, x0n, ulps, mu, un;

  Sample sample(double s) const {
    Affine3 P;
    double ln, tn;
    sr.power(s, P, ln, tn);
    const Vector x = P.applyPoint(x0);
    const Vector v = M * x + u;
    const double xs = x.norm() + x0n * ln + tn;
    return {m.dot(x) - h, m.dot(v), m.dot(M * v), ulps * (mn * xs + std::abs(h)), ulps * mn * (mu * xs + un), v.norm()};
  }
  // g'(s) - g'(c) = m^T M (L^(s-c) - 1) v_c / ... bounded by |M^T m| |v_c| r phi1(r mu); the
  // path length |x(s) - x(c)| <= |v_c| r phi1(r mu) bounds |g(s) - g(c)| directly too.
  Bounds bounds(const Sample& c, double r) const {
    const double w = wm * c.vn;
    const detail::Phis p = detail::phis(r * mu);
    Bounds b;
    b.D = kBoundSlack * w * r * p.p1;
    b.reach = std::min(std::abs(c.gp) * r + kBoundSlack * w * r * r * p.p2, kBoundSlack * mn * c.vn * r * p.p1);
    return b;
  }
};

// g(s) = ((L^s e0) x d) . (q0 - A^s p0).
struct EdgeEdgeFn {
  using Vector = Eigen::Vector3d;
  struct Sample {
    double g, gp, gpp, eps, epsd;
    double en, men, mmen, vn, mvn, wn, nn;  // |e|, |M e|, |M^2 e|, |v|, |M v|, |q0 - x|, |e x d|
  };
  const SpanRoots& sr;
  const Eigen::Matrix3d& M;
  const Vector& u;
  Vector p0, e0, q0, d;
  double dn, p0n, e0n, ulps, mu, un;

  Sample sample(double s) const {
    Affine3 P;
    double ln, tn;
    sr.power(s, P, ln, tn);
    const Vector x = P.applyPoint(p0);
    const Vector e = P.linear() * e0;
    const Vector me = M * e, mme = M * me;
    const Vector v = M * x + u, mv = M * v;
    const Vector w = q0 - x;
    const Vector n = e.cross(d);
    Sample r;
    r.g = n.dot(w);
    r.gp = me.cross(d).dot(w) - n.dot(v);
    r.gpp = mme.cross(d).dot(w) - 2 * me.cross(d).dot(v) - n.dot(mv);
    r.en = e.norm();
    r.men = me.norm();
    r.mmen = mme.norm();
    r.vn = v.norm();
    r.mvn = mv.norm();
    r.wn = w.norm();
    r.nn = n.norm();
    const double xs = x.norm() + p0n * ln + tn;  // magnitude behind the rounding of x
    const double es = r.en + ln * e0n;            // and of e
    r.eps = ulps * dn * es * (r.wn + xs + q0.norm());
    r.epsd = ulps * dn * ((r.men + mu * es) * (r.wn + xs + q0.norm()) + es * (r.vn + mu * xs + un));
    return r;
  }
  // g'' = (M^2 e x d).w - 2 (M e x d).v - (e x d).(M v), every factor moving by at most
  // e^(|s-c| mu) from its value at c (M commutes with L^s), |w(s)| <= |w_c| + path length, and
  // |e(s) x d| <= |e_c x d| + |d| |M e_c| r phi1(r mu) (so edges that stay parallel give 0).
  Bounds bounds(const Sample& c, double r) const {
    const double z = r * mu, grow = std::exp(z);
    const double W = c.wn + c.vn * r * phi1(z);
    const double N = c.nn + dn * c.men * r * phi1(z);
    const double K = kBoundSlack * (dn * (grow * c.mmen * W + 2 * grow * grow * c.men * c.vn) + N * grow * c.mvn);
    Bounds b;
    b.D = K * r;
    b.reach = std::abs(c.gp) * r + 0.5 * K * r * r;
    return b;
  }
};

}  // namespace

SpanRoots::SpanRoots(const Span3& span, const RootOptions& options) : SpanRoots(span, options, true) {}

SpanRoots::SpanRoots(const Span3& span, const RootOptions& options, bool cache_powers)
    : span_(span), options_(options) {
  if (!(options_.time_tolerance > 0) || !(options_.value_ulps >= 1) || options_.max_intervals < 1)
    throw Error(ErrorCode::InvalidArgument,
                "RootOptions: time_tolerance must be > 0, value_ulps >= 1, max_intervals >= 1");
  id_ = nextSpanRootsId();
  M_ = span_.log().M;
  u_ = span_.log().u;
  mu_ = detail::spectralBound(M_);
  if (!cache_powers) return;
  cache_.reserve(kCacheSteps + 1);
  for (int k = 0; k <= kCacheSteps; ++k) {
    const Affine3 P = span_.power(static_cast<double>(k) / kCacheSteps);
    cache_.push_back({P, P.linear().norm(), P.translation().norm()});
  }
}


void SpanRoots::power(double s, Affine3& P, double& lnorm, double& tnorm) const {
  const double k = s * kCacheSteps;
  // A cache hit holds exactly what span_.power(s) computes: a lookup, not a case.
  if (!cache_.empty() && k >= 0 && k <= kCacheSteps && k == std::floor(k)) {
    const Cached& c = cache_[static_cast<std::size_t>(k)];
    P = c.P;
    lnorm = c.lnorm;
    tnorm = c.tnorm;
    return;
  }
  std::uint64_t bits;
  std::memcpy(&bits, &s, sizeof bits);
  const std::uint64_t h = (bits ^ (bits >> 29) ^ (id_ * 0x9E3779B97F4A7C15ull)) * 0xBF58476D1CE4E5B9ull;
  PowerMemo& slot = t_memo[h >> 58];
  if (slot.id == id_ && slot.bits == bits) {
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) P.linear()(r, c) = slot.m[3 * c + r];
    P.translation() = Eigen::Vector3d(slot.m[9], slot.m[10], slot.m[11]);
    lnorm = slot.lnorm;
    tnorm = slot.tnorm;
    return;
  }
  P = span_.power(s);
  lnorm = P.linear().norm();
  tnorm = P.translation().norm();
  slot.id = id_;
  slot.bits = bits;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) slot.m[3 * c + r] = P.linear()(r, c);
  for (int r = 0; r < 3; ++r) slot.m[9 + r] = P.translation()[r];
  slot.lnorm = lnorm;
  slot.tnorm = tnorm;
}

Affine3 SpanRoots::power(double s) const {
  Affine3 P;
  double ln, tn;
  power(s, P, ln, tn);
  return P;
}

namespace {

PointPlaneFn pointPlaneFn(const SpanRoots& sr, const Eigen::Matrix3d& M, const Eigen::Vector3d& u,
                          const Eigen::Vector3d& x0, const Eigen::Vector3d& m, double h) {
  if (!x0.allFinite() || !m.allFinite() || !std::isfinite(h))
    throw Error(ErrorCode::NonFinite, "point/plane solve: the point or the plane is not finite");
  const double mn = m.norm();
  if (!(mn > 0)) throw Error(ErrorCode::DegenerateInput, "point/plane solve: the plane normal m is zero");
  return {sr, M, u, x0, m, h, mn, (M.transpose() * m).norm(), x0.norm(),
          sr.options().value_ulps * kUlp, sr.logNorm(), u.norm()};
}

EdgeEdgeFn edgeEdgeFn(const SpanRoots& sr, const Eigen::Matrix3d& M, const Eigen::Vector3d& u,
                      const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                      const Eigen::Vector3d& q1) {
  if (!p0.allFinite() || !p1.allFinite() || !q0.allFinite() || !q1.allFinite())
    throw Error(ErrorCode::NonFinite, "edge/edge solve: an edge end is not finite");
  const Eigen::Vector3d e0 = p1 - p0, d = q1 - q0;
  if (!(e0.norm() > 0) || !(d.norm() > 0))
    throw Error(ErrorCode::DegenerateInput, "edge/edge solve: an edge has zero length");
  return {sr, M, u, p0, e0, q0, d, d.norm(), p0.norm(), e0.norm(),
          sr.options().value_ulps * kUlp, sr.logNorm(), u.norm()};
}

template <class F>
std::size_t collect(const F& f, double s0, double s1, const RootOptions& o, std::vector<ContactRoot>& out) {
  const std::size_t before = out.size();
  detail::isolateRoots(f, s0, s1, o, [&](const ContactRoot& p) {
    return detail::appendMerged(out, before, p, o.time_tolerance);
  });
  return out.size() - before;
}

template <class F>
std::optional<ContactRoot> earliest(const F& f, double s0, double s1, const RootOptions& o) {
  std::optional<ContactRoot> found;
  detail::isolateRoots(f, s0, s1, o, [&](const ContactRoot& p) {
    found = p;
    return true;
  });
  return found;
}

}  // namespace

std::size_t SpanRoots::pointPlane(const Vector& x0, const Vector& m, double h, double s0, double s1,
                                  std::vector<ContactRoot>& out) const {
  checkRange(s0, s1, "point/plane solve");
  return collect(pointPlaneFn(*this, M_, u_, x0, m, h), s0, s1, options_, out);
}

std::optional<ContactRoot> SpanRoots::firstPointPlane(const Vector& x0, const Vector& m, double h, double s0,
                                                      double s1) const {
  checkRange(s0, s1, "point/plane solve");
  return earliest(pointPlaneFn(*this, M_, u_, x0, m, h), s0, s1, options_);
}

std::size_t SpanRoots::edgeEdge(const Vector& p0, const Vector& p1, const Vector& q0, const Vector& q1, double s0,
                                double s1, std::vector<ContactRoot>& out) const {
  checkRange(s0, s1, "edge/edge solve");
  return collect(edgeEdgeFn(*this, M_, u_, p0, p1, q0, q1), s0, s1, options_, out);
}

std::optional<ContactRoot> SpanRoots::firstEdgeEdge(const Vector& p0, const Vector& p1, const Vector& q0,
                                                    const Vector& q1, double s0, double s1) const {
  checkRange(s0, s1, "edge/edge solve");
  return earliest(edgeEdgeFn(*this, M_, u_, p0, p1, q0, q1), s0, s1, options_);
}

}  // namespace steady
