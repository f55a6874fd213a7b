#pragma once
/// @file
/// Motions built from SAM spans: polySAMs through key poses, SAM Bézier and bi-arc curves,
/// four-point subdivision, SAM patches, Alexa's blends (as comparators) and the ARA steadiness
/// measure.
///
/// Two types carry a motion:
/// - Motion: a chain of SAM spans over key times. This is what the sweep and collision modules
///   consume; every span has a stationary velocity field.
/// - KeyframeMotion: a motion as a user describes it (key poses plus an interpolation). It
///   evaluates the exact curve and converts itself to a Motion: exactly for the piecewise
///   steady kinds (polySAM, subdivision), within a reported pose tolerance for the curved ones
///   (Bézier, bi-arc), which are not steady.
///
/// Time: span i of a Motion covers key times `[t_i, t_{i+1}]`; at time t in it the pose is
/// `A_i^s P_i` with `s = (t - t_i) / (t_{i+1} - t_i)` and `A_i = P_{i+1} P_i^-1`. Velocities are
/// per unit of that global time, i.e. the span's field divided by the span's duration.

#include <steady/core/ear.hpp>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace steady {

template <int D>
class KeyframeMotion;
struct ApproximationOptions;

/// A key pose at a key time. Poses map body coordinates to world coordinates.
template <int D>
struct Keyframe {
  double t = 0.0;    ///< key time
  Affine<D> pose;    ///< body-to-world pose at `t`
};

/// An axis-aligned box (in body coordinates when it describes a body).
template <int D>
struct Box {
  using Vector = typename Affine<D>::Vector;
  Vector lo = Vector::Zero();  ///< lower corner
  Vector hi = Vector::Zero();  ///< upper corner

  /// The smallest box that holds every point. Throws Error(DegenerateInput) for no point and
  /// Error(NonFinite) for a non-finite coordinate.
  static Box of(const std::vector<Vector>& points);
  /// The 2^D corners, in binary order of (x, y[, z]) with x fastest.
  std::vector<Vector> corners() const;
  /// Length of the diagonal `|hi - lo|`.
  double diagonal() const { return (hi - lo).norm(); }
};

/// What a polySAM does when two consecutive key poses have no SAM between them.
enum class NoSamPolicy {
  Fail,   ///< throw Error(NoRealLog) (or the underlying reason) naming the span
  Split,  ///< insert the midpoint of an always-defined unsteady interpolation
          ///< (polarInterpolate) and retry, recursively; the inserted spans are reported
};

/// Options of the motion constructions.
struct MotionOptions {
  EarOptions ear;                            ///< options of every log/power
  NoSamPolicy no_sam = NoSamPolicy::Fail;    ///< see NoSamPolicy
  /// Depth limit of the Split fallback: a span is halved at most this many times. 2^12
  /// sub-spans have never been needed; reaching the limit throws Error(NoRealLog).
  int max_split_depth = 12;
};

/// The velocity discontinuity of a polySAM at one joint.
struct VelocityJump {
  std::size_t joint = 0;   ///< index of the key pose between span joint-1 and span joint
  double t = 0.0;          ///< key time of the joint
  /// Largest `|v_after - v_before|` over the corners of the body box at the joint pose
  /// (length per unit time).
  double magnitude = 0.0;
  /// magnitude divided by the largest speed of those corners on either side (0 when the body
  /// is at rest on both sides). 0 means C1 at this joint.
  double relative = 0.0;
};

/// A chain of SAM spans through key poses at increasing key times (a polySAM). C0 at the
/// joints, with velocity jumps there (see velocityJumps()).
template <int D>
class Motion {
 public:
  using Vector = typename Affine<D>::Vector;

  /// The polySAM through `keys` (at least 2, times strictly increasing and finite). Throws
  /// Error(InvalidArgument) for times that do not increase, Error(NonFinite) for a non-finite
  /// time, Error(NonFinite) / Error(NotOrientationPreserving)
  /// / Error(Singular) for a bad pose (naming it), and, with NoSamPolicy::Fail, the reason a
  /// span has no SAM, naming the span ("span 2 (key 2 -> 3)").
  static Motion polySam(const std::vector<Keyframe<D>>& keys, const MotionOptions& options = {});
  /// The polySAM through `poses` at key times i / (n - 1).
  static Motion polySam(const std::vector<Affine<D>>& poses, const MotionOptions& options = {});

  /// Number of SAM spans (key poses minus one, plus the spans inserted by the fallback).
  std::size_t spanCount() const { return spans_.size(); }
  /// Span i, parameterised over [0, 1]: `span(i).pose(s)`.
  const Span<D>& span(std::size_t i) const { return spans_[i]; }
  /// Key time at which span i starts.
  double spanBegin(std::size_t i) const { return times_[i]; }
  /// Key time at which span i ends.
  double spanEnd(std::size_t i) const { return times_[i + 1]; }
  /// Whether span i was introduced by the NoSamPolicy::Split fallback (its end poses are not
  /// both user key poses).
  bool spanIsFallback(std::size_t i) const { return fallback_[i] != 0; }
  /// Number of spans for which spanIsFallback() holds.
  std::size_t fallbackSpanCount() const;
  /// First key time.
  double beginTime() const { return times_.front(); }
  /// Last key time.
  double endTime() const { return times_.back(); }
  /// The span that holds time t: at an interior key time, the span that starts there; times
  /// outside the key range go to the first or last span, which then extrapolates its SAM.
  std::size_t spanIndex(double t) const;
  /// The pose at time t.
  Affine<D> pose(double t) const;
  /// The world velocity, at time t, of the body point currently at world position p (per unit
  /// key time). At a joint, the velocity of the span that starts there.
  Vector velocity(double t, const Vector& p) const;
  /// The key poses, including those inserted by the fallback.
  std::vector<Keyframe<D>> keyframes() const;
  /// The velocity jump at every interior joint for a body occupying `body` (body
  /// coordinates).
  std::vector<VelocityJump> velocityJumps(const Box<D>& body) const;
  /// For a Motion made by approximating a curved motion: the largest deviation measured
  /// between the curve and the spans (see ApproximationOptions). 0 for an exact polySAM.
  double approximationError() const { return approximation_error_; }

 private:
  friend class KeyframeMotion<D>;
  template <int E>
  friend Motion<E> approximate(const std::function<Affine<E>(double)>&, double, double,
                               const Box<E>&, const ApproximationOptions&,
                               const MotionOptions&);
  Motion() = default;
  std::vector<double> times_;
  std::vector<Span<D>> spans_;
  std::vector<Affine<D>> poses_;  // key poses, one per time
  std::vector<char> fallback_;
  double approximation_error_ = 0.0;
};

/// How a curved (unsteady) motion is replaced by a polySAM.
struct ApproximationOptions {
  /// If positive: exactly this many spans of equal duration, and no tolerance control (the
  /// deviation is still measured and reported).
  int spans = 0;
  /// Otherwise: spans are halved until the deviation is at most `tolerance` times the body
  /// box diagonal. The deviation of a span is the largest distance between the curve's and
  /// the span's images of the body box corners, measured at s = 1/4, 1/2, 3/4 of the span
  /// (the span interpolates the curve at s = 0 and 1).
  double tolerance = 1e-3;
  /// Safety limit: more spans than this throws Error(InvalidArgument) (the curve is not
  /// continuous, or the tolerance is too small for double precision).
  int max_spans = 1 << 16;
};

/// A polySAM approximating `curve` over [t0, t1] for a body in `body` (see
/// ApproximationOptions). The result's approximationError() is the measured deviation.
template <int D>
Motion<D> approximate(const std::function<Affine<D>(double)>& curve, double t0, double t1,
                      const Box<D>& body, const ApproximationOptions& approximation = {},
                      const MotionOptions& options = {});

// --- constructions on poses (SAM paper §5.3, §7) -----------------------------------------

/// `(F_B F_A^-1)^t F_X`: the SAM from A to B applied to X (the paper's SAM(F_X, F_A, t, F_B)).
template <int D>
Affine<D> samFrom(const Affine<D>& X, const Affine<D>& A, double t, const Affine<D>& B,
                  const EarOptions& options = {});

/// The SAM Bézier curve with control poses `controls` (2 or more) at parameter s, by de
/// Casteljau's algorithm with SAM in place of linear interpolation (3 controls: the quadratic
/// `SAM(SAM(F_A,s,F_B), s, SAM(F_B,s,F_C))`, 4: the cubic). Interpolates the first and last
/// control pose. Throws like sam() when an intermediate pair has no SAM.
template <int D>
Affine<D> bezier(const std::vector<Affine<D>>& controls, double s, const EarOptions& options = {});

/// The bi-arc control pose `SAM(SAM(F_A, 3/4, F_B), F_C, 1/4, F_B)` (the paper's leftControl).
template <int D>
Affine<D> biArcControl(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C,
                       const EarOptions& options = {});

/// The bi-arc through A (s = 0), B (s = 1/2) and C (s = 1): two quadratic SAM Béziers
/// (A, L, B) and (B, R, C) with `L = biArcControl(A, B, C)`, `R = biArcControl(C, B, A)`. C1 at
/// B, and `B = sam(L, 1/2, R)`.
template <int D>
struct BiArc {
  Affine<D> A, L, B, R, C;  ///< the five control poses
  /// The bi-arc through three poses. Throws like sam().
  static BiArc through(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C,
                       const EarOptions& options = {});
  /// The pose at s in [0, 1].
  Affine<D> pose(double s, const EarOptions& options = {}) const;
};

/// Rounds of four-point subdivision in the space of affinities: each round keeps the n poses
/// at even indices and inserts n - 1 predictions (2n - 1 poses out), with weights tending to
/// (-1/16, 9/16, 9/16, -1/16) when the poses commute. Needs n >= 3; end spans use the
/// three-point prediction. Regular patterns stay regular. Throws like sam().
template <int D>
std::vector<Affine<D>> subdivide(const std::vector<Affine<D>>& poses, int rounds,
                                 const EarOptions& options = {});
/// Subdivision of keyframes: poses as above, inserted key times at the midpoints.
template <int D>
std::vector<Keyframe<D>> subdivide(const std::vector<Keyframe<D>>& keys, int rounds,
                                   const EarOptions& options = {});

/// The SAM patch through four corner poses: `pose(s, u) = SAM(SAM(A,s,B), u, SAM(C,s,D))`.
template <int D>
class SamPatch {
 public:
  /// The patch with corners A (0,0), B (1,0), C (0,1), D (1,1).
  static SamPatch corners(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C,
                          const Affine<D>& D4, const EarOptions& options = {});
  /// The regular patch: D = B A^-1 C, so that `pose(s, u) = M^s N^u A` with `M = B A^-1`,
  /// `N = C A^-1` (for any M and N: the row at s runs from M^s A to M^s C).
  static SamPatch regular(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C,
                          const EarOptions& options = {});
  /// The pose at (s, u).
  Affine<D> pose(double s, double u) const;
  /// The (ns + 1) x (nu + 1) poses at s = i / ns, u = j / nu, row-major in u (index j (ns+1) + i).
  std::vector<Affine<D>> grid(int ns, int nu) const;
  /// The fourth corner (D).
  const Affine<D>& cornerD() const { return d_; }

 private:
  SamPatch(const Affine<D>& A, const Affine<D>& B, const Affine<D>& C, const Affine<D>& D4,
           const EarOptions& options);
  Span<D> bottom_, top_;
  Affine<D> d_;
  EarOptions options_;
};

// --- unsteady comparators -----------------------------------------------------------------

/// The polar-decomposition Log-Exp interpolation from B (t = 0) to C (t = 1): with
/// `C B^-1 = [R S | w]` (R a rotation, S symmetric positive definite), the pose
/// `[R^t S^t | t w] B`. Defined whenever det > 0 (a rotation by exactly a half turn takes the
/// HalfTurn convention), but not steady. Used by the NoSamPolicy::Split fallback.
template <int D>
Affine<D> polarInterpolate(const Affine<D>& B, const Affine<D>& C, double t,
                           const EarOptions& options = {});

/// `exp([M | u])`, the affinity whose homogeneous log is X (Eigen's scaling and squaring with a
/// Padé approximant: a few ulps for |X| of order 1; the error grows about linearly with |X|,
/// e.g. a rotation by an angle a is accurate to about a * 1e-16).
template <int D>
Affine<D> exp(const AffineLog<D>& X);

/// Alexa's `A ⊕ B = exp(log A + log B)`. Throws like log().
template <int D>
Affine<D> alexaAdd(const Affine<D>& A, const Affine<D>& B, const EarOptions& options = {});
/// Alexa's weighted blend `exp(sum_i w_i log T_i)`. Throws Error(InvalidArgument) for sizes
/// that differ or no pose, and like log().
template <int D>
Affine<D> alexaBlend(const std::vector<Affine<D>>& poses, const std::vector<double>& weights,
                     const EarOptions& options = {});
/// Alexa's interpolation `exp((1 - t) log B + t log C)`; steady only when B and C commute.
template <int D>
Affine<D> alexaInterpolate(const Affine<D>& B, const Affine<D>& C, double t,
                           const EarOptions& options = {});
/// Linear interpolation of the matrices, `(1 - t) B + t C` (an unsteady comparator).
template <int D>
Affine<D> lerp(const Affine<D>& B, const Affine<D>& C, double t);

// --- steadiness ------------------------------------------------------------------------------

/// Sampling of the ARA measure.
struct AraOptions {
  /// Sample times: the midpoints of this many equal sub-intervals of [t0 + 9h T, t1 - 9h T]
  /// (T = t1 - t0, h = step), inset so that no difference stencil leaves [t0, t1] (curves may
  /// be clamped or undefined outside it).
  int time_samples = 64;
  int space_samples = 4;   ///< a grid of this many points per axis over the region (corners included)
  /// Central-difference step, relative to the duration t1 - t0: `W(t) = A(t)^-1 A'(t)` uses
  /// step h, and `W'(t)` uses step 8h.
  double step = 1e-3;
};

/// The ARA steadiness measure of a motion over a region (body coordinates): the mean, over the
/// sample times and the grid points p, of `|W'(t) [p; 1]|` where `W(t) = A(t)^-1 A'(t)` is the
/// body-frame velocity (so `W(t)[p;1] = L(t)^-1 d/dt A_t(p)`), divided by the region's
/// diagonal. Zero up to rounding for a SAM, for which W is constant (about 1e-11 for a unit
/// region and motions of unit size); positive for unsteady motions (from Rot 90 deg to
/// Translate(6, 0) over the square [-1, 1]^2: linear interpolation 4.8, Alexa's blend 0.85). Time is normalised to [0, 1] so the value does not depend on t1 - t0.
/// Derivatives are central differences (see AraOptions).
template <int D>
double ara(const std::function<Affine<D>(double)>& motion, double t0, double t1,
           const Box<D>& region, const AraOptions& options = {});
/// ARA of a polySAM, averaged over its spans with the stencil kept inside each span (the
/// velocity jumps at joints are reported by Motion::velocityJumps instead). Each span is zero
/// up to rounding, which the time normalisation amplifies: about 1e-11 n^2 for n equal spans.
template <int D>
double ara(const Motion<D>& motion, const Box<D>& region, const AraOptions& options = {});

// --- motions as users describe them -----------------------------------------------------------

/// How key poses are joined.
enum class Interpolation {
  PolySam,    ///< one SAM span per pair of consecutive keys
  Bezier,     ///< one SAM Bézier curve with the keys as control poses (times: first to last)
  BiArc,      ///< bi-arcs through keys 0-1-2, 2-3-4, ... (an odd number of keys, at least 3)
  Subdivide,  ///< polySAM through the keys after `rounds` rounds of four-point subdivision
};

/// Stable name ("polysam", "bezier", "biarc", "subdivide").
const char* to_string(Interpolation kind) noexcept;

/// A motion described by key poses and an interpolation. Evaluates the exact curve and
/// converts to a Motion (spans) for the sweep and collision modules.
template <int D>
class KeyframeMotion {
 public:
  /// Validates the keys (count for the kind, finite increasing times, poses with det > 0)
  /// and, for PolySam and Subdivide, builds the spans. `rounds` is used by Subdivide only
  /// (0 to 8). Throws typed errors naming the offending key or span.
  KeyframeMotion(std::vector<Keyframe<D>> keys, Interpolation kind, int rounds = 3,
                 const MotionOptions& options = {});

  /// The interpolation kind.
  Interpolation interpolation() const { return kind_; }
  /// The keys as given.
  const std::vector<Keyframe<D>>& keyframes() const { return keys_; }
  /// First key time.
  double beginTime() const { return keys_.front().t; }
  /// Last key time.
  double endTime() const { return keys_.back().t; }
  /// Whether the motion is a chain of SAM spans (PolySam, Subdivide): then toMotion() is exact.
  bool piecewiseSteady() const { return kind_ == Interpolation::PolySam || kind_ == Interpolation::Subdivide; }
  /// The exact pose at time t (clamped to [beginTime, endTime] for the curved kinds).
  /// For BiArc, key times map piecewise linearly to the bi-arc parameter (C1 in time when
  /// the middle key time is the midpoint).
  Affine<D> pose(double t) const;
  /// The motion as SAM spans for a body in `body`: the exact polySAM for the piecewise steady
  /// kinds, else approximate() with `approximation`.
  Motion<D> toMotion(const Box<D>& body, const ApproximationOptions& approximation = {}) const;

 private:
  std::vector<Keyframe<D>> keys_;
  Interpolation kind_;
  MotionOptions options_;
  std::vector<Motion<D>> steady_;        // PolySam / Subdivide: one element
  std::vector<BiArc<D>> arcs_;           // BiArc: one per key triple
};

using Motion2 = Motion<2>;
using Motion3 = Motion<3>;
using KeyframeMotion2 = KeyframeMotion<2>;
using KeyframeMotion3 = KeyframeMotion<3>;

}  // namespace steady
