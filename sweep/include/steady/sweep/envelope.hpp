#pragma once
/// @file
/// The envelope of a sweep: the boundary of the volume `⋃_t A_t(body)` swept by a closed body
/// along a SAM span or a polySAM, as one closed, 2-manifold, outward triangle mesh.
///
/// Method (details in sweep/README.md and src/cycle.cpp, src/trim.cpp).
/// 1. The sweep cycle. On each span the grazing set is fixed on the body (grazing.hpp). Let
///    Front be the part of the body surface whose velocity points outward (`n·v > 0`) and
///    Back the rest. The closed, consistently oriented surface
///    `Q = Back(τ = 0) + Front(τ = 1) + strips swept by the boundary curves of Front`
///    has a winding number `w_Q(x) >= 0` everywhere, and the volume swept along the span is
///    exactly `{x : w_Q(x) >= 1}` (a degree argument: `w_Q` is the body's indicator at τ = 0
///    plus the number of times the front region passes over x). A polySAM sums the cycles of
///    its spans; the swept volume is again `{w >= 1}`.
/// 2. Trimming. The triangles of Q are intersected with each other in exact arithmetic (CGAL
///    Epeck) and re-triangulated so that they meet only along shared edges; each resulting
///    patch gets its winding numbers from one exact ray count; the faces with `w = 0` on one
///    side and `w >= 1` on the other form the envelope. Vertices are rounded to double at the
///    end (the only rounding of the result).
///
/// Tolerance. The only approximation is the tessellation of the swept strips in time and along
/// the grazing curves: every point of a true swept strip is within ε/2 of the tessellated strip
/// (bound derived in tessellation.hpp, not sampled). Caps and grazing curves are exact up to
/// rounding. Where the sweep of the grazing curve folds over itself, two tessellated strips can
/// swap sides and leave a thin empty pocket inside the swept volume; pockets whose walls have
/// their empty side inside the swept volume 0.75 ε beyond them (the exact inside test) are
/// removed and their mouths closed (Envelope::buried_patches_removed); so are the walls of such
/// layers that reach the envelope and are joined to its outer patches, found face by face
/// (Envelope::crack_faces_removed), and vertices of three faces that poke into the swept volume
/// (Envelope::buried_dents_filled). Every posed body point lies inside the envelope or within
/// ε of it, and the envelope's vertices lie within ε of the true boundary except near pockets
/// and cracks whose mouths could not be closed (kept and counted: Envelope::buried_patches_kept,
/// crack_faces_kept; they may lie deeper than ε inside) and, rarely, at the apex of a thin fold
/// that none of these tests finds. The vertices on kept walls are checked on every run: each
/// gets a certified bound on its distance to the true boundary; one that is not certified
/// within ε is moved onto the true boundary where that is safe
/// (Envelope::uncertified_vertices_moved), and those left are listed
/// (Envelope::kept_wall_uncertified), as are the faces there whose centroid is not certified
/// (kept_wall_faces_uncertified), so a kept wall deeper than ε is never silent (README, "What
/// does not hold yet").

#include <steady/core/motion.hpp>
#include <steady/sweep/body.hpp>
#include <steady/sweep/grazing.hpp>

#include <Eigen/Core>

#include <array>
#include <atomic>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace steady::sweep {

/// Progress of sweptEnvelope(): the stage and the fraction of it done, in [0, 1].
struct SweepProgress {
  /// "cycle", "intersect", "label" or "output".
  const char* stage = "";
  double fraction = 0.0;
};

/// Options of sweptEnvelope().
struct SweepOptions {
  /// ε: the largest distance between the envelope and the true boundary of the swept volume
  /// (world units); the strips are tessellated to ε/2 (see the file comment), or finer on a
  /// re-sweep (see `refinements`).
  /// Unset: `relative_tolerance` times the bounding-box diagonal of the body (body coordinates).
  std::optional<double> tolerance;
  /// Used when `tolerance` is unset. Default 1e-3.
  double relative_tolerance = 1e-3;
  /// Snapping of the grazing set (see GrazingOptions).
  GrazingOptions grazing;
  /// Safety limit on the time steps of one strip grid and on the pieces of one grazing
  /// segment; more throws Error(InvalidArgument) (the tolerance is too small for the motion).
  int max_steps = 1 << 16;
  /// Check the rounded output for self-intersections with CGAL (EnvelopeCheck); costs about
  /// a tenth of the sweep. Default on.
  bool check = true;
  /// Threads for the exact re-triangulations, the edge orderings of the labels, the inside
  /// tests and the mouth fillings: 0 (default) uses every hardware thread, 1 runs on the
  /// calling thread alone. The envelope is the same, bit for bit, for any number and from run
  /// to run.
  int threads = 0;
  /// Called now and then from the calling thread: once per span of the motion in the cycle
  /// stage, every 4,096 crossing pairs and every 4,096 re-triangulated triangles of the
  /// intersect stage, when the labels cast their rays, and at the start and end of the output
  /// stage (a re-sweep reports its stages again from the start); may be empty.
  std::function<void(const SweepProgress&)> progress;
  /// A flag to stop the sweep early (may be null). Once `*cancel` is true, set from any thread
  /// (a user interface, a signal handler: storing to a lock-free atomic is safe there), or from
  /// `progress`, sweptEnvelope() throws steady::Error with ErrorCode::Cancelled at its next
  /// check instead of returning (the message names the stage); nothing it computed is kept, and
  /// a later call starts over. The checks come before each progress report (none follows a
  /// cancellation), between the serial steps of the stages and between the work items of the
  /// parallel steps (whatever `threads` is), so the sweep stops within a few hundredths of its
  /// running time: on the elephant screw at 1e-3, a 2 s sweep, 33-44 ms on average and 57-71
  /// ms at most (two runs) from the flag to the caller's catch, unwinding included, over flags
  /// set at nine points of the sweep; on bunny00's, 10.8 s, 206 ms and 297 ms (BM_SweepCancel in bench/).
  /// A flag that stays false changes nothing: the envelope is the same, bit for bit. The flag
  /// is only read: resetting it is the caller's business.
  const std::atomic<bool>* cancel = nullptr;
  /// Re-sweeps allowed when the envelope leaves doubt: its check fails, or some of its vertices
  /// or face centroids on kept walls or inner shells are not certified within ε
  /// (Envelope::kept_wall_uncertified, kept_wall_faces_uncertified, cavity_uncertified,
  /// cavity_faces_uncertified). Each re-sweep halves the tessellation tolerance (ε/4, then
  /// ε/8, ...), which makes the cracks and pockets of the tessellated sheets thinner. It does
  /// so on every span, unless the sweep before it listed fewer than 256 points and the spans
  /// whose tessellated sheets pass within 8 ε of them (a box test) are at most a quarter of the
  /// motion's spans: then on those alone (Envelope::spans_refined). The elephant along the
  /// bundled `keys.json` (112 spans, 28 refined) took 32 s instead of 40 to 46 s, and 0.70 GB
  /// instead of 0.99 GB. The envelope returned is the best of the sweeps run (a passing check,
  /// then the fewest uncertified vertices and faces, 256 or more counting as equally many, then
  /// the fewest deep fillings; the earliest among equals), and Envelope::resweeps says how many
  /// ran. Deep
  /// fillings taken (Envelope::deep_fillings_taken) alone do not call for a re-sweep: on the
  /// benchmark screws a finer tessellation still takes one. A re-sweep holds about twice as
  /// many triangles per halving and usually costs as much as the first sweep or more. While a
  /// re-sweep may follow, a sweep stops certifying once 256 of its points are found uncertified
  /// (the rest would mostly be the costly ones); the envelope returned always has all of its
  /// certificates. (bunny00's benchmark screw at a relative tolerance of 1e-2: 25,624 points
  /// uncertified on the first sweep, which took 205 s when it certified them all; the whole
  /// call, clean re-sweep included, now takes 43 s.) A re-sweep that throws
  /// steady::Error (say, more than `max_steps` time steps) ends the series with the envelopes
  /// before it. 0: never sweep again.
  /// Default 2: on the seeded stress campaign's cases 31,800 to 34,199 it turned 5 of the 6
  /// failing cases into envelopes the oracle accepts (the sixth fails by a deep filling only).
  int refinements = 2;
};

/// Wall-clock seconds of each stage of sweptEnvelope().
struct SweepTimings {
  double cycle = 0;      ///< grazing sets and the tessellated sweep cycle
  double intersect = 0;  ///< exact triangle/triangle intersections and re-triangulation
  double label = 0;      ///< patches and their winding numbers
  double output = 0;     ///< selection, rounding, manifold output
  double check = 0;      ///< the self-intersection check (0 when SweepOptions::check is off)
  double total = 0;      ///< the whole call, re-sweeps included (the stages are those of the sweep returned)
};

/// Properties of a closed triangle mesh, as checked by inspectMesh().
struct MeshCheck {
  bool closed = false;        ///< every edge has exactly two faces
  bool manifold = false;      ///< ... and every vertex has one fan of faces
  bool oriented = false;      ///< every edge is traversed once in each direction
  /// Number of pairs of faces that intersect other than along their shared edge or vertex
  /// (CGAL's exact test on the double coordinates), among the faces that are not degenerate;
  /// -1 when not checked.
  long self_intersections = -1;
  /// Faces with no area (a repeated vertex, or three collinear corners).
  long degenerate_faces = 0;
  int shells = 0;             ///< connected components (through shared edges)
  double volume = 0;          ///< signed volume (divergence theorem); > 0 when outward
  double area = 0;
};

/// The swept envelope and what was done to get it.
struct Envelope {
  std::vector<Eigen::Vector3d> vertices;       ///< world coordinates
  std::vector<std::array<int, 3>> triangles;   ///< counter-clockwise seen from outside
  double volume = 0;         ///< enclosed volume
  double area = 0;           ///< surface area
  double tolerance = 0;      ///< ε used (world units)
  /// The finest tessellation tolerance of the sweep returned (world units): ε/2, or ε/4, ε/8, ...
  /// on the spans that re-sweeps refined (see SweepOptions::refinements).
  double tessellation_tolerance = 0;
  /// Sweeps run again with a finer tessellation because an envelope left doubt (see
  /// SweepOptions::refinements); 0 when the first was returned without doubt or none was allowed.
  std::size_t resweeps = 0;
  /// Spans whose tessellation is finer in the sweep returned than in the first (0 when the first
  /// was returned; `spans` when every span was refined).
  std::size_t spans_refined = 0;
  MeshCheck check;           ///< properties of the output (self_intersections -1 if not checked)
  std::size_t spans = 0;                 ///< spans of the motion
  /// Spans left out of the cycle because an earlier span sweeps the same poses, the same way or
  /// back, to within 1e-6 ε (a motion to a pose and back, again and again, keeps its first stroke).
  std::size_t spans_repeated = 0;
  std::size_t cycle_triangles = 0;       ///< triangles of the sweep cycle Q
  /// Edges of Q not matched by a reverse edge (by vertex index). 0 by construction; anything
  /// else means the winding numbers, hence the envelope, cannot be trusted.
  std::size_t cycle_open_edges = 0;
  std::size_t intersecting_pairs = 0;    ///< pairs of cycle triangles that cross
  std::size_t arrangement_triangles = 0; ///< triangles after re-triangulation
  /// Coincident faces of the arrangement merged into one weighted face (coplanar layers, e.g.
  /// strips sliding in a grazing plane over its face), and those whose layers cancelled.
  std::size_t coincident_merged = 0;
  std::size_t coincident_cancelled = 0;
  std::size_t patches = 0;               ///< patches labelled with a winding number
  std::size_t ray_retries = 0;           ///< rays re-cast because they hit an edge or vertex
  /// Patches labelled by a ray of their own: one per connected group of patches, plus a check
  /// sample (the others take their winding numbers across the edges where patches meet).
  std::size_t patches_by_ray = 0;
  /// Connected groups of patches whose winding numbers, carried across edges, contradicted
  /// each other around a cycle or disagreed with a check ray; each such group is labelled by a
  /// ray per patch instead (counted in patches_by_ray). 0 unless the exact arrangement is not
  /// what it should be, which has not been seen: a non-zero count is worth a bug report.
  std::size_t label_mismatches = 0;
  /// Cavities (inner shells) thinner than ε on average (2 |volume| / area <= ε) that were
  /// removed: pockets pinched between a cap and a strip leaving it tangentially, artefacts of
  /// the tessellation within the tolerance.
  std::size_t thin_cavities_removed = 0;
  /// Closed solid shells thinner than ε on average, other than the largest, that were removed:
  /// crumbs left where strips fold near a tangency (the swept volume of a connected body is
  /// connected), artefacts of the tessellation within the tolerance.
  std::size_t thin_solids_removed = 0;
  /// Patches left out because they bounded an empty pocket inside the swept volume: the point
  /// 0.75 ε beyond them on their empty side is inside (the exact inside test). Such pockets
  /// appear where the sweep of the grazing curve folds over itself and the tessellations of
  /// the two nearly coincident sheets swap sides.
  std::size_t buried_patches_removed = 0;
  /// Faces left out because they were walls of a crack: a thin empty layer inside the swept
  /// volume that reaches the envelope, so that its walls are joined to the outer patches and no
  /// patch of it is buried as a whole. It appears where the front region of a face is a sliver
  /// moving nearly in its own plane and the tessellated strips of its boundary swap sides. A
  /// face is such a wall when a probe 0.75 ε long from its centroid or a corner towards its
  /// empty side meets a selected face facing it and ends inside the swept volume.
  std::size_t crack_faces_removed = 0;
  /// Buried patches and crack walls found as above but kept, because the mouths that leaving
  /// them out would open could not be closed (the envelope must stay closed): patches of which
  /// some piece was kept (pieces of about 1 ε, those with an edge on such a mouth), and faces.
  /// They lie inside the swept volume, so near them an envelope vertex may lie deeper than ε
  /// inside it; where both are 0, every buried patch and crack wall found is gone.
  std::size_t buried_patches_kept = 0;
  std::size_t crack_faces_kept = 0;  ///< (see buried_patches_kept)
  /// Output vertices on those kept walls (within 2e-3 ε of one of their points: later steps move
  /// vertices by at most 1e-3 ε), and a certified bound on how far the farthest of them lies
  /// from the true boundary of the swept volume (world units): each has, within its bound, a
  /// point on the other side of the boundary by the exact inside test (at a distance less four
  /// times the test's tolerance). The probes go across the surface (the vertex and face normals,
  /// both ways, at ε and at radii halved down to 1e-6 ε), along it (the vertex's edges and 12
  /// directions in the plane of each normal, down to ε/16), then along the 26 directions to the
  /// faces, edges and corners of a cube, at 1, 1.25, 1.5, 2, 4 and 8 ε. The bound is one of those
  /// multiples of ε; infinity when some vertex has no such point within 8 ε; 0 when no output
  /// vertex is on a kept wall. The bound covers the centroids of the faces at those vertices
  /// too (see kept_wall_faces_uncertified).
  std::size_t kept_wall_vertices = 0;
  double kept_wall_depth_bound = 0;
  /// The vertices on kept walls whose bound exceeds ε (indices into `vertices`, increasing):
  /// empty means every output vertex on a kept wall is certified within ε of the true boundary.
  /// A listed vertex is not certified, which is not the same as deeper than ε: a probe that
  /// misses the nearest point across can only overstate a depth (near a flat stretch of boundary
  /// a vertex at depth d is certified by 1.13 d, but a crack of outside space thinner than 1% of
  /// ε, ending at the vertex, may escape every probe).
  std::vector<int> kept_wall_uncertified;
  /// The faces with a vertex on a kept wall whose centroid is not certified within ε (indices
  /// into `triangles`, increasing): a face can stand off the true boundary with its vertices on
  /// it. Each centroid is probed across its face, both ways, at the claims above.
  std::vector<int> kept_wall_faces_uncertified;
  /// The vertices of the envelope's inner shells: every shell but the one of largest volume (the
  /// swept volume of a connected body is connected, so other shells bound cavities). They are
  /// certified like the vertices of kept walls (see kept_wall_depth_bound): the largest bound
  /// (0 when there is one shell), and the vertices whose bound exceeds ε (indices into
  /// `vertices`, increasing; empty means every cavity vertex is certified within ε of the true
  /// boundary).
  std::size_t cavity_vertices = 0;
  double cavity_depth_bound = 0;
  std::vector<int> cavity_uncertified;
  /// The faces of inner shells whose centroid is not certified within ε (as
  /// kept_wall_faces_uncertified; their bounds count in cavity_depth_bound).
  std::vector<int> cavity_faces_uncertified;
  /// Vertices of kept walls and inner shells first found not certified within ε and then moved
  /// onto the true boundary: each towards the probe that its certificate found on the other
  /// side of the boundary (or another probe at that distance), to where the segment between
  /// them crosses it (bisection with the exact inside test, to within ε/128 plus the test's
  /// tolerance), or 0.5 or 0.85 ε short of that; the move is shorter than the vertex's bound. A
  /// position is refused when it would turn a face at the vertex by a right angle or more,
  /// leave one without area, or make one cross another face (exact tests), so the surface stays
  /// closed, oriented and free of self-intersections; and a move into the region the surface
  /// encloses goes ε at most, so that every point the envelope held stays inside it or within
  /// ε of it. The bounds and lists above are measured after the moves; an envelope whose listed
  /// vertices all moved leaves no doubt (no re-sweep). (Not done on an envelope that a re-sweep
  /// may replace and whose certificates were given up part-way: see SweepOptions::refinements.)
  std::size_t uncertified_vertices_moved = 0;
  /// Mouths of such pockets and cracks (loops of edges left with one face) closed by hole filling.
  /// Before a filling is taken, some of its points (each face's centroid, and of points spread
  /// over it at least 2 ε from the loop, the farthest from the loop on each of its faces and the
  /// 16 farthest of the rest) get the certified bound above; a filling with a bound over ε is refused, and the
  /// walls at its mouth are kept. Its other points are not probed, so this is a check, not a
  /// certificate of the whole filling.
  std::size_t pocket_mouths_filled = 0;
  /// Of those fillings, how many were taken although a probe had a bound over ε: a mouth
  /// whose filling is refused keeps its walls, which open new mouths, and the selection may
  /// not settle; after the first 4 rounds of each series of 16, such fillings are taken rather
  /// than refused again, unless the check finds fewer of them than the check before it (the
  /// refusals are then converging). Not 0 means that some filling may lie farther than ε from the true
  /// boundary: see filling_depth_bound.
  std::size_t deep_fillings_taken = 0;
  /// Of the mouth fillings taken, how many were refined: a flat filling found farther than ε
  /// from the true boundary had its inner edges cut (to about ε) and each new point moved along
  /// the filling's normal onto the true boundary (by bisection with the exact inside test, to
  /// within ε/128), then was checked and probed again like any filling.
  std::size_t fillings_refined = 0;
  /// The largest certified bound (world units, as kept_wall_depth_bound) over the probed points
  /// of the fillings taken; infinity when some probe has no point across the boundary within 8
  /// ε; 0 when no filling was probed.
  double filling_depth_bound = 0;
  /// Faces left out because they lay across such a mouth: an edge on its rim and the third
  /// corner on the same rim (a flap folded over the mouth, whose rims are less than the 0.75 ε
  /// probe apart). Their other edges then become part of the mouth, which is closed as a whole.
  std::size_t mouth_flaps_removed = 0;
  /// Faces left out because a mouth's every filling crossed them and their corners all lie
  /// within 1.5 tessellation tolerances (0.75 ε) of its rim (faces of the rim folded over the
  /// mouth with a corner off it); the mouth, grown by them, was closed in a later round.
  std::size_t mouth_rim_faces_removed = 0;
  /// Vertices of three faces whose tip lay behind the triangle of their three neighbours (a
  /// dent, the apex of a thin fold of the tessellated strips) and poked into the swept volume:
  /// a probe 0.75 ε from the tip towards that triangle's outward side ended inside (the exact
  /// inside test). Each such fan of three faces was replaced by that triangle, unless the
  /// triangle's centroid, or the foot of the tip on it, has a certified bound (as above) over ε.
  std::size_t buried_dents_filled = 0;
  /// Vertices merged after rounding because they lay within 1e-13 times the envelope's box
  /// diagonal of another (distinct exact points a few ulps apart, whose rounded slivers would
  /// cross); the triangles they collapse are dropped, which keeps the surface closed. When the
  /// envelope so merged fails its check, it is finished again without merging, and that one is
  /// returned (with 0 here) if it passes (a fallback: merging once folded faces in the sliding
  /// planes of planar motions, whose cause is now fixed elsewhere).
  std::size_t rounding_merged = 0;
  /// When the output check found self-intersecting pairs: slivers left by rounding that were
  /// flipped away (triangles whose corner lay on their opposite side within 1e-13 times the
  /// envelope's box diagonal, so that, rounded, they overlapped their neighbour; the side is
  /// flipped to the diagonal of the two triangles, and no vertex moves), kept because the check
  /// then found fewer pairs. 0 for every envelope whose check passed at once. (An L-shaped
  /// prism along a turn whose pose has denormal entries needs 10 such flips.)
  std::size_t rounding_slivers_flipped = 0;
  /// Vertices where the envelope touches itself (several fans of faces), given one copy per
  /// extra fan so that the mesh is a 2-manifold. The copies are then moved apart, each towards
  /// its own fan by 1e-3 of the fan's size and at most 1e-3 ε, so that the fans no longer meet
  /// (halving the step while the move would make faces cross). Where no direction per point
  /// works (two sheets touching along an edge, both of whose ends are pinched), the copies of
  /// the points joined by edges try every combination of their own directions. The moved
  /// copies' faces are tested again at the end, since a neighbour that could not move and went
  /// back may cross them; those copies then search again beside it.
  std::size_t pinched_vertices_split = 0;
  /// Copies of pinch vertices that could not be moved apart without making faces cross and so
  /// still share a position (the check then counts their fans as touching face pairs).
  std::size_t pinches_touching = 0;
  SweepTimings timings;
};

/// The envelope of `body` swept along every span of `motion`.
///
/// @param[in] body validated body (body coordinates)
/// @param[in] motion the motion; span i moves the body from `motion.span(i).start()` to its
///   end pose; all spans are swept together, so the result is one closed envelope
/// @param[in] options tolerance, grazing snapping, check, progress
/// @return the envelope in world coordinates
/// @throws Error(InvalidArgument) for a tolerance that is not finite and positive, or when a
///   strip needs more than `max_steps` steps (raise the tolerance); Error(NonFinite) when the
///   posed body overflows; Error(DegenerateInput) when the exact trimming could not label a
///   patch (never seen; the message asks for a bug report with the input).
Envelope sweptEnvelope(const Body& body, const Motion3& motion, const SweepOptions& options = {});

/// The envelope of `body` swept along one span (pose `span.pose(τ)`, τ in [0, 1]).
Envelope sweptEnvelope(const Body& body, const Span3& span, const SweepOptions& options = {});

/// Whether `envelope` passed its check: closed, manifold, oriented, no self-intersecting face
/// pair (or not checked: SweepOptions::check off), no degenerate face, and a closed sweep cycle
/// (Envelope::cycle_open_edges 0). The CLI writes an envelope that fails it for inspection only
/// (exit status 4).
bool passedCheck(const Envelope& envelope);

/// Checks a triangle mesh: closed, oriented, manifold, self-intersections (exact predicates on
/// the double coordinates, when `self_intersections` is true), shells, volume and area.
/// Never throws for bad meshes (that is what it reports); throws Error(InvalidArgument) for a
/// face index out of range.
MeshCheck inspectMesh(const std::vector<Eigen::Vector3d>& vertices,
                      const std::vector<std::array<int, 3>>& triangles, bool self_intersections = true);

}  // namespace steady::sweep
