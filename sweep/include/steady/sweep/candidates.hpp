#pragma once
/// @file
/// The candidate surface of a sweep: triangles that contain the boundary of the volume swept
/// by a body along a SAM span (or a polySAM), before any trimming.
///
/// The boundary of the volume swept along one span lies in the union of: the body at the start
/// pose (τ = 0), the body at the end pose (τ = 1), and the ruled surfaces swept by the grazing
/// segments (grazing.hpp), `{A^τ B ((1 - s) p + s q) : s, τ in [0, 1]}` for a segment [p, q]
/// (each τ gives a straight segment, since A^τ is affine). Most of this surface is inside the
/// volume; the trimming step (still to come) keeps the outer part.
///
/// Tessellation with a guaranteed bound. Each connected component of the grazing curves (a
/// loop, in generic position) gets one grid of span times `0 = τ_0 < ... < τ_K = 1`, shared by
/// all its segments, so neighbouring strips share the trajectories of their common points.
/// Each segment is cut into m equal pieces (m per segment) and each cell
/// `[s_i, s_i+1] x [τ_k, τ_k+1]` becomes two triangles split along the diagonal from
/// `(s_i, τ_k)` to `(s_i+1, τ_k+1)`. Every point `F(s, τ) = A^τ X0(s)` of the true strip is
/// then within `tolerance` of the triangles of its cell (derivation in candidates.cpp):
/// the chordal error of the trajectories is kept below tolerance/2 by the τ grid, and the twist
/// of each cell below tolerance/2 by m. The bound is derived, not sampled; it assumes the poses
/// are exact (rounding adds about 1e-16 times the scene's size).

#include <steady/core/motion.hpp>
#include <steady/sweep/body.hpp>
#include <steady/sweep/grazing.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

namespace steady::sweep {

/// Options of the candidate surface.
struct CandidateOptions {
  /// ε: the largest distance between a point of a true swept strip and the tessellation (world
  /// units). Unset: `relative_tolerance` times the body's bounding-box diagonal.
  std::optional<double> tolerance;
  /// Used when `tolerance` is unset. Default 1e-3.
  double relative_tolerance = 1e-3;
  /// Options of the grazing set of each span.
  GrazingOptions grazing;
  /// Safety limit on the τ steps of one grid and on the pieces of one segment; more throws
  /// Error(InvalidArgument) (the tolerance is too small for the motion). Default 65536.
  int max_steps = 1 << 16;
};

/// What a candidate triangle is part of.
enum class CandidateKind {
  StartCap,  ///< a body face at the span's start pose (τ = 0)
  EndCap,    ///< a body face at the span's end pose (τ = 1)
  Swept,     ///< the strip swept by a grazing segment
};

/// Stable name ("start-cap", "end-cap", "swept").
const char* to_string(CandidateKind k) noexcept;

/// The origin of one candidate triangle.
struct CandidateTag {
  CandidateKind kind = CandidateKind::StartCap;
  int span = 0;     ///< the span index (0 for spanCandidates())
  /// Caps: the body face. Swept: the segment's face (GrazingSegment::face), or -1.
  int face = -1;
  int edge = -1;     ///< Swept: the segment's edge (GrazingSegment::edge), or -1
  int segment = -1;  ///< Swept: index into `grazing[span].segments`
  SegmentKind segment_kind = SegmentKind::Face;  ///< Swept: the segment's kind
  int group = -1;    ///< Swept: index into `grids` (the τ grid used)
};

/// One swept strip (one grazing segment of one span).
struct CandidateStrip {
  int span = 0;
  int segment = -1;              ///< index into `grazing[span].segments`
  int group = -1;                ///< index into `grids`
  int pieces = 0;                ///< m: pieces along the segment
  std::size_t first_triangle = 0;  ///< its triangles are [first_triangle, first_triangle + triangle_count)
  std::size_t triangle_count = 0;  ///< 2 m K minus the degenerate triangles dropped
};

/// The τ grid of one connected component of a span's grazing curves.
struct TimeGrid {
  int span = 0;
  std::vector<int> points;   ///< grazing point indices of the component
  std::vector<double> tau;   ///< 0 = tau[0] < ... < tau.back() = 1 (K + 1 entries)
};

/// The candidate surface: an indexed triangle soup in world coordinates. Triangles of one strip
/// and of strips of the same grid share vertices (watertight strips); cap vertices are shared
/// with the strips at τ = 0 and 1 where a grazing point is a body vertex. No manifoldness or
/// orientation is implied across parts.
struct CandidateSurface {
  std::vector<Eigen::Vector3d> vertices;       ///< world coordinates
  std::vector<std::array<int, 3>> triangles;   ///< vertex indices
  std::vector<CandidateTag> tags;              ///< one per triangle
  std::vector<CandidateStrip> strips;          ///< one per non-degenerate grazing segment
  std::vector<TimeGrid> grids;                 ///< one per grazing component and span
  std::vector<GrazingSet> grazing;             ///< one per span
  double tolerance = 0.0;                      ///< ε used
  std::size_t degenerate_dropped = 0;          ///< zero-area strip triangles left out
};

/// The candidate surface of `body` on one span: start cap, end cap, swept grazing segments.
///
/// @param[in] body validated body (body coordinates)
/// @param[in] span the SAM span, start pose at τ = 0, end pose at τ = 1
/// @param[in] options tolerance ε and grazing options
/// @throws Error(InvalidArgument) for a tolerance that is not finite and positive (or a
/// relative tolerance that is not, when the tolerance is unset), for max_steps < 1, or when
/// a grid or a segment needs more than max_steps steps; Error(NonFinite) like grazingSet().
/// A stationary span (grazing.stationary) gives the two caps only.
CandidateSurface spanCandidates(const Body& body, const Span3& span, const CandidateOptions& options = {});

/// The candidate surfaces of every span of a polySAM, concatenated (tags carry the span index).
/// Both caps of every span are kept: the end cap of span i and the start cap of span i+1
/// coincide up to rounding. Throws like spanCandidates().
CandidateSurface motionCandidates(const Body& body, const Motion3& motion,
                                  const CandidateOptions& options = {});

}  // namespace steady::sweep
