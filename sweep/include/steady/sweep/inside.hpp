#pragma once
/// @file
/// The inside test of a swept volume: is a world point inside the volume `⋃_t pose(t)(body)`
/// swept by a body along a SAM span or a polySAM? Exact up to a documented tolerance, without
/// building the envelope.
///
/// Method. A world point x is inside the swept volume iff for some time t the body point
/// `pose(t)^-1 x` is inside the body. On a span with pose `A^τ B`, work in the frame of the span
/// start (the body posed by B, vertices `W = B p`): there the point moves along
/// `z(τ) = A^-τ x`, which is the trajectory of a point on the same SAM run backwards (span
/// times s = -τ in [-1, 0]). So
/// - x is inside at the start of the motion (a static test, below), or
/// - z(τ) enters the posed body at some first time τe; then z(τe) lies on a face f, so τe is a
///   root of the point/plane function `m_f · z(τ) - h_f` (a short sum of exponentials and damped
///   sinusoids), which collide's SpanRoots isolates with a guarantee that no root is missed
///   (span_roots.hpp). At each root, x is compared with the face posed at that time.
/// Only the motion start needs the static test: a point inside at the start of a later span
/// was reached during an earlier span. The backward trajectory is evaluated as the span's own
/// SAM at negative times, never through the log of the inverse relative motion (for a half
/// turn that log may turn the other way). Roots reported as a band (the point slides in the face's
/// plane, or a double root known only to about 1e-7 in time) are resolved by solving, over the
/// band, the planes through the face's edges perpendicular to the face: the point can only
/// enter the face across one of them.
///
/// Static test (the body posed at the motion start): x is inside if it is within the tolerance
/// δ of a posed face; otherwise by ray parity in body coordinates with filtered exact
/// orientation signs: the segment from x to a far point crosses a triangle when both
/// orientation signs are certain (the determinant exceeds its rounding bound); a segment that
/// passes within rounding of an edge or a vertex, or runs nearly parallel to a triangle whose
/// plane holds x, is cast again in another of 32 fixed directions (a generalized winding
/// number decides if all of them are ambiguous, which needs a point within rounding of the
/// surface: not seen in practice since such points are within δ and already decided).
///
/// Broad phase. A bounding-volume hierarchy of the body faces (body coordinates) is built once.
/// Over a time interval of half width r about c the trajectory stays within
/// `r²/2 μ e^(rμ) |v(z(c))|` of its chord (μ ≥ |M|₂; linear interpolation error, as for the
/// sweep's strips); intervals with many face boxes near the chord's box are halved, and only
/// the faces within that distance of the chord (plus the tolerance) are solved. (The ball
/// about z(c) that bounded the whole interval before sent 14 times more faces to the root
/// solver for points near a swept surface.) A face is measured against the chord only when
/// the chord is not wholly beyond that distance outside the face's plane or outside one of
/// the three planes through its edges perpendicular to it (cheap tests, which settle a third
/// of the faces that the distance alone settled before, on the elephant's screw).
///
/// Tolerance (δ, world units). A point is reported inside when, at the reported time, it is
/// inside the posed body or within `δ + η` of its surface, where η is the distance the surface
/// moves over the width of the root's time bracket (at most δ; about 1e-12 times the largest
/// speed for a transversal crossing). So every point reported inside is within `2 δ` of the
/// swept volume. Conversely every point that enters the interior of a posed body is reported
/// inside, except within rounding of degenerate configurations (a trajectory that runs along an
/// edge line of a face) and when the root solver's work limit (RootOptions::max_intervals) is
/// reached, whose undecided intervals are checked like bands. Points on the boundary of the
/// swept volume that a face slides over (in the face's plane) are reported inside; points that
/// the body touches only at an isolated instant (the trajectory tangent to a face), and points
/// within 2 δ outside the swept volume, may go either way.
///
/// Cost: building is O(F log F + spans (F + 129 poses)); a query solves a few point/plane
/// functions per face near the trajectory (about 0.2 to 1 µs each), so a point far from every
/// posed body costs a few box tests per span. Const queries are safe to run concurrently.

#include <steady/collide/span_roots.hpp>
#include <steady/core/motion.hpp>
#include <steady/sweep/body.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <optional>

namespace steady::sweep {

/// Options of the swept-volume inside test.
struct InsideOptions {
  /// δ: a point within this world distance of the posed body's surface at some time counts as
  /// inside (see the file comment). Must be finite and positive. Unset:
  /// `relative_tolerance` times the bounding-box diagonal of the body (body coordinates).
  std::optional<double> tolerance;
  /// Used when `tolerance` is unset; must be finite and positive. Default 1e-9: far above the
  /// rounding of the poses (about 1e-16 times the scene size times the condition of the pose),
  /// far below any modelling precision.
  double relative_tolerance = 1e-9;
  /// Options of the root isolation (collide's span_roots.hpp).
  RootOptions roots;
};

/// The answer of one query.
struct InsideResult {
  /// x is inside the swept volume (within the tolerance, see the file comment).
  bool inside = false;
  /// When inside: the earliest time at which x is inside the posed body or on its surface
  /// (within δ + η); motion key time for a Motion3, span time τ in [0, 1] for a Span3. No
  /// earlier time has x inside the posed body (up to the rounding caveat of the file comment).
  double time = 0.0;
  /// When inside: the span of `time`.
  std::size_t span = 0;
  /// When inside: the face through which x is reached at `time`, or -1 when x is inside (or
  /// within δ of) the body at the start of the motion.
  int face = -1;
};

/// A time at which a point lies strictly inside the posed body (SweptVolume::hint), for
/// asking about many points near it (SweptVolume::contains with a hint).
struct InsideHint {
  std::size_t span = 0;  ///< the span
  double tau = 0.0;      ///< span time τ in [0, 1]
};

/// The volume swept by a body along a motion, prepared for many inside queries.
///
/// Holds copies of what it needs (the body's mesh and a box hierarchy of its faces, about 100
/// bytes a face, the spans, and per span a table of 1,025 poses along it, about 115 KB); the
/// Body and Motion may be destroyed afterwards.
class SweptVolume {
 public:
  /// Prepares the queries for `body` along every span of `motion`.
  /// @throws Error(InvalidArgument) for a tolerance (or relative tolerance) that is not finite
  ///   and positive, or bad root options; Error(NonFinite) when a posed body overflows;
  ///   Error(Singular) when a span's start pose is not invertible.
  SweptVolume(const Body& body, const Motion3& motion, const InsideOptions& options = {});
  /// Prepares the queries for `body` along one span (pose `span.pose(τ)`, τ in [0, 1]); times
  /// in the results are span times. Throws like the Motion3 constructor.
  SweptVolume(const Body& body, const Span3& span, const InsideOptions& options = {});
  ~SweptVolume();
  SweptVolume(SweptVolume&&) noexcept;
  SweptVolume& operator=(SweptVolume&&) noexcept;
  SweptVolume(const SweptVolume&) = delete;
  SweptVolume& operator=(const SweptVolume&) = delete;

  /// Whether the world point x is inside the swept volume (see the file comment).
  /// @throws Error(NonFinite) when x has a NaN or infinite coordinate.
  bool contains(const Eigen::Vector3d& x) const;
  /// Whether x is inside, and the earliest time at which the body reaches it.
  /// @throws Error(NonFinite) when x has a NaN or infinite coordinate.
  InsideResult query(const Eigen::Vector3d& x) const;
  /// A time at which x lies strictly inside the posed body, or none: after query(x).time, the
  /// first such time in steps of 2^-16 of the span (at most 256 steps), then steps doubling
  /// from it while x stays inside (up to 256 steps away), and the middle of that run. Each is a
  /// static test: x in body coordinates, farther than its rounding from every face, inside by
  /// ray parity. For a caller about to ask about many points near x (the sweep's depth
  /// certificates). Depends on x alone, not on threads or earlier queries.
  /// @throws Error(NonFinite) when x has a NaN or infinite coordinate.
  std::optional<InsideHint> hint(const Eigen::Vector3d& x) const;
  /// contains(y), settled by one static test when y lies strictly inside the body posed at the
  /// hint's time (a point inside a posed body is in the interior of the swept volume, which
  /// contains() reports inside), else by contains(y). The answers are those of contains(y),
  /// except where contains() misses an interior point (the rounding caveat of the file
  /// comment), which this reports inside. (On bunny00 along data/motions/screw.json, a count
  /// with a hint at the middle of the whole run: 97.5% of the 1.67M inside answers of the kept
  /// walls' depth certificates came from the static test.)
  /// @throws Error(NonFinite) when y has a NaN or infinite coordinate.
  bool contains(const Eigen::Vector3d& y, const InsideHint& hint) const;
  /// Whether x is inside the body (or within δ of its surface) at the start of the motion.
  /// @throws Error(NonFinite) when x is not finite.
  bool containsAtStart(const Eigen::Vector3d& x) const;
  /// δ, world units.
  double tolerance() const;
  /// Number of spans.
  std::size_t spanCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Whether the world point x is inside the volume swept by `body` along `motion` (builds a
/// SweptVolume; prefer the class for many points). Throws like SweptVolume.
bool sweptContains(const Body& body, const Motion3& motion, const Eigen::Vector3d& x,
                   const InsideOptions& options = {});

/// Whether the world point x is inside the volume swept by `body` along one span. Throws like
/// SweptVolume.
bool sweptContains(const Body& body, const Span3& span, const Eigen::Vector3d& x,
                   const InsideOptions& options = {});

}  // namespace steady::sweep
