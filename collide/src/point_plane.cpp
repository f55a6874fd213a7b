// Guaranteed root isolation of point/plane functions along a SAM span (see point_plane.hpp for
// the bounds and the rounding policy).
#include <steady/collide/point_plane.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace steady {

namespace {

constexpr int kCacheSteps = 128;           // cached powers at s = k / 128
constexpr double kUlp = 0x1.0p-52;
// Relative inflation of the derivative bounds, for the rounding of their own evaluation (a few
// dozen flops on positive numbers).
constexpr double kBoundSlack = 1.0 + 1e-12;

// (e^z - 1) / z and (e^z - 1 - z) / z^2 for z >= 0, accurate near 0.
double phi1(double z) { return z < 1e-8 ? 1.0 + 0.5 * z : std::expm1(z) / z; }
double phi2(double z) {
  if (z < 1e-3) return 0.5 + z * (1.0 / 6 + z * (1.0 / 24 + z / 120));
  return (std::expm1(z) - z) / (z * z);
}

// One evaluation of g at span time s.
struct Sample {
  double g = 0, gp = 0;  // g(s), g'(s)
  double w = 0;          // |M^T m| |v(x(s))|, the factor of the derivative bounds
  double mv = 0;         // |m| |v(x(s))|
  double eps = 0, epsd = 0;  // value tolerances of g and g'
};

int signOf(double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }

}  // namespace

SpanPlaneSolver::SpanPlaneSolver(const Span3& span, const PlaneRootOptions& options)
    : span_(span), options_(options) {
  if (!(options_.time_tolerance > 0) || !(options_.value_ulps >= 1) || options_.max_intervals < 1)
    throw Error(ErrorCode::InvalidArgument,
                "PlaneRootOptions: time_tolerance must be > 0, value_ulps >= 1, max_intervals >= 1");
  M_ = span_.log().M;
  u_ = span_.log().u;
  // Spectral norm of M (the largest singular value), slightly inflated so that rounding of
  // the eigen-solve cannot make it an underestimate; capped by the Frobenius norm.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(span_.log().M.transpose() * span_.log().M,
                                                          Eigen::EigenvaluesOnly);
  const double frob = span_.log().M.norm();
  mu_ = std::min(frob, std::sqrt(std::max(0.0, es.eigenvalues().maxCoeff())) * (1 + 1e-12) + 1e-300);
  cache_.reserve(kCacheSteps + 1);
  for (int k = 0; k <= kCacheSteps; ++k) {
    const Affine3 P = span_.power(static_cast<double>(k) / kCacheSteps);
    cache_.push_back({P, P.linear().norm(), P.translation().norm()});
  }
}

Affine3 SpanPlaneSolver::power(double s) const {
  const double k = s * kCacheSteps;
  // A cache hit returns exactly what span_.power(s) computes, so this is a lookup, not a case.
  if (k >= 0 && k <= kCacheSteps && k == std::floor(k)) return cache_[static_cast<std::size_t>(k)].P;
  return span_.power(s);
}

template <class Visit>
void SpanPlaneSolver::isolate(const Vector& x0, const Vector& m, double h, double s0, double s1,
                              Visit&& visit) const {
  if (!x0.allFinite() || !m.allFinite() || !std::isfinite(h) || !std::isfinite(s0) || !std::isfinite(s1))
    throw Error(ErrorCode::NonFinite, "point/plane solve: the point, plane or time range is not finite");
  if (!(s1 >= s0))
    throw Error(ErrorCode::InvalidArgument, "point/plane solve: the time range is reversed (s1 < s0)");
  const double mn = m.norm();
  if (!(mn > 0)) throw Error(ErrorCode::DegenerateInput, "point/plane solve: the plane normal m is zero");
  const double wm = (M_.transpose() * m).norm();
  const double x0n = x0.norm();
  const double mu = mu_;
  const double ulps = options_.value_ulps * kUlp;
  const double mu_norm = u_.norm();

  auto eval = [&](double s) {
    const double k = s * kCacheSteps;
    Vector x;
    double xs;
    if (k >= 0 && k <= kCacheSteps && k == std::floor(k)) {  // cache lookup (same values)
      const Cached& e = cache_[static_cast<std::size_t>(k)];
      x = e.P.applyPoint(x0);
      xs = x0n * e.lnorm + e.tnorm;
    } else {
      const Affine3 P = span_.power(s);
      x = P.applyPoint(x0);
      xs = x0n * P.linear().norm() + P.translation().norm();
    }
    const Vector v = M_ * x + u_;
    Sample r;
    r.g = m.dot(x) - h;
    r.gp = m.dot(v);
    const double vn = v.norm();
    r.w = wm * vn;
    r.mv = mn * vn;
    xs += x.norm();
    r.eps = ulps * (mn * xs + std::abs(h));
    r.epsd = ulps * mn * (mu * xs + mu_norm);
    return r;
  };

  // Refines the root bracketed by sign(g(lo)) = sl != sign(g(hi)) on an interval where
  // |g'| >= gmin > 0 (monotone, certified by the derivative bound). By the mean value theorem
  // the root lies within (|g(t)| + eps_g) / gmin of any t, so safeguarded Newton steps stop as
  // soon as that radius is below half the time tolerance, or below the noise band
  // 2 eps_g / gmin when rounding does not allow the tolerance.
  auto refine = [&](double lo, double hi, int sl, const Sample& slo, double gmin) {
    const double tol = options_.time_tolerance;
    double t = lo - slo.g / slo.gp;
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
    double est = t;
    for (int it = 0; it < 200 && hi - lo > tol; ++it) {
      const Sample st = eval(t);
      est = t;
      const double rho = (std::abs(st.g) + st.eps) / gmin;
      if (rho <= std::max(0.5 * tol, 2 * st.eps / gmin)) {
        lo = std::max(lo, t - rho);
        hi = std::min(hi, t + rho);
        break;
      }
      if (signOf(st.g) == sl) lo = t; else hi = t;
      double next = st.gp != 0 ? t - st.g / st.gp : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      t = next;
    }
    PlaneRoot r;
    r.lo = lo;
    r.hi = hi;
    r.t = std::min(std::max(est, lo), hi);
    r.crossing = -sl;
    return r;
  };

  struct Interval { double a, b; };
  std::vector<Interval> stack;
  stack.push_back({s0, s1});
  int budget = options_.max_intervals;
  while (!stack.empty()) {
    const Interval iv = stack.back();
    stack.pop_back();
    const double a = iv.a, b = iv.b, c = 0.5 * (a + b), r = 0.5 * (b - a);
    const Sample sc = eval(c);
    const double z = r * mu;
    const double D = kBoundSlack * sc.w * r * phi1(z);
    const double E = kBoundSlack * sc.w * r * r * phi2(z);
    // Largest possible |g(s) - g(c)|: from the Taylor bound, or from |x(s) - x(c)| <=
    // |v(x(c))| r phi1(r |M|) (the point's path length), whichever is smaller.
    const double reach = std::min(std::abs(sc.gp) * r + E, kBoundSlack * sc.mv * r * phi1(z));
    if (std::abs(sc.g) - sc.eps > reach) continue;  // no root
    if (std::abs(sc.g) + reach <= sc.eps) {      // within eps of the plane throughout
      PlaneRoot p;
      p.t = p.lo = a;
      p.hi = b;
      p.crossing = 0;
      if (visit(p)) return;
      continue;
    }
    if (std::abs(sc.gp) - sc.epsd > D) {  // monotone: at most one root
      const Sample sa = eval(a), sb = eval(b);
      const int dir = signOf(sc.gp);
      PlaneRoot p;
      if (std::abs(sa.g) <= sa.eps) {
        p.t = p.lo = p.hi = a;
        p.crossing = dir;
      } else if (std::abs(sb.g) <= sb.eps) {
        p.t = p.lo = p.hi = b;
        p.crossing = dir;
      } else if (signOf(sa.g) != signOf(sb.g)) {
        p = refine(a, b, signOf(sa.g), sa, std::abs(sc.gp) - sc.epsd - D);
      } else {
        continue;
      }
      if (visit(p)) return;
      continue;
    }
    if (r <= 0.5 * options_.time_tolerance || --budget <= 0) {
      // Undecided at the time resolution: a touch (double root, or roots closer than the
      // tolerance), or the work limit.
      PlaneRoot p;
      p.t = c;
      p.lo = a;
      p.hi = b;
      p.crossing = 0;
      p.certain = budget > 0;
      if (visit(p)) return;
      if (budget <= 0) {
        // Report every undecided interval conservatively at its start and stop working.
        while (!stack.empty()) {
          const Interval rest = stack.back();
          stack.pop_back();
          PlaneRoot q;
          q.t = q.lo = rest.a;
          q.hi = rest.b;
          q.crossing = 0;
          q.certain = false;
          if (visit(q)) return;
        }
      }
      continue;
    }
    stack.push_back({c, b});  // right half after the left one
    stack.push_back({a, c});
  }
}

std::size_t SpanPlaneSolver::roots(const Vector& x0, const Vector& m, double h, double s0, double s1,
                                   std::vector<PlaneRoot>& out) const {
  const std::size_t before = out.size();
  isolate(x0, m, h, s0, s1, [&](const PlaneRoot& p) {
    // Merge with the previous root when they overlap within the time tolerance (a root on the
    // shared end of two intervals, or adjacent sliding pieces).
    if (out.size() > before) {
      PlaneRoot& q = out.back();
      if (p.lo <= q.hi + options_.time_tolerance) {
        q.hi = std::max(q.hi, p.hi);
        if (q.crossing != p.crossing) q.crossing = 0;
        q.certain = q.certain && p.certain;
        return false;
      }
    }
    out.push_back(p);
    return false;
  });
  return out.size() - before;
}

std::optional<PlaneRoot> SpanPlaneSolver::first(const Vector& x0, const Vector& m, double h, double s0,
                                                double s1) const {
  std::optional<PlaneRoot> found;
  isolate(x0, m, h, s0, s1, [&](const PlaneRoot& p) {
    found = p;
    return true;
  });
  return found;
}

}  // namespace steady
