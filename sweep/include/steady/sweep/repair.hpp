#pragma once
/// @file
/// Opt-in repair of a triangle mesh before it becomes a sweep Body: what can be fixed without
/// guessing is fixed, everything else is reported.
///
/// Nothing here runs unless called: Body() never repairs, it rejects (body.hpp). repairMesh()
/// is for meshes from the outside world (STL exports with every corner repeated, files with a
/// few faces turned, inside-out bodies) and says exactly what it changed.
///
/// Steps, in this order (CGAL 5.5, Polygon Mesh Processing; CGAL stays inside the .cpp):
/// 1. Merge duplicate vertices: vertices with exactly equal coordinates become one (the first
///    in file order keeps its place). No tolerance: nearby but different points stay apart.
/// 2. Remove degenerate faces: faces that name a vertex twice after step 1 (they have no area
///    and no orientation).
/// 3. Remove duplicate faces: a face listed again with the same three vertices in the same
///    cyclic order is kept once.
/// 4. Remove opposite pairs: two faces on the same three vertices in opposite orders (an
///    internal wall between two cells, or a flat two-face pocket) are both removed. Their
///    contributions to the winding number cancel, so the enclosed volume is unchanged.
/// 5. Remove isolated vertices: vertices used by no face (the others are renumbered in order).
/// 6. Orient consistently: connected faces are turned so that every shared edge is traversed
///    once in each direction (orient_polygon_soup). Where that is impossible without cutting
///    (an edge of more than two faces, a vertex whose faces form several fans, a Möbius-like
///    strip), CGAL cuts the mesh by duplicating vertices. Two closed shells that touched along
///    an edge or at a vertex become two closed shells whose copies of it coincide (a Body
///    accepts that; the report counts the places); a cut that opens the mesh leaves holes.
/// 7. Optionally (RepairOptions::fill_holes) fill each hole with triangles
///    (triangulate_hole: a minimum-weight triangulation of its boundary; it adds no vertex).
/// 8. Orient outward: when the mesh is closed, has no zero-area face and every connected
///    component encloses a volume (|volume| above 1e-12 times its box diagonal cubed), each
///    component is turned so that the mesh bounds a volume, outer shells outward and nested
///    shells as cavities (orient_to_bound_a_volume). An open mesh has no inside, and CGAL's
///    inside test does not end on flat components: the orientation is then left as step 6
///    made it, and the report says so.
///
/// What it does not fix, and reports: boundary edges and holes (unless filled), zero-area
/// faces whose corners are distinct (collinear corners; removing them would open the mesh).
/// Not looked for: self-intersections (sweptEnvelope() and inspectMesh() check the output).
/// Vertex coordinates are never moved.

#include <steady/sweep/body.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace steady::sweep {

/// Options of repairMesh().
struct RepairOptions {
  /// Fill the holes of an open mesh (step 7). Off by default: a filled hole is a guess at the
  /// missing surface, flat or nearly so, which changes the body.
  bool fill_holes = false;
  /// The zero-area test of the report (`degenerate_faces`), the same as
  /// BodyOptions::degenerate_tolerance: twice the area at most this times the squared longest
  /// edge.
  double degenerate_tolerance = BodyOptions{}.degenerate_tolerance;
};

/// What repairMesh() changed, and what is still wrong.
struct RepairReport {
  // --- the mesh before and after -------------------------------------------------------------
  std::size_t vertices_in = 0, faces_in = 0;    ///< sizes of the input
  std::size_t vertices_out = 0, faces_out = 0;  ///< sizes of the result

  // --- changes -------------------------------------------------------------------------------
  std::size_t duplicate_vertices_merged = 0;  ///< vertices removed by merging equal ones (step 1)
  std::size_t degenerate_faces_removed = 0;   ///< faces with a repeated vertex (step 2)
  std::size_t duplicate_faces_removed = 0;    ///< repeated faces, same orientation (step 3)
  std::size_t opposite_faces_removed = 0;     ///< faces removed in opposite pairs (step 4; even)
  std::size_t isolated_vertices_removed = 0;  ///< unused vertices removed (step 5)
  /// Faces whose final orientation is the reverse of their input orientation (steps 6 and 8
  /// together: a face turned by both counts as not flipped).
  std::size_t faces_flipped = 0;
  std::size_t vertices_duplicated = 0;        ///< vertices CGAL duplicated to cut the mesh (step 6)
  std::size_t holes_filled = 0;               ///< holes filled (step 7)
  std::size_t hole_faces_added = 0;           ///< triangles added by filling them

  // --- state of the result -------------------------------------------------------------------
  /// Non-manifold edges (more than two faces) and vertices (more than one fan of faces) found
  /// in step 6; the mesh was cut there (`vertices_duplicated`), so the result has none.
  std::size_t non_manifold_edges = 0;
  std::size_t non_manifold_vertices = 0;
  std::size_t boundary_edges = 0;    ///< edges of one face only in the result
  std::size_t holes = 0;             ///< boundary cycles in the result (0: closed)
  std::size_t holes_not_filled = 0;  ///< holes fill_holes could not triangulate
  std::size_t degenerate_faces = 0;  ///< zero-area faces left (distinct but collinear corners)
  std::size_t components = 0;        ///< connected components (through shared edges)
  bool closed = false;               ///< no boundary edge (and not empty)
  /// The outward orientation was established (step 8 ran: the mesh is closed, without
  /// zero-area faces or flat components). False otherwise: the orientation is only consistent.
  bool oriented_outward = false;

  /// True when the mesh was modified at all.
  bool changed() const;
  /// True when nothing reported here stands in the way of a Body: not empty, closed, outward,
  /// no zero-area face. (Body() may still reject the result for a flat body.)
  bool usable() const;
};

/// Repairs the mesh in place (see the file comment for the steps) and reports what changed.
/// Vertex coordinates are copied, never moved: the result's vertices are input positions in
/// input order (a merged vertex where it first appears), followed by the copies made at
/// non-manifold places; faces keep their input order and first corner (reversed when
/// flipped), followed by the triangles of filled holes. A mesh without defects comes back
/// unchanged.
///
/// @throws Error(NonFinite) for a vertex with a NaN or infinite coordinate, and
///   Error(InvalidArgument) for a face index outside [0, #V) or a bad tolerance; the mesh is
///   left unchanged then. Never throws for defects it reports.
RepairReport repairMesh(std::vector<Eigen::Vector3d>& vertices, std::vector<std::array<int, 3>>& faces,
                        const RepairOptions& options = {});

/// One line for people: every change and every remaining defect, e.g.
/// "merged 24 duplicate vertices, flipped 12 faces (outward); closed, 8 vertices, 12 faces",
/// or "no change; closed, ...".
std::string describe(const RepairReport& report);

}  // namespace steady::sweep
