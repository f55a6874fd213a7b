#pragma once
/// @file
/// Narrow phase of the contact predictor: the times at which features carried by a SAM span
/// meet static features, found with a guarantee that no root is missed.
///
/// Along a span, a body point at world position `x0` at span time 0 is at `x(s) = A^s x0` (s is
/// the span's own parameter, 0 to 1) and moves with the span's stationary velocity field
/// `v(p) = M p + u`; directions move by `L^s`. Two contact functions are solved:
/// - point/plane: `g(s) = m . x(s) - h` (a moving vertex against a static face's plane, or,
///   with the inverse span, a static vertex against a moving face);
/// - edge/edge: `g(s) = ((L^s e) x d) . (q0 - x(s))`, zero when the line of the moving edge
///   (through x(s), direction L^s e) and the static line (through q0, direction d) are coplanar.
///
/// Both are short sums of exponentials and damped sinusoids (products of two for edges). Since
/// `v(x(s)) = L^(s-c) v(x(c))` and `|L^(s-c)| <= e^(|s-c| |M|)` (|M| the spectral norm), the
/// derivatives of g over `|s - c| <= r` are bounded from the values at c. These bounds decide,
/// on each interval, that there is no root, or that g is monotone (then a sign change brackets
/// exactly one root, refined by safeguarded Newton steps, stopped by the mean value theorem:
/// where |g'| >= gmin the root is within |g(t)| / gmin of t); other intervals are halved.
///
/// Rounding: every decision adds a value tolerance eps_g to the quantities it compares. It is
/// `value_ulps * 2^-52` times the magnitudes that enter g (for point/plane,
/// `|m| (|x(s)| + |x0| |L^s| + |t_s|) + |h|`, t_s the translation of A^s). A root is missed only
/// if g stays within eps_g of zero around it; such near-touches are reported as touches
/// (crossing 0), never dropped, and so are stretches where |g| <= eps_g throughout (sliding).

#include <steady/core/ear.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace steady {

/// Options of the span root solvers.
struct RootOptions {
  /// Roots are located to within this span time: a reported crossing lies in [lo, hi] with
  /// hi - lo <= time_tolerance, and `t` (Newton's estimate) inside; where rounding blurs g over
  /// a wider band (|g'| tiny), [lo, hi] is that band, 4 eps_g / |g'| wide. A double root
  /// (grazing) is located to about sqrt(eps_g / |g''|), 1e-7 for unit sizes, the limit set by
  /// the rounding of g itself. Default 1e-12.
  double time_tolerance = 1e-12;
  /// The value tolerance eps_g, in units of 2^-52 of the magnitudes involved. Default 64.
  double value_ulps = 64.0;
  /// Work limit per solve: after this many halvings the undecided intervals are reported as
  /// possible contacts at their start (conservative: never a missed first contact), with
  /// `certain = false`. Reached only for pathological inputs.
  int max_intervals = 4096;
};

/// One root of a contact function along a span.
struct ContactRoot {
  double t = 0.0;    ///< span time of the contact (Newton's estimate, in [lo, hi])
  double lo = 0.0;   ///< the root lies in [lo, hi]; for the first contact, lo is never late
  double hi = 0.0;   ///< see lo
  /// How g behaves: +1 crosses from negative to positive, -1 from positive to negative, 0
  /// touches without a certain crossing: a double root, a near-touch within eps_g, or a stretch
  /// [lo, hi] over which g stays within eps_g of zero (sliding contact).
  int crossing = 0;
  bool certain = true;  ///< false only when the work limit was reached (see RootOptions)
};

/// Precomputed data of one span for many root solves: the log's norms and the powers A^s at
/// s = k/128 (k = 0..128). Const member functions are safe to call concurrently.
class SpanRoots {
 public:
  using Vector = Eigen::Vector3d;

  /// Precomputes the cache (129 evaluations of A^s). Throws Error(InvalidArgument) for bad
  /// options.
  explicit SpanRoots(const Span3& span, const RootOptions& options = {});
  /// The same without the cache when `cache_powers` is false: for a query that solves only a
  /// few dozen features on a span, the 129 powers cost more than they save. Answers are
  /// identical either way (a cached power is exactly the computed one).
  SpanRoots(const Span3& span, const RootOptions& options, bool cache_powers);

  /// Appends to `out`, in increasing order, every span time s in [s0, s1] at which the point at
  /// `x0` (world position at span time 0) is on the plane `m . x = h` (m need not be unit);
  /// returns the number appended. Throws Error(NonFinite) for non-finite input,
  /// Error(DegenerateInput) for m = 0 and Error(InvalidArgument) for s1 < s0.
  std::size_t pointPlane(const Vector& x0, const Vector& m, double h, double s0, double s1,
                         std::vector<ContactRoot>& out) const;
  /// The earliest point/plane contact in [s0, s1], or none; stops as soon as it is decided.
  std::optional<ContactRoot> firstPointPlane(const Vector& x0, const Vector& m, double h,
                                             double s0 = 0.0, double s1 = 1.0) const;

  /// Appends every span time in [s0, s1] at which the line through the moving edge (p0, p1)
  /// (world positions at span time 0) and the static line through (q0, q1) are coplanar: the
  /// candidate times of an edge/edge contact (the caller checks that the segments meet).
  /// Parallel lines are coplanar too, so times at which the edges turn parallel are roots.
  /// Throws Error(NonFinite), Error(DegenerateInput) for a zero-length edge,
  /// Error(InvalidArgument) for s1 < s0.
  std::size_t edgeEdge(const Vector& p0, const Vector& p1, const Vector& q0, const Vector& q1,
                       double s0, double s1, std::vector<ContactRoot>& out) const;
  /// The earliest edge/edge coplanarity in [s0, s1], or none.
  std::optional<ContactRoot> firstEdgeEdge(const Vector& p0, const Vector& p1, const Vector& q0,
                                           const Vector& q1, double s0 = 0.0, double s1 = 1.0) const;

  /// The span.
  const Span3& span() const { return span_; }
  /// The options.
  const RootOptions& options() const { return options_; }
  /// Spectral norm of the span's M (an upper bound): every point moves at most by a factor
  /// e^(|s| norm) of its velocity, see the file comment.
  double logNorm() const { return mu_; }
  /// `A^s` (from the cache when s = k/128, k = 0..128).
  Affine3 power(double s) const;
  /// `A^s` with `|L^s|_F` and `|t_s|` (the magnitudes used by the rounding tolerances).
  void power(double s, Affine3& P, double& lnorm, double& tnorm) const;

 private:
  struct Cached {
    Affine3 P;            // A^(k/128)
    double lnorm, tnorm;  // |L|_F and |t| of P
  };
  Span3 span_;
  RootOptions options_;
  Eigen::Matrix3d M_;
  Eigen::Vector3d u_;
  double mu_ = 0.0;  // spectral norm of M (upper bound)
  std::vector<Cached> cache_;
  std::uint64_t id_ = 0;  // identity for a per-thread memo of powers off the cache grid
};

}  // namespace steady
