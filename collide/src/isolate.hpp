#pragma once
// Guaranteed root isolation of a smooth function of span time, shared by every contact feature.
//
// A feature function F provides
//   typename F::Sample sample(double s) const;   // with members g, gp (value and derivative at
//                                                 // s), eps, epsd (their rounding tolerances)
//   Bounds bounds(const Sample& c, double r) const;  // valid for |s - c| <= r:
//       D     >= |g'(s) - g'(c)|
//       reach >= |g(s) - g(c)|
// and isolateRoots() visits every root in [s0, s1] in increasing time: an interval is dropped
// when |g(c)| - eps > reach, reported whole as a touch when |g(c)| + reach <= eps, searched for
// its single root when |g'(c)| - epsd > D (monotone), and halved otherwise, down to half the time
// tolerance (then reported as a touch: a double root or roots closer than the tolerance).
#include <steady/collide/span_roots.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>

namespace steady::detail {

struct Bounds {
  double D = 0;      // bound of |g'(s) - g'(c)|
  double reach = 0;  // bound of |g(s) - g(c)|
};

inline int signOf(double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }

// (e^z - 1) / z and (e^z - 1 - z) / z^2 for z >= 0, accurate near 0.
inline double phi1(double z) { return z < 1e-8 ? 1.0 + 0.5 * z : std::expm1(z) / z; }
inline double phi2(double z) {
  if (z < 1e-3) return 0.5 + z * (1.0 / 6 + z * (1.0 / 24 + z / 120));
  return (std::expm1(z) - z) / (z * z);
}

// An upper bound of the spectral norm of M (its largest singular value): the eigen-solve of
// M^T M, inflated by 1e-12 relative so that its rounding cannot make it an underestimate, capped
// by the Frobenius norm (always an upper bound).
inline double spectralBound(const Eigen::Matrix3d& M) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M.transpose() * M, Eigen::EigenvaluesOnly);
  return std::min(M.norm(), std::sqrt(std::max(0.0, es.eigenvalues().maxCoeff())) * (1 + 1e-12) + 1e-300);
}

// Relative inflation of every derivative bound, for the rounding of its own evaluation (a few
// dozen flops on positive numbers).
constexpr double kBoundSlack = 1.0 + 1e-12;

template <class F, class Visit>
void isolateRoots(const F& f, double s0, double s1, const RootOptions& o, Visit&& visit) {
  using Sample = typename F::Sample;
  const double tol = o.time_tolerance;

  // Refines the root bracketed by sign(g(lo)) = sl != sign(g(hi)) on an interval where
  // |g'| >= gmin > 0. By the mean value theorem the root lies within (|g(t)| + eps) / gmin of
  // any t, so safeguarded Newton steps stop as soon as that radius is below half the time
  // tolerance, or below the noise band 2 eps / gmin when rounding does not allow the tolerance.
  auto refine = [&](double lo, double hi, int sl, const Sample& slo, double gmin) {
    double t = slo.gp != 0 ? lo - slo.g / slo.gp : 0.5 * (lo + hi);
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
    double est = t;
    for (int it = 0; it < 200 && hi - lo > tol; ++it) {
      const Sample st = f.sample(t);
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
    ContactRoot r;
    r.lo = lo;
    r.hi = hi;
    r.t = std::min(std::max(est, lo), hi);
    r.crossing = -sl;
    return r;
  };

  struct Interval {
    double a, b;
  };
  // Depth-first, left half first. Each halving adds one entry, and halving stops at tol / 2, so
  // the stack never holds more than log2((s1 - s0) / tol) + 1 entries; beyond kStack the
  // interval is reported as undecided (certain = false), which needs s1 - s0 > 2^120 tol.
  constexpr int kStack = 120;
  std::array<Interval, kStack> stack;
  int top = 0;
  stack[top++] = {s0, s1};
  int budget = o.max_intervals;
  auto undecided = [&](double a, double b, double t, bool certain) {
    ContactRoot p;
    p.t = t;
    p.lo = a;
    p.hi = b;
    p.crossing = 0;
    p.certain = certain;
    return visit(p);
  };
  while (top > 0) {
    const Interval iv = stack[--top];
    const double a = iv.a, b = iv.b, c = 0.5 * (a + b), r = 0.5 * (b - a);
    const Sample sc = f.sample(c);
    const Bounds bd = f.bounds(sc, r);
    if (std::abs(sc.g) - sc.eps > bd.reach) continue;  // no root
    if (std::abs(sc.g) + bd.reach <= sc.eps) {         // within eps of zero throughout
      if (undecided(a, b, a, true)) return;
      continue;
    }
    if (std::abs(sc.gp) - sc.epsd > bd.D) {  // monotone: at most one root
      const Sample sa = f.sample(a), sb = f.sample(b);
      const int dir = signOf(sc.gp);
      ContactRoot p;
      if (std::abs(sa.g) <= sa.eps) {
        p.t = p.lo = p.hi = a;
        p.crossing = dir;
      } else if (std::abs(sb.g) <= sb.eps) {
        p.t = p.lo = p.hi = b;
        p.crossing = dir;
      } else if (signOf(sa.g) != signOf(sb.g)) {
        p = refine(a, b, signOf(sa.g), sa, std::abs(sc.gp) - sc.epsd - bd.D);
      } else {
        continue;
      }
      if (visit(p)) return;
      continue;
    }
    if (r <= 0.5 * tol || --budget <= 0 || top + 2 > kStack) {
      // Undecided at the time resolution: a touch (double root, or roots closer than the
      // tolerance); or a work limit, after which every pending interval is reported
      // conservatively at its start.
      const bool certain = r <= 0.5 * tol;
      if (undecided(a, b, c, certain)) return;
      if (!certain) {
        while (top > 0) {
          const Interval rest = stack[--top];
          if (undecided(rest.a, rest.b, rest.a, false)) return;
        }
      }
      continue;
    }
    stack[top++] = {c, b};  // the right half after the left one
    stack[top++] = {a, c};
  }
}

// Appends the roots visited by isolateRoots to `out`, merging roots whose brackets meet within
// the time tolerance (a root on the shared end of two intervals, adjacent touching pieces).
inline bool appendMerged(std::vector<ContactRoot>& out, std::size_t first, const ContactRoot& p,
                         double tol) {
  if (out.size() > first) {
    ContactRoot& q = out.back();
    if (p.lo <= q.hi + tol) {
      q.hi = std::max(q.hi, p.hi);
      if (q.crossing != p.crossing) q.crossing = 0;
      q.certain = q.certain && p.certain;
      return false;
    }
  }
  out.push_back(p);
  return false;
}

}  // namespace steady::detail
