#pragma once
/// @file
/// The grazing set of a body on one SAM span: the body points whose world velocity is tangent
/// to the surface.
///
/// Why it is fixed on the body. Along a span, the body point p is at `A^τ B p` and moves with
/// the stationary field `v(x) = M x + u`; normals transform by `L^{-τ T}` and velocities by
/// `L^τ`, so `n_τ · v(A^τ x) = n · v(x)`: a point grazes at every time of the span or at none.
/// The grazing set is therefore computed once, at span time 0.
///
/// Method. Vertices are posed at span time 0 (`W = B p`, B = span.start()) and every face f
/// gets the unit world normal `n_f` of its posed triangle. `g_f(x) = n_f · v(x)` is affine on
/// the face, so it is known from its values at the three corners. These values are snapped to
/// zero when `|g| <= eps_g` (see GrazingOptions), and everything below uses the snapped values
/// and their signs only; the grazing curves are the boundary, on the surface, between the front
/// region (g > 0, moving outward) and the back region (g < 0):
/// - Face segments: where g_f changes sign inside a face, the chord of the face on which the
///   affine g_f vanishes (end points on edges, or at a corner whose value snapped to zero).
/// - Silhouette segments: on an edge, the parts where the two adjacent faces' g have opposite
///   signs. Each g is affine along the edge, so the edge splits at the (at most two) zeros into
///   pieces of constant sign pattern; up to two pieces are silhouettes.
/// - Grazing-boundary segments: faces on which g_f vanishes entirely are Grazing (their plane
///   is invariant under the span); their edges towards non-grazing faces, or towards grazing
///   faces in another plane, are reported whole. Sweeping them covers the boundary of the
///   planar region swept by the grazing faces.
/// Zeros of the two faces of an edge that fall within 1e-12 (edge parameter) of each other are
/// merged into one point, so the curves stay closed when neighbouring faces are coplanar.
///
/// Continuity. Snapping moves a curve end point onto a corner when its value crosses eps_g;
/// the jump is at most about `eps_g / |g_other|` times the edge length, where g_other is the
/// value at the edge's other end. No case is selected by exact floating-point equality.

#include <steady/core/ear.hpp>
#include <steady/sweep/body.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <vector>

namespace steady::sweep {

/// Options of grazingSet().
struct GrazingOptions {
  /// Corner values with `|g| <= eps_g` count as zero, where
  /// `eps_g = tolerance * V + 64 * 2^-52 * max_i (|M|_F |W_i| + |u|)`, V the largest speed
  /// `|v(W_i)|` over the vertices at span time 0 and the second term the rounding of g.
  /// Default 1e-9: a face is Grazing when its velocity's normal component is below a
  /// billionth of the body's largest speed at all three corners.
  double tolerance = 1e-9;
  /// The span counts as stationary (the body does not move) when the largest speed V is at
  /// most this tolerance times the bounding-box diagonal of the body posed at span time 0:
  /// then no vertex moves farther than that over the span (up to a factor e^|M|), which is the
  /// rounding of a log computed from two equal poses. Default 1e-12.
  double stationary_tolerance = 1e-12;
};

/// How g behaves on a face.
enum class FaceClass {
  Front,    ///< g >= 0 on the face (and > 0 somewhere): the face moves outward
  Back,     ///< g <= 0 on the face (and < 0 somewhere): the face moves inward
  Grazing,  ///< g = 0 on the whole face (within eps_g): the face slides in its plane
  Split,    ///< g changes sign: a face segment splits it into a front and a back part
};

/// Stable name ("front", "back", "grazing", "split").
const char* to_string(FaceClass c) noexcept;

/// Where a grazing segment comes from.
enum class SegmentKind {
  Face,             ///< the zero chord of g_f inside a Split face
  Silhouette,       ///< a sub-segment of an edge whose two faces have g of opposite signs
  GrazingBoundary,  ///< a whole edge bounding a region of Grazing faces
};

/// Stable name ("face", "silhouette", "grazing-boundary").
const char* to_string(SegmentKind k) noexcept;

/// An end point of grazing segments.
struct GrazingPoint {
  Eigen::Vector3d body = Eigen::Vector3d::Zero();   ///< body coordinates
  Eigen::Vector3d world = Eigen::Vector3d::Zero();  ///< world position at span time 0 (`B body`)
  int vertex = -1;       ///< the body vertex it is, or -1
  int edge = -1;         ///< otherwise the edge it lies on (index into Body::edges())
  double parameter = 0;  ///< position on that edge: `(1 - parameter) p[v0] + parameter p[v1]`
};

/// A grazing segment between two GrazingPoint's.
///
/// Face and Silhouette segments are oriented with the front region on their left seen from
/// outside (in the direction points[0] -> points[1]), so that the closed curves run
/// counter-clockwise around the front region. GrazingBoundary segments run along their Grazing
/// face's winding.
struct GrazingSegment {
  SegmentKind kind = SegmentKind::Face;
  std::array<int, 2> points{{-1, -1}};  ///< indices into GrazingSet::points
  int face = -1;  ///< Face: the split face; GrazingBoundary: the grazing face; else -1
  int edge = -1;  ///< Silhouette and GrazingBoundary: the edge; Face: -1
};

/// A chain of segments joined end to end; closed when it returns to its first point.
struct GrazingLoop {
  std::vector<int> segments;  ///< indices into GrazingSet::segments, in order along the chain
  /// Point indices along the chain: segments.size() + 1 entries, the last equal to the first
  /// when closed.
  std::vector<int> points;
  bool closed = false;
  /// Body coordinates of `points` (the loop as a polyline of body points).
  std::vector<Eigen::Vector3d> polyline;
};

/// The grazing set of a body on a span.
struct GrazingSet {
  std::vector<FaceClass> faces;          ///< one class per body face
  /// Per face, g_f = n_f · v at its three corners (in the face's corner order), snapped to 0
  /// where |g| <= eps_g; the classes and the curves depend on these values only. Empty for a
  /// stationary span.
  std::vector<std::array<double, 3>> corner_values;
  std::vector<GrazingPoint> points;      ///< curve end points (shared by the segments they join)
  std::vector<GrazingSegment> segments;  ///< face, silhouette and grazing-boundary segments
  /// The segments chained at shared points. Every segment is in exactly one loop. Where a point
  /// joins more than two segments (non-generic input, e.g. the corners of a region of Grazing
  /// faces) the pairing is arbitrary and some chains may be open.
  std::vector<GrazingLoop> loops;
  /// True when every point joins exactly two segments (then every loop is closed).
  bool generic = true;
  /// True when the span does not move the body (see GrazingOptions::stationary_tolerance):
  /// every face is Grazing and there is no segment.
  bool stationary = false;
  double speed = 0.0;      ///< V: the largest speed |v(W_i)| over the vertices at span time 0
  double eps_g = 0.0;      ///< the snapping threshold used (see GrazingOptions)
};

/// The grazing set of `body` on `span` (see the file comment for the method).
///
/// @param[in] body the validated body (body coordinates)
/// @param[in] span the SAM span; its start pose B places the body at span time 0
/// @param[in] options snapping tolerance
/// @return face classes, grazing points and segments in body and world (time 0) coordinates,
///         and the segments chained into loops
/// @throws Error(InvalidArgument) for a non-finite or negative tolerance (either of them); Error(NonFinite) when
///         the posed body or its velocities overflow.
GrazingSet grazingSet(const Body& body, const Span3& span, const GrazingOptions& options = {});

}  // namespace steady::sweep
