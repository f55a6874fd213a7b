#pragma once
/// @file
/// Narrow phase of the contact predictor: the times at which a point carried by a SAM span meets
/// a static plane, found with a guarantee that no root is missed.
///
/// Along a span, the point at world position `x0` at span time 0 is at `x(s) = A^s x0`
/// (s in [0, 1] is the span's own parameter), and its signed plane function
/// `g(s) = m . x(s) - h` is a short sum of exponentials and damped sinusoids. Its derivative is
/// `g'(s) = m . v(x(s))`, with the span's stationary velocity field `v(p) = M p + u`, and since
/// `v(x(s)) = L^(s - c) v(x(c))`,
///
///     |g'(s) - g'(c)| <= |M^T m| |v(x(c))| (e^(r |M|) - 1) / |M|   for |s - c| <= r
///
/// (|.| the Euclidean norm, |M| the spectral norm, computed once per span). This
/// bound and its integral decide, on each interval, that there is no root (|g(c)| exceeds the
/// largest possible change), or that g is monotone (|g'(c)| exceeds the largest possible change
/// of g'), where a sign change brackets exactly one root; other intervals are halved. Roots are
/// refined by safeguarded Newton steps, stopped by the mean value theorem: where |g'| >= gmin,
/// the root is within |g(t)| / gmin of t. A double root (grazing) is located to about
/// sqrt(eps_g / |g''|) (1e-7 for unit sizes), the limit set by the rounding of g itself.
///
/// Rounding: every decision adds the value tolerance `eps_g = value_ulps * 2^-52 * (|m| (|x(c)| +
/// |x0| |L^c| + |t_c|) + |h|)` (t_c the translation of A^c) to the quantities it compares, so a
/// root is missed only if g stays within eps_g of zero around it: such near-touches are reported
/// as grazing contacts instead (never dropped). Intervals on which |g| <= eps_g throughout
/// (the point slides in the plane) are reported as one coincident contact from their start.

#include <steady/core/ear.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <vector>

namespace steady {

/// Options of the point/plane solver.
struct PlaneRootOptions {
  /// Roots are located to within this span time: a reported crossing lies in [lo, hi] with
  /// hi - lo <= time_tolerance, and `t` (Newton's estimate) inside; where rounding blurs g over
  /// a wider band (|g'| tiny), [lo, hi] is that band, 4 eps_g / |g'| wide. Default 1e-12.
  double time_tolerance = 1e-12;
  /// The value tolerance eps_g, in units of 2^-52 of the magnitudes involved (see the file
  /// comment). Default 64.
  double value_ulps = 64.0;
  /// Work limit: after this many intervals the remaining undecided ones are reported as
  /// possible contacts at their start (conservative: never a missed first contact), with
  /// `certain = false`. Reached only for pathological inputs.
  int max_intervals = 4096;
};

/// One contact of a point with a plane along a span.
struct PlaneRoot {
  double t = 0.0;    ///< span time of the contact (Newton's estimate, in [lo, hi])
  double lo = 0.0;   ///< the root lies in [lo, hi]; for the first contact, lo is never late
  double hi = 0.0;
  /// How g behaves: +1 crosses from negative to positive (the point leaves the plane's negative
  /// side), -1 from positive to negative, 0 touches without a certain crossing: a double root, a
  /// near-touch within eps_g, or a stretch [lo, hi] over which the point stays within eps_g of
  /// the plane (it slides in it).
  int crossing = 0;
  bool certain = true;  ///< false only when the work limit was reached (see PlaneRootOptions)
};

/// Precomputed data of one span for many point/plane solves (thread-safe for concurrent const
/// calls). Spans are queried over sub-intervals [s0, s1] of [0, 1] (or beyond: SAMs extend to
/// any real time); the powers A^s at s = k/128 are cached.
class SpanPlaneSolver {
 public:
  using Vector = Eigen::Vector3d;

  /// Precomputes the span's log norms and the cached powers (129 evaluations of A^s).
  explicit SpanPlaneSolver(const Span3& span, const PlaneRootOptions& options = {});

  /// Appends to `out` every contact time s in [s0, s1] of the point at `x0` (world position at
  /// span time 0) with the plane `m . x = h` (m need not be unit), in increasing order; returns
  /// the number appended. Throws Error(NonFinite) for non-finite input, Error(DegenerateInput)
  /// for m = 0 and Error(InvalidArgument) for s1 < s0.
  std::size_t roots(const Vector& x0, const Vector& m, double h, double s0, double s1,
                    std::vector<PlaneRoot>& out) const;
  /// The earliest contact in [s0, s1], or none; stops searching as soon as it is decided.
  std::optional<PlaneRoot> first(const Vector& x0, const Vector& m, double h, double s0 = 0.0,
                                 double s1 = 1.0) const;

  /// The span.
  const Span3& span() const { return span_; }
  /// `A^s` (from the cache when s = k/128, k = 0..128).
  Affine3 power(double s) const;

 private:
  template <class Visit>
  void isolate(const Vector& x0, const Vector& m, double h, double s0, double s1, Visit&& visit) const;

  Span3 span_;
  PlaneRootOptions options_;
  struct Cached {
    Affine3 P;             // A^(k/128)
    double lnorm, tnorm;   // |L|_F and |t| of P
  };
  Eigen::Matrix3d M_;
  Eigen::Vector3d u_;
  double mu_ = 0.0;      // spectral norm of M (upper bound)
  std::vector<Cached> cache_;
};

}  // namespace steady
