#pragma once
// The sweep cycle Q (see envelope.hpp): a closed, consistently oriented, possibly
// self-intersecting triangle surface whose region of positive winding number is the swept
// volume. Internal to steady::sweep.
#include <steady/core/motion.hpp>
#include <steady/sweep/body.hpp>
#include <steady/sweep/grazing.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace steady::sweep::detail {

// Where a cap vertex lies exactly: X = A + s (B - A) + t (C - A), with A, B, C earlier vertices
// of the cycle (posed body vertices, or such points of the joint a span starts from; c < 0 when
// t = 0: a point on the segment AB) and s, t read as exact numbers. Its double coordinates round
// this point. Caps built this way lie exactly in the posed faces' planes, so the caps that two
// spans of a polySAM leave on the same posed body are exactly coplanar and the trimming
// resolves their overlap exactly instead of finding near-coplanar sheets that cross. a < 0: the
// vertex is exactly its double coordinates.
struct ExactPosition {
  int a = -1, b = -1, c = -1;
  double s = 0, t = 0;
};

struct Cycle {
  std::vector<Eigen::Vector3d> vertices;      // world coordinates (rounded, see `exact`)
  std::vector<ExactPosition> exact;           // per vertex
  std::vector<std::array<int, 3>> triangles;  // oriented: Q's winding number is >= 0
  std::size_t cap_triangles = 0;
  std::size_t strip_triangles = 0;
  // The joint left by the last span appended with an `end_pose`: the vertices it placed at that
  // pose, per body vertex (-1: none) and, per body edge, its points on the edge (edge parameter
  // from the edge's first vertex, vertex). The next span, which starts at that pose, takes these
  // vertices for the same body points instead of posing them again, so that both spans meet in
  // identical exact points even where one of them moved its points onto a line (cycle.cpp,
  // "Strips that slide along themselves"). Empty after a span appended without `end_pose`.
  std::vector<int> joint_vertex;
  std::vector<std::vector<std::pair<double, int>>> joint_edge;
  // Per body face split by a grazing chord both at the end of that span and at the start of the
  // next, when their caps there are merged (appendSpanCycle): the vertices of its chord at the
  // end, from the Front polygon's first zero to its second. Empty for the other faces.
  std::vector<std::vector<int>> joint_chord;
  // Slivers of joint caps cut at a crossing of their chords (appendSpanCycle): per sliver its
  // triangle (r, s, x) as (index in `triangles`, r, s, x), x a rounding off the line r s, to be
  // merged with a triangle on the other side of r s by mergeJointSlivers.
  std::vector<std::array<int, 4>> joint_slivers;
};

// What a span's cycle depends on besides its neighbours (cycle.cpp): the span's grazing set,
// the boundary segments of Front, their time grids and the points that subdivide them. Built
// once per span; a polySAM's spans read their neighbours' plans at the joints.
struct SpanPlan;
struct SpanPlanDelete {
  void operator()(SpanPlan* plan) const;
};
using SpanPlanPtr = std::unique_ptr<SpanPlan, SpanPlanDelete>;

// The zeros of g that a polySAM's spans found on the body's edges, per edge (edge parameters
// from the edge's first vertex), filled by planSpan in the order the spans are planned.
using EdgeZeros = std::vector<std::vector<double>>;

// Plans the cycle of `body` on `span` with tessellation tolerance eps (tessellation.hpp).
// `end_pose` may be null: then the span's end key pose as given (Span3::end()) is used, not
// its exponential at τ = 1, which carries the log's rounding (a half turn about z as exp(pi J)
// has sin(pi) = 1.2e-16 off the axis), nor the product relative() start(), which carries the
// inverse's (a z row of (0, 0, 1 - 1.1e-16) for the identity after a pose keeping z). A polySAM
// passes the next span's start, so that joints coincide exactly. `seen` (may be null): the
// zeros found by the spans planned before; a zero within 1e-12 (in the edge parameter) of one
// of them takes its value, and the others are added. So a face split by one grazing line in two spans, such as a motion's first
// span and its last when the motion returns along itself (the velocities are negated, and the
// zeros agree only to rounding), gets the same chord ends in both, and caps that meet in the
// same posed face are cut along one exact line instead of two lines an ulp apart (a thin plate
// stretched and brought back: 3,359 slivers at the start pose, 13 s in the labels' exact rays).
// Throws steady::Error when the grids need more than max_steps. The plan keeps a pointer to
// `body`, which must outlive it.
SpanPlanPtr planSpan(const Body& body, const Span3& span, const Affine3* end_pose, double eps,
                     const GrazingOptions& grazing, int max_steps, int span_index, EdgeZeros* seen = nullptr);

// Appends the cycle of the planned span to `out`:
//   Back (with the Grazing faces) at τ = 0, Front at τ = 1, and the strips swept by the
//   boundary curves of Front, oriented with Front on their left. A span that continues a
//   polySAM (`prev`, the plan of the span before, appended just before this one) puts the
//   reversed Front at τ = 0 instead of Back: the polySAM's cycle is body(0) plus each span's
//   Front(1) - Front(0) + strips (the reasoning is at the top of cycle.cpp).
// Joints (`prev` and `next`, null at the motion's ends): where two spans meet, the edges that
//   neither span slides along themselves nor holds still subdivide at the points of both spans
//   (an edge that a sliding or fixed grazing chord only crosses does too), and a
//   face's end cap and the next span's reversed start cap, which then have the same sides, are
//   not emitted when they cancel (a face Front in both) or are replaced by their sum (Front in
//   one span and split by a grazing chord in the other: the side of the chord that is Back in
//   the split span; split in both: the region between the two chords).
// Caps are cut exactly along the grazing chords; every point where a strip meets a cap is a
// vertex of both (no T-junction), so Q is closed as a chain: every directed edge is matched by
// its reverse. When `next` is given, the span records its joint in `out` (Cycle::joint_vertex,
// joint_edge, joint_chord), and the next call must be for `next`, with this plan as its `prev`;
// otherwise it throws steady::Error.
void appendSpanCycle(Cycle& out, const SpanPlan* prev, const SpanPlan& plan, const SpanPlan* next);

// A test switch: while an object of this type lives, appendSpanCycle on the thread that made it
// fans every cap polygon around one point, however many points it has (no graded rings; see
// kGradedCapPoints in cycle.cpp). Both cover the same polygons, which tests check by comparing
// them. Objects may nest; each restores the setting it found.
class FanEveryCap {
 public:
  FanEveryCap();
  ~FanEveryCap();
  FanEveryCap(const FanEveryCap&) = delete;
  FanEveryCap& operator=(const FanEveryCap&) = delete;

 private:
  bool before_;
};

// A test switch: while one lives on a thread, planSpan on that thread keeps the time grids of
// condition (1) alone (see kBalancedPieces in cycle.cpp), so that the tests of the graded cap
// rings can reach them with the finely cut cap sides that only unbalanced grids make.
class UnbalancedGrids {
 public:
  UnbalancedGrids();
  ~UnbalancedGrids();
  UnbalancedGrids(const UnbalancedGrids&) = delete;
  UnbalancedGrids& operator=(const UnbalancedGrids&) = delete;

 private:
  bool before_;
};

// Removes from the cycle's triangles every pair of the same three vertices in opposite
// orientations (their sum as a chain is zero, so the winding numbers stay), keeping the
// triangles that remain in their order. (A polySAM's joints leave such pairs where the caps of a
// face could not be merged: next to an edge placed on a line, see appendSpanCycle.)
void cancelOpposite(Cycle& cycle);

// Merges each of the cycle's joint slivers (Cycle::joint_slivers) (r, s, x) with a triangle
// (s, r, w) that holds their edge in reverse: the two become (s, x, w) and (x, r, w), in the
// places of the two (so the triangles' count and every span's range of them stay), with the same
// sum of boundaries. A sliver whose edge no other triangle holds is left as it is. Call it when
// every span is appended, before cancelOpposite; it empties joint_slivers.
void mergeJointSlivers(Cycle& cycle);

}  // namespace steady::sweep::detail
