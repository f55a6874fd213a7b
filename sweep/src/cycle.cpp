// The sweep cycle of one span (see cycle.hpp and envelope.hpp).
//
// Why Q bounds the swept volume. Along a span a body point X moves to A^τ X; a fixed world point
// x that is outside the body at τ = 0 and inside at some later time is crossed by the body's
// surface where that surface moves outward (n·v > 0: the Front region). So the swept volume is
// body(0) ∪ Φ(Front × [0, 1]) with Φ(X, τ) = A^τ X. Φ preserves orientation on Front × [0, 1]
// (its Jacobian has the sign of n·v), so the number of preimages of x under Φ is the winding
// number of Φ(∂(Front × [0, 1])) = Front(1) - Front(0) + strips(∂Front) around x, which is >= 0.
// Adding body(0) = Front(0) + Back(0) gives Q = Back(0) + Front(1) + strips, whose winding number
// is the body's indicator at τ = 0 plus that count: >= 0, and >= 1 exactly on the swept volume.
// Grazing faces (n·v = 0 on the whole face) slide in their plane and are counted with Back.
//
// PolySAMs. Spans j = 0..n-1 in a row: the swept volume of span j is body(start of j) ∪
// Φj(Frontj × [0, 1]), and body(start of j) = body(end of j - 1) lies in the swept volume of
// span j - 1, so by induction the polySAM sweeps body(0) ∪ ⋃j Φj(Frontj × [0, 1]). The cycle
// is then body(0) + Σj Φj(∂(Frontj × [0, 1])): Q for the first span, and for every later one
// Front(1) - Front(0) + strips (the start cap is Front at τ = 0, reversed, instead of Back),
// with winding number 1 on body(0) plus the counts: >= 0, and >= 1 exactly on the swept volume.
// At a joint the end cap of one span and the reversed start cap of the next lie in the same
// posed faces, and their sum is emitted instead of both (appendSpanCycle, "Joints"): nothing
// where both spans move a face outward, the part between the two spans' grazing chords where
// they split it. The caps of Q for every span left a whole posed body at every joint instead,
// inside the swept volume but crossed by the strips around it: on the elephant along the bundled
// bi-arc motion (112 spans) 661k of the cycle's 998k triangles were caps, against 70k of 406k
// when the caps of faces Front on both sides cancelled as identical triangles (cancelOpposite),
// which they do only where no strip point lies on the face's edges.
//
// Construction. Corner values of g = n·v come from grazingSet() (snapped to 0 below eps_g);
// only their signs and the affine interpolation between them decide what is front. On every
// edge the zeros of its two faces' g (merged within 1e-12 in the edge parameter, as grazing.cpp
// does) split it into pieces; a piece is a boundary curve of Front when exactly one of its two
// faces is front there. Inside a split face the boundary is the chord where g vanishes. Every
// boundary segment is oriented with Front on its left (the front polygon's winding), swept
// into a strip (tessellation.hpp gives the time grid and the pieces), and every point where a
// strip meets a cap (its ends and subdivision points at τ = 0 and 1) is also a vertex of the
// cap polygons, which are cut exactly along the chords and fanned into triangles (or, with
// more than kGradedCapPoints points, triangulated in graded rings).
//
// Concave edges. Where the body is concave along a boundary edge of Front, the strip the edge
// sweeps lies inside the swept volume: near the edge the body is the union of its two faces'
// inner half-spaces, one face moving out and the other in, so every point near the strip lies
// in the body posed a little earlier or later. Such strips are still part of Q and are cut
// like the others (about half of the crossing pairs on the elephant and bunny00): their
// tessellated copies stray across other sheets by up to the tessellation's error where their
// room inside is thinner (near τ = 0 and 1, and where the faces nearly graze), and when they
// were left uncut, counted only by the rays, the pockets so made reached the other sheets'
// labels and the envelope came out open (docs/history.md, twenty-fourth round).
#include "cycle.hpp"

#include "tessellation.hpp"

#include <steady/core/error.hpp>

#include <Eigen/Geometry>  // cross products
#include <unsupported/Eigen/MatrixFunctions>  // exp of the cleaned log

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <string>

namespace steady::sweep::detail {

namespace {

using Vec = Eigen::Vector3d;

// Edge-parameter distance below which the zeros of the two faces of an edge are one point
// (the same rule as grazing.cpp).
constexpr double kMergeParameter = 1e-12;
// A point whose speed is at most this fraction of the body's largest speed is held fixed over
// the span (one vertex for all times): it moves by at most 1e-12 V e^|M| in truth, far below ε.
constexpr double kFixedSpeed = 1e-12;
// A fixed point inside a boundary segment cuts it when it lies more than this (in the segment's
// parameter) from the segment's ends and replaces the segment's own cuts as close to it.
constexpr double kFixedCutMargin = 1e-9;
// A boundary segment whose positions at every grid row lie within this fraction of ε of the line
// through its τ = 0 ends sweeps no area (see "Strips that slide along themselves" below); the
// snap moves vertices by at most 1e-9 ε.
constexpr double kOnLine = 1e-9;
// Cap polygons with more points than this are triangulated in graded rings (see emitPolygon)
// instead of fanned around one interior point. A fan of n triangles on a side cut into n pieces
// puts n thin triangles about one apex whose boxes all meet: n² pairs for the crossing tests,
// and n² again for the output's self-intersection check, since those triangles reach the
// envelope. Sides are cut that finely where strips need many pieces along straight trajectories
// (shears and scalings: pieces in proportion to 1/ε). Below it a fan is as fast as the rings,
// which make three times as many triangles: the L-shaped prism of LongCapSidesAreTriangulated-
// InGradedRings at 1e-2 (its largest caps between 65 and 256 points) took 0.026-0.035 s
// fanned, 0.039-0.052 s in rings from 64 points on, 0.026-0.030 s with this bound; at 5e-3 and
// 2e-3 the rings were as fast or faster. (The 9 bundled scenes and the elephant along
// screw.json at the default tolerance, knot1 along screw_scale.json and CGAL's sphere along
// keys.json at 5e-3 have no larger caps: their envelopes are those of the fans, bit for bit.)
constexpr std::size_t kGradedCapPoints = 256;
// Condition (2) asks for pieces in proportion to the time step h of a cell. Where the
// trajectories are straight (shears and scalings) condition (1) takes the whole span in one
// step, and a twisting strip then gets all its pieces along the segment: N cells as long as the
// span and 1/N wide. The same bound is met by about as many cells with steps and pieces
// balanced (about sqrt N of each), whose triangles are not long and thin and which cut the
// body's edges into sqrt N points instead of N. (Long thin cells also misstate the area: on
// the L-shaped prism's shear the envelope's area stayed 1.5% high at every tolerance, as a
// Schwarz lantern's does, while the balanced grids' converges.) A component's grid is balanced
// when (1) takes the whole span in one step and a segment would need more than this many
// pieces in it: every cell then gets at most ceil(sqrt N) pieces, by shorter steps. Other
// grids are those of (1) alone, to the last bit. (Balancing every grid whose first step gives
// more than this many pieces per unit of the step also took the spans of the bundled keys.json,
// 50 to 111 there, whose first steps are 0.6 to 0.9: the tetrahedron's envelope along it then
// lost the motion's tunnel and the box's gained six small handles, both still within ε of the
// true boundary. Not traced.)
constexpr double kBalancedPieces = 64;
thread_local bool unbalanced_grids = false;  // (see UnbalancedGrids)
thread_local bool fan_every_cap = false;  // (see FanEveryCap)

int sgn(double x) { return (x > 0) - (x < 0); }

int findRoot(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// Where a body-coordinate point lies on the body: P[a] + s (P[b] - P[a]) + t (P[c] - P[a]) with
// body vertices a, b, c (c < 0: on the edge ab); a < 0 for the body's own vertices. Posed, the
// same combination of the posed vertices is the point's exact position (ExactPosition). `edge`:
// the body edge (a, b) for a point on an edge, -1 otherwise.
struct Where {
  int a = -1, b = -1, c = -1;
  double s = 0, t = 0;
  int edge = -1;
};

// A point on an edge at parameter r, `(1 - r) p[v0] + r p[v1]`.
struct EdgePoint {
  double r = 0;
  int point = -1;
};

// A boundary segment of Front from point p to point q (Front on its left): an edge piece
// (edge >= 0, parameters rp, rq) or a chord of a split face (face >= 0).
struct Segment {
  int p = -1, q = -1;
  int edge = -1, face = -1;
  double rp = 0, rq = 0;
};

// A polygon corner: a point, and whether it is a true corner (a face vertex or a zero of the
// face's own g) rather than a point that only subdivides a side.
struct Corner {
  int point = -1;
  bool true_corner = true;
  bool zero = false;
  int vertex = -1;  // its vertex of the cycle when known (a neighbour's point at a joint)
};

// The span's poses with its log cleaned of rounding noise: entries of M (and u) below 16 units
// in the last place of |M|_F (of |u|) are indistinguishable from zero and are set to zero, so
// that planes the motion keeps invariant (a rotation about a coordinate axis, a translation
// along one) stay exactly invariant in floating point: otherwise a log such as
// M_22 = -5.6e-17 for a turn about z lifts the strips off the grazing planes by an ulp, and
// the exact trimming resolves (and rounding then tangles) sheets that should coincide.
// pose(τ) = exp(τ [M u; 0 0]) B (Eigen's Padé exponential, accurate to a few ulps).
class CleanPoses {
 public:
  explicit CleanPoses(const Span3& span) : start_(span.start()) {
    const Eigen::Matrix3d& M = span.log().M;
    const Vec& u = span.log().u;
    const double tm = 16 * std::numeric_limits<double>::epsilon() * M.norm();
    const double tu = 16 * std::numeric_limits<double>::epsilon() * u.norm();
    X_.setZero();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) X_(i, j) = std::abs(M(i, j)) <= tm ? 0.0 : M(i, j);
      X_(i, 3) = std::abs(u[i]) <= tu ? 0.0 : u[i];
    }
  }
  Affine3 operator()(double tau) const {
    Eigen::Matrix4d E = (tau * X_).exp();
    // A row i of the generator that is λ e_i (zero off its diagonal) scales coordinate i alone:
    // row i of its exponential is e^(λτ) e_i, so the planes x_i = 0 stay put. A column j < 3
    // that is λ e_j keeps direction e_j: column j is e^(λτ) e_j. Both are set exactly: Padé's
    // solve can miss the zeros and ones by an ulp (a turn of 30 degrees about z gave E_22 =
    // 1 - 1.1e-16 at τ = 0.993, which lowered the top face's strip vertices off its plane by
    // 3e-17; a thin plate scaled by 3/2 along x, its face x = 0 sliding in its plane, got strip
    // vertices at x = 1e-15, and its envelope came out open).
    for (int i = 0; i < 3; ++i) {
      const double lambda = X_(i, i);
      Eigen::Matrix<double, 1, 4> row = X_.row(i);
      row(i) = 0;
      if (row.isZero(0.0)) E.row(i) = std::exp(lambda * tau) * Eigen::Matrix4d::Identity().row(i);
      Eigen::Vector4d col = X_.col(i);
      col(i) = 0;
      if (col.isZero(0.0)) E.col(i) = std::exp(lambda * tau) * Eigen::Matrix4d::Identity().col(i);
    }
    return Affine3(E.topLeftCorner<3, 3>(), E.topRightCorner<3, 1>()) * start_;
  }

 private:
  Affine3 start_;
  Eigen::Matrix4d X_;
};

// What of each face is front: all, nothing (Back and Grazing faces), or a part (Split).
enum Part : char { kBack, kFront, kSplit };

// Points placed exactly on the line through the τ = 0 vertices of points a and b (see "Strips
// that slide along themselves" in appendSpanCycle).
struct LinePlacement {
  std::vector<int> pts;
  int a = -1, b = -1;
};

// The coordinates (s, t) of a point x of the plane of a triangle (a, b, c):
// x = a + s (b - a) + t (c - a), from the normal equations (the nearest such point for an x off
// the plane). Keeps copies of the corners.
class PlaneCoordinates {
 public:
  PlaneCoordinates(const Vec& a, const Vec& b, const Vec& c)
      : a_(a), u1_(b - a), u2_(c - a), g11_(u1_.dot(u1_)), g12_(u1_.dot(u2_)), g22_(u2_.dot(u2_)),
        det_(g11_ * g22_ - g12_ * g12_) {}
  std::array<double, 2> operator()(const Vec& x) const {
    const Vec d = x - a_;
    const double b1 = u1_.dot(d), b2 = u2_.dot(d);
    return {{(g22_ * b1 - g12_ * b2) / det_, (g11_ * b2 - g12_ * b1) / det_}};
  }

 private:
  Vec a_, u1_, u2_;
  double g11_, g12_, g22_, det_;
};

// The time grid of one connected component of the boundary curves.
struct Grid {
  std::vector<double> tau;
  std::vector<Affine3> pose;
  std::vector<std::vector<Vec>> world;  // [row][local point]
};

}  // namespace

struct SpanPlan {
  const Body* body = nullptr;
  std::string where;  // "sweptEnvelope: span i", for messages
  bool end_given = false;
  GrazingSet gs;
  Affine3 start, end_pose;
  Eigen::Matrix3d M;
  Vec u;
  std::vector<char> part;                       // per face: a Part
  std::vector<Vec> pt;                          // body-coordinate points (body vertices first)
  std::vector<Where> on_body;                   // per point
  std::vector<std::vector<EdgePoint>> on_edge;  // per edge: interior points, sorted by r
  std::vector<std::array<int, 2>> zero;         // per edge: zero point of faces[i]'s g on it
  std::vector<Segment> segs;                    // boundary segments of Front
  std::vector<int> chord_segment;               // per face: its chord's segment, or -1
  std::vector<int> comp_of, local;              // per point: component, index in it
  std::vector<std::vector<int>> comp_points;    // per component: its points
  std::vector<Grid> grids;                      // per component
  std::vector<std::vector<int>> sub;            // per segment: interior points from p to q
  std::vector<char> fixed;                      // per point: held fixed over the span
  std::vector<LinePlacement> lines;             // in the order they are placed
  // Per edge: no piece of it is a boundary segment that slides along itself (placed on a line)
  // or stands still (both ends fixed), so the points of a neighbouring span can be inserted
  // between its own (appendSpanCycle, "Joints"). Points that a chord placed on a line or held
  // fixed only where it crosses the edge do not count (see there).
  std::vector<char> plain_edge;
};

void SpanPlanDelete::operator()(SpanPlan* plan) const { delete plan; }

namespace {

double cornerValue(const SpanPlan& plan, int f, int v) {
  const auto& F = plan.body->faces();
  for (int k = 0; k < 3; ++k)
    if (F[f][k] == v) return plan.gs.corner_values[f][k];
  return 0.0;
}

// Is face f front at parameter r of its edge (a, b)? (Affine interpolation of snapped values.)
bool frontAt(const SpanPlan& plan, int f, int a, int b, double r) {
  if (plan.part[f] != kSplit) return plan.part[f] == kFront;
  return (1 - r) * cornerValue(plan, f, a) + r * cornerValue(plan, f, b) > 0;
}

// The polygon of face f on one side (sign +1: front, -1: back) through its corners and zeros,
// in the face's winding, without the points that only subdivide sides (added later).
std::vector<Corner> sidePolygon(const SpanPlan& plan, int f, int sign) {
  const auto& F = plan.body->faces();
  const auto& E = plan.body->edges();
  const auto& FE = plan.body->faceEdges();
  std::vector<Corner> poly;
  for (int k = 0; k < 3; ++k) {
    const int v = F[f][k];
    const double gk = plan.gs.corner_values[f][k], gn = plan.gs.corner_values[f][(k + 1) % 3];
    if (sign * gk >= 0) poly.push_back({v, true, sgn(gk) == 0});
    if (sgn(gk) * sgn(gn) < 0) {
      const int e = FE[f][k];
      poly.push_back({plan.zero[e][E[e].faces[0] == f ? 0 : 1], true, true});
    }
  }
  return poly;
}

// Barycentric coordinates of point q (a vertex of face f, or a point on its edges or chord)
// with respect to the corners of face f.
std::array<double, 3> barycentric(const SpanPlan& plan, int q, int f) {
  const auto& F = plan.body->faces();
  std::array<double, 3> l{{0, 0, 0}};
  // (a point made from others, such as a chord point from the chord's ends, takes theirs)
  std::function<void(int, double)> add = [&](int v, double weight) {
    for (int k = 0; k < 3; ++k)
      if (F[f][k] == v) {
        l[k] += weight;
        return;
      }
    const Where& w = plan.on_body[v];
    if (w.a < 0) return;
    add(w.a, weight * (1.0 - w.s - w.t));
    add(w.b, weight * w.s);
    if (w.c >= 0) add(w.c, weight * w.t);
  };
  add(q, 1.0);
  return l;
}

}  // namespace

SpanPlanPtr planSpan(const Body& body, const Span3& span, const Affine3* end_given, double eps,
                     const GrazingOptions& grazing, int max_steps, int span_index, EdgeZeros* seen) {
  SpanPlanPtr plan(new SpanPlan);
  SpanPlan& S = *plan;
  S.body = &body;
  S.where = "sweptEnvelope: span " + std::to_string(span_index);
  S.end_given = end_given != nullptr;
  S.gs = grazingSet(body, span, grazing);
  // The span's end is its key pose, as the joints are (the next span's start): exp(log A) at
  // τ = 1 carries the log's rounding, and the body at the end is the one the caller posed. A
  // half turn about the z axis through a face of the body (the bracket along screw.json, 1e-17
  // of input noise on the axis) left the end cap 3e-17 off the start cap's plane: the exact
  // trimming kept the void sliver between them, and rounding made its walls cross. Span3::end()
  // is the key pose itself, not relative() start(): after a pose that keeps z, that product
  // gave the final identity a z row of (0, 0, 1 - 1.1e-16) (a sweep fuzz input, the thin plate).
  S.end_pose = end_given ? *end_given : span.end();
  if (!S.end_pose.isFinite())
    throw Error(ErrorCode::NonFinite, "sweptEnvelope: the end pose of span " + std::to_string(span_index) +
                                          " is not finite");
  S.start = span.start();
  S.M = span.log().M;
  S.u = span.log().u;
  const GrazingSet& gs = S.gs;
  const auto& P = body.vertices();
  const auto& F = body.faces();
  const auto& E = body.edges();
  const std::size_t nf = F.size(), ne = E.size();
  const Affine3& start = S.start;
  const Eigen::Matrix3d& M = S.M;
  const Vec& u = S.u;
  const std::string& where = S.where;

  // Body-coordinate points: the body's vertices, then points on edges and chords.
  std::vector<Vec>& pt = S.pt;
  std::vector<Where>& on_body = S.on_body;
  pt.assign(P.begin(), P.end());
  on_body.assign(P.size(), Where{});
  auto addPoint = [&](const Vec& x, const Where& w) {
    pt.push_back(x);
    on_body.push_back(w);
    return static_cast<int>(pt.size()) - 1;
  };

  std::vector<char>& part = S.part;
  part.assign(nf, kBack);
  if (!gs.stationary)
    for (std::size_t f = 0; f < nf; ++f)
      part[f] = gs.faces[f] == FaceClass::Front ? kFront : gs.faces[f] == FaceClass::Split ? kSplit : kBack;
  auto g = [&](int f, int v) { return cornerValue(S, f, v); };

  // 1. Edges: zeros of the split faces' g, then the boundary pieces.
  auto& on_edge = S.on_edge;
  auto& zero = S.zero;
  std::vector<Segment>& segs = S.segs;
  on_edge.assign(ne, {});
  zero.assign(ne, {{-1, -1}});
  for (std::size_t e = 0; e < ne; ++e) {
    const int a = E[e].vertices[0], b = E[e].vertices[1];
    std::array<double, 2> root{{-1, -1}};
    for (int i = 0; i < 2; ++i) {
      const int f = E[e].faces[i];
      if (part[f] != kSplit) continue;
      const double ga = g(f, a), gb = g(f, b);
      if (sgn(ga) * sgn(gb) < 0) root[i] = ga / (ga - gb);
      if (root[i] < 0 || !seen) continue;
      std::vector<double>& known = (*seen)[e];
      const auto same = std::find_if(known.begin(), known.end(),
                                     [&](double r) { return std::abs(r - root[i]) <= kMergeParameter; });
      if (same != known.end())
        root[i] = *same;
      else
        known.push_back(root[i]);
    }
    for (int i = 0; i < 2; ++i) {
      if (root[i] < 0) continue;
      if (i == 1 && zero[e][0] >= 0 && std::abs(root[1] - root[0]) <= kMergeParameter) {
        zero[e][1] = zero[e][0];
        continue;
      }
      // (as a + r (b - a): exact in a coordinate the edge's ends share, such as the height of
      // a face that slides in its plane; (1 - r) a + r b can miss it by an ulp)
      const int id = addPoint(P[a] + root[i] * (P[b] - P[a]), Where{a, b, -1, root[i], 0.0, static_cast<int>(e)});
      zero[e][i] = id;
      on_edge[e].push_back({root[i], id});
    }
    std::sort(on_edge[e].begin(), on_edge[e].end(), [](const EdgePoint& x, const EdgePoint& y) { return x.r < y.r; });
    // Pieces between consecutive break points; a boundary where exactly one face is front.
    std::vector<EdgePoint> breaks{{0.0, a}};
    breaks.insert(breaks.end(), on_edge[e].begin(), on_edge[e].end());
    breaks.push_back({1.0, b});
    for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
      const double mid = 0.5 * (breaks[k].r + breaks[k + 1].r);
      const bool f0 = frontAt(S, E[e].faces[0], a, b, mid), f1 = frontAt(S, E[e].faces[1], a, b, mid);
      if (f0 == f1) continue;
      // faces[0] runs along the edge from a to b: Front on the left means its direction.
      Segment s;
      s.edge = static_cast<int>(e);
      if (f0) {
        s.p = breaks[k].point, s.q = breaks[k + 1].point, s.rp = breaks[k].r, s.rq = breaks[k + 1].r;
      } else {
        s.p = breaks[k + 1].point, s.q = breaks[k].point, s.rp = breaks[k + 1].r, s.rq = breaks[k].r;
      }
      segs.push_back(s);
    }
  }

  // 2. Chords of split faces: from the front polygon's first zero to its second.
  S.chord_segment.assign(nf, -1);
  for (std::size_t f = 0; f < nf; ++f) {
    if (part[f] != kSplit) continue;
    const std::vector<Corner> poly = sidePolygon(S, static_cast<int>(f), +1);
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n; ++i)
      if (poly[i].zero && poly[(i + 1) % n].zero) {
        Segment s;
        s.p = poly[i].point;
        s.q = poly[(i + 1) % n].point;
        s.face = static_cast<int>(f);
        S.chord_segment[f] = static_cast<int>(segs.size());
        segs.push_back(s);
        break;
      }
  }

  // 3. Connected components of the boundary curves; one time grid each (condition (1)).
  const double mu = spectralBound(M);
  std::vector<int> parent(pt.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const Segment& s : segs) parent[findRoot(parent, s.p)] = findRoot(parent, s.q);
  auto& comp_of = S.comp_of;
  auto& local = S.local;
  auto& comp_points = S.comp_points;
  comp_of.assign(pt.size(), -1);
  local.assign(pt.size(), -1);
  {
    std::vector<int> comp_of_root(pt.size(), -1);
    for (const Segment& s : segs)
      for (int q : {s.p, s.q}) {
        if (comp_of[q] >= 0) continue;
        int& c = comp_of_root[findRoot(parent, q)];
        if (c < 0) {
          c = static_cast<int>(comp_points.size());
          comp_points.emplace_back();
        }
        comp_of[q] = c;
        local[q] = static_cast<int>(comp_points[c].size());
        comp_points[c].push_back(q);
      }
  }
  const CleanPoses clean(span);
  auto poseAt = [&](double tau, bool first, bool last) {
    return first ? start : last ? S.end_pose : clean(tau);
  };
  auto& grids = S.grids;
  grids.resize(comp_points.size());
  std::vector<std::vector<int>> comp_segs(comp_points.size());  // the segments of each component
  for (std::size_t j = 0; j < segs.size(); ++j) comp_segs[static_cast<std::size_t>(comp_of[segs[j].p])].push_back(static_cast<int>(j));
  for (std::size_t c = 0; c < comp_points.size(); ++c) {
    Grid& grid = grids[c];
    double tau = 0.0;
    double balanced = 0;  // the pieces a cell may need in a balanced grid (see kBalancedPieces), or 0
    for (bool first = true;; first = false) {
      const bool last = !first && tau >= 1.0;
      const Affine3 pose = poseAt(tau, first, last);
      std::vector<Vec> row;
      row.reserve(comp_points[c].size());
      FlowNorms accel;  // of M v over the points (tessellation.hpp)
      for (int q : comp_points[c]) {
        row.push_back(pose(pt[q]));
        accel.include(FlowNorms::of(M, M * (M * row.back() + u)));
      }
      grid.tau.push_back(tau);
      grid.pose.push_back(pose);
      grid.world.push_back(std::move(row));
      if (last) break;
      if (static_cast<int>(grid.tau.size()) > max_steps)
        throw Error(ErrorCode::InvalidArgument, where + ": more than " + std::to_string(max_steps) +
                                                    " time steps for tolerance " + std::to_string(eps) +
                                                    "; raise the tolerance (or max_steps)");
      const double next = nextGridTime(tau, accel, mu, eps);
      const bool may_balance = first && !unbalanced_grids && next >= 1.0;
      if (!may_balance && balanced == 0) {
        tau = next;
        continue;
      }
      // The largest twist rate |M e| of the component's segments at this row, and the pieces
      // a step h would give them (condition (2), tessellation.hpp).
      FlowNorms twist_rate;
      for (const int j : comp_segs[c]) {
        const Segment& s = segs[static_cast<std::size_t>(j)];
        const Vec e = grid.world.back()[static_cast<std::size_t>(local[s.q])] - grid.world.back()[static_cast<std::size_t>(local[s.p])];
        twist_rate.include(FlowNorms::of(M, M * e));
      }
      const auto pieces = [&](double h) { return cellTwist(h, mu, twist_rate) / (0.5 * eps); };
      if (may_balance && pieces(1.0) > kBalancedPieces) balanced = std::ceil(std::sqrt(pieces(1.0)));
      if (balanced > 0 && pieces(next - tau) > balanced) {
        // The largest step whose cells need at most `balanced` pieces, evened out over what is
        // left of the span (so that no sliver of a step is left at its end).
        double h = (next - tau) * balanced / pieces(next - tau);
        while (pieces(h) > balanced) h *= 0.97;
        const double rem = 1.0 - tau, steps = std::ceil(rem / h);
        tau = steps <= 1 ? 1.0 : tau + rem / steps;
      } else {
        tau = next;
      }
    }
  }

  // 4. Pieces per segment (condition (2)) and their subdivision points, which the caps share.
  auto& sub = S.sub;
  sub.resize(segs.size());
  for (std::size_t j = 0; j < segs.size(); ++j) {
    Segment& s = segs[j];
    const Grid& grid = grids[comp_of[s.p]];
    double twist = 0.0;
    for (std::size_t k = 0; k + 1 < grid.tau.size(); ++k) {
      const Vec e = grid.world[k][local[s.q]] - grid.world[k][local[s.p]];
      twist = std::max(twist, cellTwist(grid.tau[k + 1] - grid.tau[k], mu, FlowNorms::of(M, M * e)));
    }
    const int m = piecesFor(twist, eps, max_steps, where + ", boundary segment " + std::to_string(j));
    // The cuts run from the segment's lesser end (body coordinates, lexicographically) to its
    // greater, whichever way the segment runs: two spans that cut the same segment alike, such as
    // a motion's first span and its last when the motion returns along itself (there the
    // segments run opposite ways), then make the same points, not points an ulp apart.
    const bool flip = std::lexicographical_compare(pt[s.q].data(), pt[s.q].data() + 3, pt[s.p].data(), pt[s.p].data() + 3);
    const int c0 = flip ? s.q : s.p, c1 = flip ? s.p : s.q;
    const double r0 = flip ? s.rq : s.rp, r1 = flip ? s.rp : s.rq;
    std::vector<double> cuts;
    for (int i = 1; i < m; ++i) cuts.push_back(static_cast<double>(i) / m);
    // A point of the segment that the motion keeps fixed (where its fixed axis or plane crosses
    // the segment: the speed is affine along it) cuts it too, and is held fixed below, so that
    // every row of the strip passes through that one vertex. Rows that only pass within an ulp
    // of it crossed each other there in thousands of faces 1e-15 wide (the tetrahedron turning
    // 100 degrees about an axis through itself, parallel to x), which the labels' rays then
    // tested in rationals for minutes.
    if (!gs.stationary) {
      const Vec vp = M * start(pt[c0]) + u, dv = M * start(pt[c1]) + u - vp;
      if (dv.squaredNorm() > 0) {
        const double t0 = -vp.dot(dv) / dv.squaredNorm();
        if (t0 > kFixedCutMargin && t0 < 1 - kFixedCutMargin && (vp + t0 * dv).norm() <= kFixedSpeed * gs.speed) {
          cuts.erase(std::remove_if(cuts.begin(), cuts.end(),
                                    [t0](double t) { return std::abs(t - t0) <= kFixedCutMargin; }),
                     cuts.end());
          cuts.insert(std::upper_bound(cuts.begin(), cuts.end(), t0), t0);
        }
      }
    }
    for (const double t : cuts) {
      const Vec x = pt[c0] + t * (pt[c1] - pt[c0]);  // (see the edges' zeros above)
      Where w;
      const double r = r0 + t * (r1 - r0);
      if (s.edge >= 0) {
        w = Where{E[s.edge].vertices[0], E[s.edge].vertices[1], -1, r, 0.0, s.edge};
      } else {
        // On the chord of face s.face, exactly: on the segment between the chord's ends. (So
        // where a polySAM's spans meet in the same chord ends, their points on it lie on one
        // line, and coincide when the spans cut it alike, instead of lying a few ulps off each
        // other's chord.)
        w = Where{c0, c1, -1, t, 0.0, -1};
      }
      const int id = addPoint(x, w);
      sub[j].push_back(id);
      if (s.edge >= 0) on_edge[s.edge].push_back({r, id});
    }
    if (flip) std::reverse(sub[j].begin(), sub[j].end());  // (from p to q)
  }
  for (auto& list : on_edge)
    std::sort(list.begin(), list.end(), [](const EdgePoint& x, const EdgePoint& y) { return x.r < y.r; });

  // Points held fixed: one vertex for all times.
  const std::size_t np = pt.size();
  S.fixed.assign(np, 0);
  for (std::size_t q = 0; q < np; ++q)
    S.fixed[q] = !gs.stationary && (M * start(pt[q]) + u).norm() <= kFixedSpeed * gs.speed;

  // Strips that slide along themselves: which points go on which line (appendSpanCycle places
  // them). A segment is flat when every row of its two ends lies within kOnLine ε of the line
  // through its τ = 0 ends; flat segments that share points form a group with one line when
  // every row of every end of the group is within reach of it, else one line per segment.
  const double line_tol = kOnLine * eps;
  // Is every row of the points `ends` (of one grid) within line_tol of the line through the τ = 0
  // positions of points a and b?
  auto alongLine = [&](const Grid& grid, int a, int b, const std::vector<int>& ends) {
    const Vec A = grid.world[0][local[a]];
    const Vec d = grid.world[0][local[b]] - A;
    if (!(d.norm() > line_tol)) return false;
    for (const auto& row : grid.world)
      for (int q : ends)
        if (!((row[local[q]] - A).cross(d).norm() <= line_tol * d.norm())) return false;
    return true;
  };
  S.plain_edge.assign(ne, 1);
  {
    std::vector<int> flat_parent(np);
    std::iota(flat_parent.begin(), flat_parent.end(), 0);
    std::vector<char> flat(segs.size(), 0);
    for (std::size_t j = 0; j < segs.size(); ++j) {
      const Segment& s = segs[j];
      flat[j] = alongLine(grids[comp_of[s.p]], s.p, s.q, {s.p, s.q});
      if (flat[j]) flat_parent[findRoot(flat_parent, s.p)] = findRoot(flat_parent, s.q);
      if (s.edge >= 0 && (flat[j] || (S.fixed[s.p] && S.fixed[s.q]))) S.plain_edge[static_cast<std::size_t>(s.edge)] = 0;
    }
    std::vector<std::vector<int>> groups;  // flat segments, by group
    std::vector<int> group_of_root(np, -1);
    for (std::size_t j = 0; j < segs.size(); ++j) {
      if (!flat[j]) continue;
      int& grp = group_of_root[findRoot(flat_parent, segs[j].p)];
      if (grp < 0) {
        grp = static_cast<int>(groups.size());
        groups.emplace_back();
      }
      groups[grp].push_back(static_cast<int>(j));
    }
    for (const std::vector<int>& group : groups) {
      std::vector<int> ends;
      for (int j : group)
        for (int q : {segs[j].p, segs[j].q})
          if (std::find(ends.begin(), ends.end(), q) == ends.end()) ends.push_back(q);
      const Grid& grid = grids[comp_of[ends[0]]];
      int a = segs[group[0]].p, b = segs[group[0]].q;
      double widest = (grid.world[0][local[b]] - grid.world[0][local[a]]).squaredNorm();
      for (std::size_t i = 0; i < ends.size(); ++i)
        for (std::size_t k = i + 1; k < ends.size(); ++k) {
          const double d2 = (grid.world[0][local[ends[k]]] - grid.world[0][local[ends[i]]]).squaredNorm();
          if (d2 > widest) widest = d2, a = ends[i], b = ends[k];
        }
      if (alongLine(grid, a, b, ends)) {
        LinePlacement line{ends, a, b};
        for (int j : group) line.pts.insert(line.pts.end(), sub[j].begin(), sub[j].end());
        S.lines.push_back(std::move(line));
      } else {
        for (int j : group) {
          LinePlacement line{{segs[j].p, segs[j].q}, segs[j].p, segs[j].q};
          line.pts.insert(line.pts.end(), sub[j].begin(), sub[j].end());
          S.lines.push_back(std::move(line));
        }
      }
    }
  }
  return plan;
}

void appendSpanCycle(Cycle& out, const SpanPlan* prev, const SpanPlan& plan, const SpanPlan* next) {
  const Body& body = *plan.body;
  // This span continues the previous one from the joint it left (Cycle::joint_vertex).
  const bool continues = prev != nullptr;
  if (continues == out.joint_vertex.empty())
    throw Error(ErrorCode::InvalidArgument,
                plan.where + ": appendSpanCycle called out of turn (" +
                    (continues ? "no joint left by the span before" : "a joint left over by another span") +
                    "); append a polySAM's spans in order, each with the plans of its neighbours");
  if (next && !plan.end_given)
    throw Error(ErrorCode::InvalidArgument, plan.where +
                                                ": the span has a next span but was planned without an end pose; "
                                                "plan it with the next span's start as its end pose");
  const auto& F = body.faces();
  const auto& E = body.edges();
  const auto& FE = body.faceEdges();
  const std::size_t nf = F.size(), ne = E.size();
  const Affine3& start = plan.start;
  const Affine3& end_pose = plan.end_pose;
  const std::vector<char>& part = plan.part;
  const std::vector<Vec>& pt = plan.pt;
  const std::vector<Where>& on_body = plan.on_body;
  const auto& on_edge = plan.on_edge;
  const std::vector<Segment>& segs = plan.segs;
  const auto& local = plan.local;
  const auto& comp_of = plan.comp_of;
  const auto& comp_points = plan.comp_points;
  const std::vector<Grid>& grids = plan.grids;
  const auto& sub = plan.sub;
  const std::vector<char>& fixed = plan.fixed;
  const std::size_t np = pt.size();

  // Vertices of points at τ = 0 and τ = 1 (shared by caps and strips); fixed points keep one.
  std::vector<int> id0(np, -1), id1(np, -1);
  auto vertex = [&](const Vec& x) {
    out.vertices.push_back(x);
    out.exact.emplace_back();
    return static_cast<int>(out.vertices.size()) - 1;
  };
  // A vertex at A + s (B - A) + t (C - A) of posed body vertices (ids of `out`, c < 0 for none).
  auto combination = [&](int a, int b, int c, double s, double t) {
    const Vec& A = out.vertices[a];
    Vec x = A + s * (out.vertices[b] - A);
    if (c >= 0) x += t * (out.vertices[c] - A);
    out.vertices.push_back(x);
    out.exact.push_back(ExactPosition{a, b, c, s, c >= 0 ? t : 0.0});
    return static_cast<int>(out.vertices.size()) - 1;
  };
  // Joints. A span that starts where the previous one ended (Cycle::joint_vertex, joint_edge)
  // starts from that span's end vertices for the same body points: body vertices by index, points
  // on an edge by their edge parameter (merged within kMergeParameter, as the zeros of an edge's
  // two faces are). So the caps and strips the two spans leave at the joint meet in identical
  // exact points, also where the previous span moved its points onto a line (below).
  if (continues) {
    for (std::size_t q = 0; q < np; ++q) {
      const Where& w = on_body[q];
      if (w.a < 0) {
        id0[q] = out.joint_vertex[q];
      } else if (w.edge >= 0) {
        for (const auto& [r, v] : out.joint_edge[static_cast<std::size_t>(w.edge)])
          if (std::abs(r - w.s) <= kMergeParameter) id0[q] = v;
      }
    }
  }
  std::function<int(int)> at0, at1;
  at0 = [&](int q) {
    if (id0[q] < 0) {
      const Where& w = on_body[q];
      id0[q] = w.a < 0 ? vertex(start(pt[q])) : combination(at0(w.a), at0(w.b), w.c < 0 ? -1 : at0(w.c), w.s, w.t);
    }
    return id0[q];
  };
  at1 = [&](int q) {
    if (fixed[q]) return at0(q);
    if (id1[q] < 0) {
      const Where& w = on_body[q];
      id1[q] = w.a < 0 ? vertex(end_pose(pt[q])) : combination(at1(w.a), at1(w.b), w.c < 0 ? -1 : at1(w.c), w.s, w.t);
    }
    return id1[q];
  };

  // Strips that slide along themselves. A boundary segment on a line that the motion keeps
  // invariant (a face containing a screw axis while the span rises or scales along it) sweeps
  // no area, but its vertices, computed a few ulps off that line, make a sliver ribbon whose
  // exact arrangement rounds into edges with four faces (or faces that cross). The plan groups
  // such flat segments (SpanPlan::lines): body vertices along the axis are rarely exactly
  // collinear (input noise of 1e-17), and a point shared by two segments placed on either
  // segment's own line would leave the other segment's strip a ribbon of slivers. All of a
  // group's vertices are placed exactly on its line (ExactPosition on the two anchors): at
  // τ = 0 every point but the anchors (unless the previous span left it at the joint, or it was
  // already placed), at the interior rows, and at τ = 1, so that its triangles have no area and
  // drop out of the arrangement. A point shared by two lines stays on the first. Vertices move by
  // at most kOnLine ε.
  std::vector<std::array<int, 2>> line_of(np, {{-1, -1}});  // anchors (vertex ids) of the line
  auto onLine = [&](int q, const Vec& x) {
    const Vec& A = out.vertices[line_of[q][0]];
    const Vec d = out.vertices[line_of[q][1]] - A;
    return combination(line_of[q][0], line_of[q][1], -1, (x - A).dot(d) / d.squaredNorm(), 0.0);
  };
  for (const LinePlacement& line : plan.lines) {
    const std::array<int, 2> anchors{{at0(line.a), at0(line.b)}};
    for (int q : line.pts)
      if (line_of[q][0] < 0) line_of[q] = anchors;
    for (int q : line.pts)
      if (q != line.a && q != line.b && id0[q] < 0 && line_of[q] == anchors) id0[q] = onLine(q, start(pt[q]));
    for (int q : line.pts)
      if (!fixed[q] && id1[q] < 0) id1[q] = onLine(q, end_pose(pt[q]));
  }
  // A strip vertex at an interior row: on its line when it has one.
  auto rowVertex = [&](int q, const Vec& x) { return line_of[q][0] >= 0 ? onLine(q, x) : vertex(x); };

  // 5. Joints: the points of both spans on the edges at a joint. At a joint with a neighbour
  // (side 0: τ = 0, the span before; side 1: τ = 1, the span after), an edge that is plain in
  // both spans (SpanPlan::plain_edge) holds the neighbour's points between its own: the caps and
  // the strips at the joint pass through all of them, on both sides. Each side's cycle stays
  // closed, and a face's caps on the two sides of the joint then have the same polygon, so the
  // joint's sum of caps can be emitted as it is: nothing where both spans move the face outward
  // (the caps cancel), the Back side of the chord where one of them splits it (below). Before,
  // each span fanned its caps through its own points: on the tetrahedron along
  // data/motions/keys.json all 21,444 cap triangles (31% of the cycle) stayed, and every
  // coplanar crossing pair of its arrangement was one cap against another.
  // The neighbour's points lie exactly on the posed edge (ExactPosition on its two end vertices,
  // which both spans share), as the span's own points there do, so they subdivide the edge
  // without moving it. A neighbour's point within kMergeParameter of one of the span's own is
  // that point.
  // Two kinds of own points lie off the posed edge by rounding: where a chord that slides along
  // itself crosses the edge (placed on the chord's line, which misses the edge by about 1e-17
  // where it runs through two faces, such as the two triangles of a box's side, whose posed
  // corners are not exactly coplanar), and where a chord that stands still crosses it (a fixed
  // point keeps its τ = 0 vertex at τ = 1). The edge then bends by that much at the point, in
  // the caps on both of its sides alike, which keeps Q closed, and the caps still merge. When
  // such points kept the edge from merging, the two spans' caps of the face both stayed: one
  // flat, one bent by 1e-17 where it reached the point, which crossed at that angle over the
  // whole face, and the trimming rounded the crossing into faces that overlap. The box along
  // random polySAMs of straight shears (the velocity field v(x) = u (w . x) + t: every velocity
  // along u, so the grazing chords slide along themselves, or, with t = 0, lie in the plane of
  // fixed points) failed its check in 4 of 4 cases with 9 to 785 crossing pairs, up to 237 s; it
  // passes in all four in 0.1 s (tests/sweep/fixtures/box_two_shears.json); of the first 90
  // cases of the campaign's polySAMs of straight shears (scripts/stress-sweep.sh 0 90 --shears),
  // 68 pass and 2 are void, against 16 and none before (64 failed, 10 ran past 200 s). An edge
  // whose own pieces slide along themselves or stand still (SpanPlan::plain_edge) still keeps
  // its points to itself: its strip, flat on its line, would be fanned at the joint to the
  // neighbour's points, which lie off that line (not tried).
  struct Extra {
    double r = 0;
    int vid = -1;  // vertex of `out` (side 1: made when first needed)
  };
  std::array<std::vector<std::vector<Extra>>, 2> extra;
  auto shared = [&](const SpanPlan* nb, std::size_t e) {
    return nb != nullptr && plan.plain_edge[e] && nb->plain_edge[e];
  };
  auto own = [&](std::size_t e, double r) {
    for (const EdgePoint& ep : on_edge[e])
      if (std::abs(ep.r - r) <= kMergeParameter) return true;
    return false;
  };
  for (int side = 0; side < 2; ++side) {
    const SpanPlan* nb = side == 0 ? prev : next;
    if (!nb) continue;
    extra[side].resize(ne);
    for (std::size_t e = 0; e < ne; ++e) {
      if (!shared(nb, e)) continue;
      if (side == 0) {
        for (const auto& [r, v] : out.joint_edge[e])
          if (!own(e, r)) extra[0][e].push_back({r, v});
      } else {
        for (const EdgePoint& ep : nb->on_edge[e])
          if (!own(e, ep.r)) extra[1][e].push_back({ep.r, -1});
      }
      std::sort(extra[side][e].begin(), extra[side][e].end(), [](const Extra& x, const Extra& y) { return x.r < y.r; });
    }
  }
  // Does every edge of face f hold the points of both spans at the joint with `nb`?
  auto merged = [&](const SpanPlan* nb, int f) {
    for (int k = 0; k < 3; ++k)
      if (!shared(nb, static_cast<std::size_t>(FE[f][k]))) return false;
    return true;
  };
  // A chord met again: where the span before left a face split by a chord with the same ends
  // (the same vertices) and as many points, running the same way, its points are this chord's
  // (both are the same combinations of the same ends), so the chords cancel at the joint.
  if (continues)
    for (std::size_t f = 0; f < nf; ++f) {
      const std::vector<int>& before = out.joint_chord[f];
      if (before.empty() || part[f] != kSplit || !merged(prev, static_cast<int>(f))) continue;
      const Segment& s = segs[plan.chord_segment[f]];
      const std::vector<int>& points = sub[plan.chord_segment[f]];
      if (before.size() != points.size() + 2 || before.front() != at0(s.p) || before.back() != at0(s.q)) continue;
      for (std::size_t k = 0; k < points.size(); ++k)
        if (id0[points[k]] < 0) id0[points[k]] = before[k + 1];
    }
  // The points strictly between edge parameters r0 and r1 of edge e at `side`, with their
  // parameters, in order from r0 to r1: the span's own points and the neighbour's.
  auto pointsBetween = [&](int e, double r0, double r1, int side) {
    const double lo = std::min(r0, r1), hi = std::max(r0, r1);
    std::vector<std::pair<double, Corner>> found;
    for (const EdgePoint& ep : on_edge[e])
      if (ep.r > lo && ep.r < hi) found.push_back({ep.r, Corner{ep.point, false, false}});
    if (!extra[side].empty())
      for (Extra& x : extra[side][e])
        if (x.r > lo && x.r < hi) {
          if (x.vid < 0) {  // (side 1: on the edge at τ = 1)
            const int a = E[e].vertices[0], b = E[e].vertices[1];
            x.vid = combination(at1(a), at1(b), -1, x.r, 0.0);
          }
          found.push_back({x.r, Corner{-1, false, false, x.vid}});
        }
    std::sort(found.begin(), found.end(), [&](const auto& x, const auto& y) {
      return r0 < r1 ? x.first < y.first : x.first > y.first;
    });
    return found;
  };
  // ... appended to `list`.
  auto between = [&](int e, double r0, double r1, int side, std::vector<Corner>& list) {
    for (const auto& f : pointsBetween(e, r0, r1, side)) list.push_back(f.second);
  };

  // 6. Caps: Back (and Grazing) polygons at τ = 0 (reversed Front polygons when the span
  // continues a polySAM), Front polygons at τ = 1, with every point that lies on their sides,
  // fanned into triangles or triangulated in graded rings (`reversed`: against the polygon's
  // winding).
  auto emitPolygon = [&](int f, const std::vector<Corner>& poly, bool at_end, bool reversed) {
    auto emit = [&](int a, int b, int c) {
      out.triangles.push_back(reversed ? std::array<int, 3>{{a, c, b}} : std::array<int, 3>{{a, b, c}});
      ++out.cap_triangles;
    };
    const int side = at_end ? 1 : 0;
    // Insert the points that subdivide the sides: along face edges, and along the chord.
    std::vector<Corner> full;
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Corner& x = poly[i];
      const Corner& y = poly[(i + 1) % n];
      full.push_back(x);
      if (x.zero && y.zero && part[f] == kSplit) {  // the chord
        const Segment& s = segs[plan.chord_segment[f]];
        const auto& list = sub[plan.chord_segment[f]];
        if (s.p == x.point)
          for (int q : list) full.push_back({q, false, false});
        else
          for (auto it = list.rbegin(); it != list.rend(); ++it) full.push_back({*it, false, false});
        continue;
      }
      // Along a face edge: find the edge holding both points and their parameters.
      for (int k = 0; k < 3; ++k) {
        const int e = FE[f][k];
        const int a = E[e].vertices[0], b = E[e].vertices[1];
        auto param = [&](int q, double& r) {
          if (q == a) return r = 0.0, true;
          if (q == b) return r = 1.0, true;
          for (const EdgePoint& ep : on_edge[e])
            if (ep.point == q) return r = ep.r, true;
          return false;
        };
        double rx = 0, ry = 0;
        if (!param(x.point, rx) || !param(y.point, ry)) continue;
        between(e, rx, ry, side, full);
        break;
      }
    }
    auto id = [&](const Corner& c) { return c.vertex >= 0 ? c.vertex : at_end ? at1(c.point) : at0(c.point); };
    const std::size_t m = full.size();
    const bool plain = std::all_of(full.begin(), full.end(), [](const Corner& c) { return c.true_corner; });
    if (m == 3) {
      emit(id(full[0]), id(full[1]), id(full[2]));
      return;
    }
    if (plain && m == 4) {  // a convex quad: split along its shorter diagonal
      const double d02 = (pt[full[0].point] - pt[full[2].point]).squaredNorm();
      const double d13 = (pt[full[1].point] - pt[full[3].point]).squaredNorm();
      const int o = d02 <= d13 ? 0 : 1;
      const int a = id(full[o]), b = id(full[o + 1]), c = id(full[o + 2]), d = id(full[(o + 3) % 4]);
      emit(a, b, c);
      emit(a, c, d);
      return;
    }
    // A fan around an interior point of the (convex) polygon: the midpoint of the diagonal 0-2
    // when it has four or more true corners, else (A + (B + C) / 2) / 2, inside the triangle
    // ABC; placed exactly in the posed face's plane by its barycentric coordinates.
    std::vector<int> corners;
    for (const Corner& c : full)
      if (c.true_corner) corners.push_back(c.point);
    const auto lA = barycentric(plan, corners[0], f), lC = barycentric(plan, corners[2], f);
    std::array<double, 3> l{};
    if (corners.size() >= 4) {
      for (int k = 0; k < 3; ++k) l[k] = 0.5 * (lA[k] + lC[k]);
    } else {
      const auto lB = barycentric(plan, corners[1], f);
      for (int k = 0; k < 3; ++k) l[k] = 0.5 * (lA[k] + 0.5 * (lB[k] + lC[k]));
    }
    auto pose = [&](int q) { return at_end ? at1(q) : at0(q); };
    const int cv = combination(pose(F[f][0]), pose(F[f][1]), pose(F[f][2]), l[1], l[2]);
    if (m <= kGradedCapPoints || fan_every_cap) {
      for (std::size_t i = 0; i < m; ++i) emit(cv, id(full[i]), id(full[(i + 1) % m]));
      return;
    }
    const int A = pose(F[f][0]), B = pose(F[f][1]), C = pose(F[f][2]);  // (made above)
    // Graded rings. The polygon's points are numbered along each side from its first true
    // corner (0) to the next (n + 1); a point of side number i has level ctz(i) (the corners
    // every level). Ring j (j = 1, 2, ...) holds the points of level >= j, moved toward the
    // centre G by the homothety of ratio rho_j: every point stays on its ray from G, so the band
    // between rings j - 1 and j splits into cells between the rays of consecutive ring-j points
    // a and b, with at most one ring-(j-1) point c between them (its side number is an odd
    // multiple of 2^(j-1)): triangles (a', c', a), (c', b, a), (c', b', b) with c, or
    // (a', b', b), (a', b, a) without (primes on ring j - 1). a', c' and b' lie on one side of
    // the polygon shrunk by rho_(j-1), and a b is parallel to a' b': each cell is a trapezoid,
    // which its triangles split, so they keep the polygon's winding (G lies inside, the polygon
    // is convex). The last ring holds the true corners alone and is fanned around G. The
    // rings' spacing along a side doubles from ring to ring, and so does the gap between rings,
    // from about the finest spacing of a side at the side nearest G, until it is half of what
    // is left to G (and at least 1e-9 of it: a gap far above the rounding of the ring points,
    // 1e-16 of the coordinates). About 3 n triangles for n points, against n for a fan, but on
    // the L-shaped prism's shear at 1e-3 (test LongCapSidesAreTriangulatedInGradedRings) their
    // boxes meet in 29 pairs per cap triangle against 588 (fans), and the sweep took 0.34-0.36 s
    // against 0.79-0.85 s.
    // Ring points are placed exactly in the posed face's plane (ExactPosition on A, B, C), by
    // their coordinates (s, t) on A, B, C: G's plus rho_j times the offset of the point's.
    std::size_t first = 0;
    while (!full[first].true_corner) ++first;
    std::vector<Corner> ring0(full.begin() + static_cast<std::ptrdiff_t>(first), full.end());
    ring0.insert(ring0.end(), full.begin(), full.begin() + static_cast<std::ptrdiff_t>(first));
    std::vector<int> level(m, std::numeric_limits<int>::max());
    std::vector<std::array<double, 2>> st(m);  // (s, t) of each point on A, B, C
    const PlaneCoordinates onFace(out.vertices[A], out.vertices[B], out.vertices[C]);
    const Vec pG = out.vertices[cv];
    double finest = std::numeric_limits<double>::infinity(), nearest = finest;
    int top = 0;  // the largest level of a point that is not a true corner
    for (std::size_t i = 0, side_start = 0; i < m; ++i) {
      if (ring0[i].true_corner) {
        side_start = i;
      } else {
        level[i] = __builtin_ctz(static_cast<unsigned>(i - side_start));
        top = std::max(top, level[i]);
      }
      if (ring0[i].point >= 0) {
        const auto b = barycentric(plan, ring0[i].point, f);
        st[i] = {{b[1], b[2]}};
      } else {  // (a neighbour's point at a joint: from its coordinates)
        st[i] = onFace(out.vertices[id(ring0[i])]);
      }
      // (per side with points on it: its spacing, and its distance from G)
      if (ring0[i].true_corner) {
        std::size_t j = i + 1;
        while (j < m && !ring0[j].true_corner) ++j;
        if (j > i + 1) {
          const Vec p = out.vertices[id(ring0[i])], q = out.vertices[id(ring0[j % m])];
          const double len = (q - p).norm();
          finest = std::min(finest, len / static_cast<double>(j - i));
          nearest = std::min(nearest, (q - p).cross(pG - p).norm() / len);
        }
      }
    }
    std::vector<int> outer(m), inner(m, -1);  // per point: its vertex on the last ring made, on this one
    for (std::size_t i = 0; i < m; ++i) outer[i] = id(ring0[i]);
    std::vector<std::size_t> before(m);  // the points of the last ring made, in order
    std::iota(before.begin(), before.end(), std::size_t{0});
    double rho = 1.0;
    for (int j = 1; j <= top + 1; ++j) {
      const double gap = std::ldexp(finest, j - 1) / nearest;  // (inf when G lies on a side)
      rho *= 1.0 - (gap >= 0.5 || !(gap >= 0) ? 0.5 : std::max(gap, 1e-9));
      std::vector<std::size_t> kept;  // (starts with point 0, a true corner, as `before` does)
      for (const std::size_t i : before)
        if (level[i] >= j) {
          kept.push_back(i);
          inner[i] = combination(A, B, C, l[1] + rho * (st[i][0] - l[1]), l[2] + rho * (st[i][1] - l[2]));
        }
      for (std::size_t k = 0, at = 0; k < kept.size(); ++k) {
        const std::size_t a = kept[k], b = kept[(k + 1) % kept.size()];
        const std::size_t after = (at + 1) % before.size();
        if (before[after] == b) {
          emit(outer[a], outer[b], inner[b]);
          emit(outer[a], inner[b], inner[a]);
          at = after;
          continue;
        }
        const std::size_t c = before[after];
        at = (after + 1) % before.size();
        if (before[at] != b)
          throw Error(ErrorCode::InvalidArgument, plan.where + ": the graded cap of face " + std::to_string(f) +
                                                      " skips a point (an internal error; please report it)");
        emit(outer[a], outer[c], inner[a]);
        emit(outer[c], inner[b], inner[a]);
        emit(outer[c], outer[b], inner[b]);
      }
      for (const std::size_t i : kept) outer[i] = inner[i];
      before = std::move(kept);
    }
    std::vector<int> last;
    for (std::size_t i = 0; i < m; ++i)
      if (ring0[i].true_corner) last.push_back(outer[i]);
    for (std::size_t k = 0; k < last.size(); ++k) emit(cv, last[k], last[(k + 1) % last.size()]);
  };
  // A face split in both spans at a joint whose edges all hold both spans' points (see 5): the
  // sum of the end cap of the span before (+ its Front part) and the reversed start cap of the
  // span after (- its Front part) is bounded by the chord before, the chord after (reversed),
  // and the pieces of the face's edges that are Front in one span only; the pieces Front in both
  // cancel. The span after emits it at τ = 0, one fan per closed loop of that boundary, around
  // the mean of the loop's points (placed exactly in the posed face's plane): where the chords
  // do not cross inside the face each loop bounds a convex region; where they cross, the one
  // loop crosses itself and is first cut there (splitAndFan). The span before leaves its
  // chord's vertices at τ = 1 in Cycle::joint_chord.
  // The vertices of face f's chord at τ = 0 or 1, from the Front polygon's first zero to its
  // second.
  auto chordVertices = [&](int f, const std::function<int(int)>& at) {
    const Segment& s = segs[plan.chord_segment[f]];
    std::vector<int> chord{at(s.p)};
    for (int q : sub[plan.chord_segment[f]]) chord.push_back(at(q));
    chord.push_back(at(s.q));
    return chord;
  };
  // Fans a closed loop of a joint cap (below) around the mean of its points, placed exactly in
  // the plane of A, B, C. Where the two chords cross inside the face, the loop crosses itself
  // and its fan would overlap itself: triangles of opposite orientations over the same area,
  // which cancel only if they are exactly coplanar, and they are not (a chord that stands still
  // keeps its τ = 0 vertices, a chord that slides along itself lies on a line through a
  // neighbouring face: both a rounding off the joint pose's plane). In the arrangement they did
  // not cancel, and one of them reached the envelope inside the swept volume, unreported (the
  // campaign's polySAMs of straight shears, case 27: 3.4 ε deep). So the loop is cut at the
  // crossing X of two of its edges (found in the face's coordinates) into the two loops on
  // either side of X, each fanned alike (each is convex: a face cut by two lines). X is placed
  // exactly on the first edge (p, q); the triangles (p, q, X) (no area: dropped by the
  // trimming) and (r, s, X) for the second edge (r, s) keep the sum of the triangles' boundaries
  // the loop. The second is a sliver, as wide as the rounding that keeps the two edges from
  // meeting; left as it is, it broke the output of 2 of 7 such cases (edges of three faces), so
  // it is merged with the triangle across r s when the cycle is complete (mergeJointSlivers).
  auto splitAndFan = [&](std::vector<int> loop, const PlaneCoordinates& onFace, int A, int B, int C) {
    auto emit = [&](int a, int b, int c) {
      out.triangles.push_back({{a, b, c}});
      ++out.cap_triangles;
    };
    std::vector<std::vector<int>> todo{std::move(loop)};
    while (!todo.empty()) {
      std::vector<int> lp = std::move(todo.back());
      todo.pop_back();
      const std::size_t n = lp.size();
      if (n < 3) continue;  // (x to y and back: nothing)
      std::vector<std::array<double, 2>> uv(n);
      for (std::size_t k = 0; k < n; ++k) uv[k] = onFace(out.vertices[lp[k]]);
      auto orient = [&](std::size_t a, std::size_t b, std::size_t c) {
        return (uv[b][0] - uv[a][0]) * (uv[c][1] - uv[a][1]) - (uv[b][1] - uv[a][1]) * (uv[c][0] - uv[a][0]);
      };
      // The first pair of edges (i, i + 1), (j, j + 1) that are not neighbours and cross
      // properly (each one's ends strictly on either side of the other's line, in doubles: a
      // crossing missed or found near an end only decides whether a tiny lobe is cut off, the
      // triangles' sum is the loop either way).
      std::size_t ci = n, cj = n;
      double at = 0;
      for (std::size_t i = 0; i + 2 < n && ci == n; ++i)
        for (std::size_t j = i + 2; j < n && ci == n; ++j) {
          const std::size_t i1 = i + 1, j1 = (j + 1) % n;
          if (j1 == i) continue;
          const double oi = orient(i, i1, j), oi1 = orient(i, i1, j1);
          const double oj = orient(j, j1, i), oj1 = orient(j, j1, i1);
          if (oi * oi1 < 0 && oj * oj1 < 0) ci = i, cj = j, at = oj / (oj - oj1);
        }
      if (ci < n) {
        const std::size_t i1 = ci + 1, j1 = (cj + 1) % n;
        const int x = combination(lp[ci], lp[i1], -1, at, 0.0);
        emit(lp[ci], lp[i1], x);
        emit(lp[cj], lp[j1], x);
        out.joint_slivers.push_back({{static_cast<int>(out.triangles.size()) - 1, lp[cj], lp[j1], x}});
        std::vector<int> one{x}, two{x};
        for (std::size_t k = i1; k <= cj; ++k) one.push_back(lp[k]);
        for (std::size_t k = j1; k != i1; k = (k + 1) % n) two.push_back(lp[k]);
        todo.push_back(std::move(one));
        todo.push_back(std::move(two));
        continue;
      }
      Vec mean = Vec::Zero();
      for (int v : lp) mean += out.vertices[v];
      mean /= static_cast<double>(n);
      const std::array<double, 2> st = onFace(mean);
      const int cv = combination(A, B, C, st[0], st[1]);
      for (std::size_t k = 0; k < n; ++k) emit(cv, lp[k], lp[(k + 1) % n]);
    }
  };
  auto emitSplitJoint = [&](int f) {
    std::vector<std::array<int, 2>> edges;  // the boundary, as directed edges
    const std::vector<int>& before = out.joint_chord[static_cast<std::size_t>(f)];
    for (std::size_t k = 0; k + 1 < before.size(); ++k) edges.push_back({{before[k], before[k + 1]}});
    const std::vector<int> chord = chordVertices(f, at0);
    for (std::size_t k = 0; k + 1 < chord.size(); ++k) edges.push_back({{chord[k + 1], chord[k]}});
    for (int k = 0; k < 3; ++k) {
      const int e = FE[f][k];
      const int a = E[e].vertices[0], b = E[e].vertices[1];
      const double r0 = F[f][k] == a ? 0.0 : 1.0;
      std::vector<std::pair<double, Corner>> pts = pointsBetween(e, r0, 1.0 - r0, 0);
      pts.insert(pts.begin(), {r0, Corner{F[f][k], true, false}});
      pts.push_back({1.0 - r0, Corner{F[f][(k + 1) % 3], true, false}});
      for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
        const double mid = 0.5 * (pts[i].first + pts[i + 1].first);
        const bool was = frontAt(*prev, f, a, b, mid), is = frontAt(plan, f, a, b, mid);
        if (was == is) continue;
        const int x = pts[i].second.vertex >= 0 ? pts[i].second.vertex : at0(pts[i].second.point);
        const int y = pts[i + 1].second.vertex >= 0 ? pts[i + 1].second.vertex : at0(pts[i + 1].second.point);
        edges.push_back(was ? std::array<int, 2>{{x, y}} : std::array<int, 2>{{y, x}});
      }
    }
    // Closed loops of the boundary (each vertex has as many edges in as out).
    const int A = at0(F[f][0]), B = at0(F[f][1]), C = at0(F[f][2]);
    // (copies of the corners: combination() below grows out.vertices)
    const PlaneCoordinates onFace(out.vertices[A], out.vertices[B], out.vertices[C]);
    std::vector<char> used(edges.size(), 0);
    for (std::size_t first = 0; first < edges.size(); ++first) {
      if (used[first]) continue;
      std::vector<int> loop;
      for (std::size_t k = first;;) {
        used[k] = 1;
        loop.push_back(edges[k][0]);
        const int to = edges[k][1];
        if (to == edges[first][0]) break;
        std::size_t n = 0;
        while (n < edges.size() && (used[n] || edges[n][0] != to)) ++n;
        if (n == edges.size())
          throw Error(ErrorCode::InvalidArgument, plan.where + ": the caps of face " + std::to_string(f) +
                                                      " at its joint do not close (an internal error; please report it)");
        k = n;
      }
      splitAndFan(loop, onFace, A, B, C);
    }
  };
  // A face's caps at a joint whose edges all hold both spans' points (see 5): the end cap of the
  // span before (+ its Front part) and the reversed start cap of the span after (- its Front
  // part) sum to nothing when the face is Front in both, to + the Back part of the span after
  // when it is Front before and split after, and to - the Back part of the span before when it
  // is split before and Front after. Each sum is emitted by the span that holds the split.
  std::vector<std::vector<int>> joint_chord(next ? nf : 0);  // for the span after (Cycle::joint_chord)
  for (std::size_t f = 0; f < nf; ++f) {
    const int fi = static_cast<int>(f);
    const std::vector<Corner> whole{{F[f][0], true, false}, {F[f][1], true, false}, {F[f][2], true, false}};
    // τ = 0
    if (!continues) {
      if (part[f] == kSplit) emitPolygon(fi, sidePolygon(plan, fi, -1), false, false);
      if (part[f] == kBack) emitPolygon(fi, whole, false, false);
    } else {
      const char before = merged(prev, fi) ? prev->part[f] : static_cast<char>(kBack);
      if (part[f] == kFront && before == kBack) emitPolygon(fi, whole, false, true);
      if (part[f] == kSplit) {
        if (before == kFront)
          emitPolygon(fi, sidePolygon(plan, fi, -1), false, false);
        else if (before == kSplit)
          emitSplitJoint(fi);
        else
          emitPolygon(fi, sidePolygon(plan, fi, +1), false, true);
      }
    }
    // τ = 1
    const char after = next && merged(next, fi) ? next->part[f] : static_cast<char>(kBack);
    if (part[f] == kFront && after == kBack) emitPolygon(fi, whole, true, false);
    if (part[f] == kSplit) {
      if (after == kFront) {
        emitPolygon(fi, sidePolygon(plan, fi, -1), true, true);
      } else if (after == kSplit) {  // (the span after emits the sum)
        joint_chord[f] = chordVertices(fi, at1);
      } else {
        emitPolygon(fi, sidePolygon(plan, fi, +1), true, false);
      }
    }
  }

  // 7. Strips: vertices of the component points at the interior grid rows, then two triangles
  // per cell, oriented so that the strip's τ = 1 side runs against the Front polygon's. At a
  // joint a cell's side on the edge holds the neighbour's points too (see 5): the cell is then
  // fanned from its corners, the same triangle cut into pieces.
  std::vector<std::vector<std::vector<int>>> rows(grids.size());  // [comp][row][local]
  for (std::size_t c = 0; c < grids.size(); ++c) {
    const std::size_t K = grids[c].tau.size() - 1;
    rows[c].resize(K + 1);
    for (std::size_t k = 0; k <= K; ++k)
      for (std::size_t i = 0; i < comp_points[c].size(); ++i) {
        const int q = comp_points[c][i];
        rows[c][k].push_back(k == 0 || fixed[q] ? at0(q) : k == K ? at1(q) : rowVertex(q, grids[c].world[k][i]));
      }
  }
  std::vector<Corner> below, above;
  for (std::size_t j = 0; j < segs.size(); ++j) {
    const Segment& s = segs[j];
    const int c = comp_of[s.p];
    const Grid& grid = grids[c];
    const std::size_t K = grid.tau.size() - 1;
    const std::size_t m = sub[j].size() + 1;
    // Edge parameter of the row's i-th point (edge pieces only).
    auto rAt = [&](std::size_t i) { return i == 0 ? s.rp : i == m ? s.rq : on_body[sub[j][i - 1]].s; };
    std::vector<int> prev_row, cur(m + 1);
    for (std::size_t k = 0; k <= K; ++k) {
      cur[0] = rows[c][k][local[s.p]];
      cur[m] = rows[c][k][local[s.q]];
      for (std::size_t i = 1; i < m; ++i) {
        const int q = sub[j][i - 1];
        cur[i] = k == 0 || fixed[q] ? at0(q) : k == K ? at1(q) : rowVertex(q, grid.pose[k](pt[q]));
      }
      if (k > 0)
        for (std::size_t i = 0; i < m; ++i) {
          // The cell's lower side from prev_row[i] to prev_row[i + 1], its upper side from cur[i]
          // to cur[i + 1], each with the neighbour's points at a joint.
          below.assign(1, Corner{-1, false, false, prev_row[i]});
          above.assign(1, Corner{-1, false, false, cur[i]});
          if (s.edge >= 0 && k == 1) between(s.edge, rAt(i), rAt(i + 1), 0, below);
          if (s.edge >= 0 && k == K) between(s.edge, rAt(i), rAt(i + 1), 1, above);
          below.push_back(Corner{-1, false, false, prev_row[i + 1]});
          above.push_back(Corner{-1, false, false, cur[i + 1]});
          // (a segment's own points on its edge are all in its row: only the neighbour's are
          // between two of them)
          for (Corner& x : below)
            if (x.vertex < 0) x.vertex = at0(x.point);
          for (Corner& x : above)
            if (x.vertex < 0) x.vertex = at1(x.point);
          auto add = [&](const std::array<int, 3>& t) {
            if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return;  // a fixed point's cell
            out.triangles.push_back(t);
            ++out.strip_triangles;
          };
          for (std::size_t b = 0; b + 1 < below.size(); ++b)
            add({{below[b].vertex, below[b + 1].vertex, cur[i + 1]}});
          for (std::size_t a = 0; a + 1 < above.size(); ++a)
            add({{prev_row[i], above[a + 1].vertex, above[a].vertex}});
        }
      prev_row = cur;
    }
  }

  // The joint for the next span (see Cycle::joint_vertex), or none; with the points of the next
  // span that this one placed on its edges (5).
  out.joint_vertex.clear();
  out.joint_edge.clear();
  out.joint_chord = std::move(joint_chord);
  if (next) {
    const auto& P = body.vertices();
    auto endVertex = [&](std::size_t q) { return fixed[q] ? id0[q] : id1[q]; };
    out.joint_vertex.resize(P.size());
    out.joint_edge.resize(ne);
    for (std::size_t q = 0; q < P.size(); ++q) out.joint_vertex[q] = endVertex(q);
    for (std::size_t q = P.size(); q < np; ++q)
      if (on_body[q].edge >= 0 && endVertex(q) >= 0)
        out.joint_edge[static_cast<std::size_t>(on_body[q].edge)].emplace_back(on_body[q].s, endVertex(q));
    for (std::size_t e = 0; e < ne; ++e)
      for (const Extra& x : extra[1][e])
        if (x.vid >= 0) out.joint_edge[e].emplace_back(x.r, x.vid);
  }
}

FanEveryCap::FanEveryCap() : before_(fan_every_cap) { fan_every_cap = true; }
FanEveryCap::~FanEveryCap() { fan_every_cap = before_; }
UnbalancedGrids::UnbalancedGrids() : before_(unbalanced_grids) { unbalanced_grids = true; }
UnbalancedGrids::~UnbalancedGrids() { unbalanced_grids = before_; }

void mergeJointSlivers(Cycle& cycle) {
  auto& T = cycle.triangles;
  // The slivers' edges in reverse, (s, r), each to the first other triangle that holds it.
  std::map<std::pair<int, int>, std::size_t> across;
  for (const auto& sl : cycle.joint_slivers) across.emplace(std::make_pair(sl[2], sl[1]), T.size());
  std::vector<char> sliver(T.size(), 0);
  for (const auto& sl : cycle.joint_slivers) sliver[static_cast<std::size_t>(sl[0])] = 1;
  for (std::size_t f = 0; f < T.size(); ++f) {
    if (sliver[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const auto it = across.find({T[f][k], T[f][(k + 1) % 3]});
      if (it != across.end() && it->second == T.size()) it->second = f;
    }
  }
  std::vector<char> taken(T.size(), 0);
  for (const auto& [index, r, s, x] : cycle.joint_slivers) {
    const std::size_t f = across[{s, r}];
    if (f == T.size() || taken[f]) continue;
    taken[f] = 1;
    std::array<int, 3> t = T[f];
    while (t[0] != s) std::rotate(t.begin(), t.begin() + 1, t.end());
    const int w = t[2];
    T[f] = {{s, x, w}};
    T[static_cast<std::size_t>(index)] = {{x, r, w}};
  }
  cycle.joint_slivers.clear();
}

void cancelOpposite(Cycle& cycle) {
  // Per triangle: its set of three vertices (sorted), its position, and +1 in one orientation
  // (the rotations of (a, b, c) with a < b < c) or -1 in the other; sorted by set, then
  // position (a sort, not a hash map: a smooth polySAM has a million cycle triangles).
  struct Entry {
    std::array<int, 3> v;
    int index, sign;
  };
  std::vector<Entry> entries(cycle.triangles.size());
  for (std::size_t f = 0; f < cycle.triangles.size(); ++f) {
    std::array<int, 3> t = cycle.triangles[f];
    // (rotate the smallest vertex first; then the order of the other two is the orientation)
    while (t[0] > t[1] || t[0] > t[2]) std::rotate(t.begin(), t.begin() + 1, t.end());
    const int sign = t[1] < t[2] ? 1 : -1;
    if (t[1] > t[2]) std::swap(t[1], t[2]);
    entries[f] = {t, static_cast<int>(f), sign};
  }
  std::sort(entries.begin(), entries.end(),
            [](const Entry& x, const Entry& y) { return x.v != y.v ? x.v < y.v : x.index < y.index; });
  // Of each set, keep the first |net| triangles of the orientation that remains, in order.
  std::vector<char> keep(cycle.triangles.size(), 0);
  for (std::size_t a = 0, b = 0; a < entries.size(); a = b) {
    int net = 0;
    for (b = a; b < entries.size() && entries[b].v == entries[a].v; ++b) net += entries[b].sign;
    for (std::size_t k = a; k < b && net != 0; ++k)
      if (entries[k].sign * net > 0) keep[static_cast<std::size_t>(entries[k].index)] = 1, net -= entries[k].sign;
  }
  std::size_t kept = 0;
  for (std::size_t f = 0; f < cycle.triangles.size(); ++f)
    if (keep[f]) cycle.triangles[kept++] = cycle.triangles[f];
  cycle.triangles.resize(kept);
}

}  // namespace steady::sweep::detail
