#pragma once
// Guaranteed root isolation of a smooth function of span time, shared by every contact feature.
//
// A feature function F provides
//   typename F::Sample sample(double s) const;   // with members g, gp, gpp (value, first and
//                                                 // second derivative at s; gpp is optional
//                                                 // and only steers the refinement), eps, epsd
//                                                 // (the rounding tolerances of g and gp)
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
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

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
// Both of them from one expm1, the same values as phi1(z) and phi2(z) (the derivative bounds
// need both per interval; expm1 was a twentieth of a point/plane solve's time). The searches
// halve from one span's [0, 1] again and again, so z = r |M| takes the same few values: a
// per-thread memo, direct-mapped on the exact bits of z, returns what the formula gave.
struct Phis {
  double p1, p2;
};
inline Phis phis(double z) {
  if (z < 1e-3) return {phi1(z), phi2(z)};
  struct Slot {
    std::uint64_t bits = 0;  // (0 is z = +0, never stored: z >= 1e-3 here)
    Phis value{0, 0};
  };
  thread_local std::array<Slot, 64> memo;
  std::uint64_t bits;
  std::memcpy(&bits, &z, sizeof bits);
  Slot& slot = memo[((bits ^ (bits >> 31)) * 0x9E3779B97F4A7C15ull) >> 58];
  if (slot.bits == bits) return slot.value;
  const double e = std::expm1(z);
  slot = {bits, {e / z, (e - z) / (z * z)}};
  return slot.value;
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

// Whether a feature's samples carry g'' (member gpp).
template <class S, class = void>
struct HasSecondDerivative : std::false_type {};
template <class S>
struct HasSecondDerivative<S, std::void_t<decltype(std::declval<S>().gpp)>> : std::true_type {};

template <class F, class Visit>
void isolateRoots(const F& f, double s0, double s1, const RootOptions& o, Visit&& visit) {
  using Sample = typename F::Sample;
  const double tol = o.time_tolerance;

  // Refines the root bracketed by sign(g(lo)) = sl != sign(g(hi)) on an interval where
  // |g'| >= gmin > 0. By the mean value theorem the root lies within (|g(t)| + eps) / gmin of
  // any t, so safeguarded Halley (or Newton) steps stop as soon as that radius is below half
  // the time tolerance, or below the noise band 2 eps / gmin when rounding does not allow the
  // tolerance.
  // The first guess interpolates the inverse function through the three samples at lo, the
  // middle and hi (a quadratic in g), or falls back to the secant of the ends: Newton from lo
  // took four samples per root on average, the last ones off the power cache.
  auto refine = [&](double lo, double hi, int sl, const Sample& slo, const Sample& smid, const Sample& shi,
                    double gmin) {
    const double mid = 0.5 * (lo + hi);
    const double ga = slo.g, gc = smid.g, gb = shi.g;
    double t = lo - ga * (hi - lo) / (gb - ga);
    if ((ga - gc) * (gc - gb) > 0) {  // (g monotone through the three samples: distinct values)
      t = lo * gc * gb / ((ga - gc) * (ga - gb)) + mid * ga * gb / ((gc - ga) * (gc - gb)) +
          hi * ga * gc / ((gb - ga) * (gb - gc));
    }
    if (!(t > lo && t < hi)) t = mid;
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
      // (Halley's step where the sample has g'': cubic convergence; else Newton's)
      double next = 0.5 * (lo + hi);
      if constexpr (HasSecondDerivative<Sample>::value) {
        const double den = 2 * st.gp * st.gp - st.g * st.gpp;
        if (den != 0) next = t - 2 * st.g * st.gp / den;
      } else {
        if (st.gp != 0) next = t - st.g / st.gp;
      }
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
        p = refine(a, b, signOf(sa.g), sa, sc, sb, std::abs(sc.gp) - sc.epsd - bd.D);
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
