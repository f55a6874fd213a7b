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
// At a joint the end cap of one span and the reversed start cap of the next are then the same
// faces wherever both spans move them outward, and cancel (cancelOpposite). The caps of Q for
// every span left a whole posed body at every joint instead, inside the swept volume but
// crossed by the strips around it: on the elephant along the bundled bi-arc motion (112 spans)
// 661k of the cycle's 998k triangles were caps, against 70k of 406k now.
//
// Construction. Corner values of g = n·v come from grazingSet() (snapped to 0 below eps_g);
// only their signs and the affine interpolation between them decide what is front. On every
// edge the zeros of its two faces' g (merged within 1e-12 in the edge parameter, as grazing.cpp
// does) split it into pieces; a piece is a boundary curve of Front when exactly one of its two
// faces is front there. Inside a split face the boundary is the chord where g vanishes. Every
// boundary segment is oriented with Front on its left (the front polygon's winding), swept
// into a strip (tessellation.hpp gives the time grid and the pieces), and every point where a
// strip meets a cap (its ends and subdivision points at τ = 0 and 1) is also a vertex of the
// cap polygons, which are cut exactly along the chords and fanned into triangles.
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
// A boundary segment whose positions at every grid row lie within this fraction of ε of the line
// through its τ = 0 ends sweeps no area (see "Strips that slide along themselves" below); the
// snap moves vertices by at most 1e-9 ε.
constexpr double kOnLine = 1e-9;

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
    const Eigen::Matrix4d E = (tau * X_).exp();
    return Affine3(E.topLeftCorner<3, 3>(), E.topRightCorner<3, 1>()) * start_;
  }

 private:
  Affine3 start_;
  Eigen::Matrix4d X_;
};

}  // namespace

void appendSpanCycle(Cycle& out, const Body& body, const Span3& span, const Affine3* end_given, double eps,
                     const GrazingOptions& grazing, int max_steps, int span_index) {
  const GrazingSet gs = grazingSet(body, span, grazing);
  const CleanPoses clean(span);
  // The span's end is its key pose, as the joints are (the next span's start): exp(log A) at
  // τ = 1 carries the log's rounding, and the body at the end is the one the caller posed. A
  // half turn about the z axis through a face of the body (the bracket along screw.json, 1e-17
  // of input noise on the axis) left the end cap 3e-17 off the start cap's plane: the exact
  // trimming kept the void sliver between them, and rounding made its walls cross.
  const Affine3 end_pose = end_given ? *end_given : span.relative() * span.start();
  if (!end_pose.isFinite())
    throw Error(ErrorCode::NonFinite, "sweptEnvelope: the end pose of span " + std::to_string(span_index) +
                                          " is not finite");
  // This span continues the previous one from the joint it left (Cycle::joint_vertex).
  const bool continues = !out.joint_vertex.empty();
  const auto& P = body.vertices();
  const auto& F = body.faces();
  const auto& E = body.edges();
  const auto& FE = body.faceEdges();
  const std::size_t nf = F.size(), ne = E.size();
  const Affine3 start = span.start();
  const Eigen::Matrix3d& M = span.log().M;
  const Vec& u = span.log().u;
  const std::string where = "sweptEnvelope: span " + std::to_string(span_index);

  // Body-coordinate points: the body's vertices, then points on edges and chords.
  std::vector<Vec> pt(P.begin(), P.end());
  std::vector<Where> on_body(P.size());
  auto addPoint = [&](const Vec& x, const Where& w) {
    pt.push_back(x);
    on_body.push_back(w);
    return static_cast<int>(pt.size()) - 1;
  };
  // Barycentric coordinates of point q (a vertex of face f, or a point on its edges or chord)
  // with respect to the corners of face f.
  auto barycentric = [&](int q, int f) {
    std::array<double, 3> l{{0, 0, 0}};
    // (a point made from others, such as a chord point from the chord's ends, takes theirs)
    std::function<void(int, double)> add = [&](int v, double weight) {
      for (int k = 0; k < 3; ++k)
        if (F[f][k] == v) {
          l[k] += weight;
          return;
        }
      const Where& w = on_body[v];
      if (w.a < 0) return;
      add(w.a, weight * (1.0 - w.s - w.t));
      add(w.b, weight * w.s);
      if (w.c >= 0) add(w.c, weight * w.t);
    };
    add(q, 1.0);
    return l;
  };

  // What of each face is front: all, nothing (Back and Grazing faces), or a part (Split).
  enum : char { kBack, kFront, kSplit };
  std::vector<char> part(nf, kBack);
  if (!gs.stationary)
    for (std::size_t f = 0; f < nf; ++f)
      part[f] = gs.faces[f] == FaceClass::Front ? kFront : gs.faces[f] == FaceClass::Split ? kSplit : kBack;
  auto g = [&](int f, int v) {
    for (int k = 0; k < 3; ++k)
      if (F[f][k] == v) return gs.corner_values[f][k];
    return 0.0;
  };
  // Is face f front at parameter r of its edge (a, b)? (Affine interpolation of snapped values.)
  auto frontAt = [&](int f, int a, int b, double r) {
    if (part[f] != kSplit) return part[f] == kFront;
    return (1 - r) * g(f, a) + r * g(f, b) > 0;
  };

  // 1. Edges: zeros of the split faces' g, then the boundary pieces.
  std::vector<std::vector<EdgePoint>> on_edge(ne);      // interior points, sorted by r
  std::vector<std::array<int, 2>> zero(ne, {{-1, -1}});  // zero point of faces[i]'s g on e
  std::vector<Segment> segs;
  for (std::size_t e = 0; e < ne; ++e) {
    const int a = E[e].vertices[0], b = E[e].vertices[1];
    std::array<double, 2> root{{-1, -1}};
    for (int i = 0; i < 2; ++i) {
      const int f = E[e].faces[i];
      if (part[f] != kSplit) continue;
      const double ga = g(f, a), gb = g(f, b);
      if (sgn(ga) * sgn(gb) < 0) root[i] = ga / (ga - gb);
    }
    for (int i = 0; i < 2; ++i) {
      if (root[i] < 0) continue;
      if (i == 1 && zero[e][0] >= 0 && std::abs(root[1] - root[0]) <= kMergeParameter) {
        zero[e][1] = zero[e][0];
        continue;
      }
      const int id = addPoint((1 - root[i]) * P[a] + root[i] * P[b], Where{a, b, -1, root[i], 0.0, static_cast<int>(e)});
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
      const bool f0 = frontAt(E[e].faces[0], a, b, mid), f1 = frontAt(E[e].faces[1], a, b, mid);
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
  auto zeroOn = [&](int f, int e) { return zero[e][E[e].faces[0] == f ? 0 : 1]; };

  // The polygon of face f on one side (sign +1: front, -1: back) through its corners and zeros,
  // in the face's winding, without the points that only subdivide sides (added later).
  auto sidePolygon = [&](int f, int sign) {
    std::vector<Corner> poly;
    for (int k = 0; k < 3; ++k) {
      const int v = F[f][k];
      const double gk = gs.corner_values[f][k], gn = gs.corner_values[f][(k + 1) % 3];
      if (sign * gk >= 0) poly.push_back({v, true, sgn(gk) == 0});
      if (sgn(gk) * sgn(gn) < 0) poly.push_back({zeroOn(f, FE[f][k]), true, true});
    }
    return poly;
  };

  // 2. Chords of split faces: from the front polygon's first zero to its second.
  std::vector<int> chord_segment(nf, -1);
  for (std::size_t f = 0; f < nf; ++f) {
    if (part[f] != kSplit) continue;
    const std::vector<Corner> poly = sidePolygon(static_cast<int>(f), +1);
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n; ++i)
      if (poly[i].zero && poly[(i + 1) % n].zero) {
        Segment s;
        s.p = poly[i].point;
        s.q = poly[(i + 1) % n].point;
        s.face = static_cast<int>(f);
        chord_segment[f] = static_cast<int>(segs.size());
        segs.push_back(s);
        break;
      }
  }

  // 3. Connected components of the boundary curves; one time grid each (condition (1)).
  const double mu = spectralBound(M);
  std::vector<int> parent(pt.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const Segment& s : segs) parent[findRoot(parent, s.p)] = findRoot(parent, s.q);
  std::vector<int> comp_of(pt.size(), -1), local(pt.size(), -1);
  std::vector<std::vector<int>> comp_points;
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
  auto poseAt = [&](double tau, bool first, bool last) {
    return first ? start : last ? end_pose : clean(tau);
  };
  struct Grid {
    std::vector<double> tau;
    std::vector<Affine3> pose;
    std::vector<std::vector<Vec>> world;  // [row][local point]
  };
  std::vector<Grid> grids(comp_points.size());
  for (std::size_t c = 0; c < comp_points.size(); ++c) {
    Grid& grid = grids[c];
    double tau = 0.0;
    for (bool first = true;; first = false) {
      const bool last = !first && tau >= 1.0;
      const Affine3 pose = poseAt(tau, first, last);
      std::vector<Vec> row;
      row.reserve(comp_points[c].size());
      double accel = 0.0;  // max |M v| over the points (tessellation.hpp)
      for (int q : comp_points[c]) {
        row.push_back(pose(pt[q]));
        accel = std::max(accel, (M * (M * row.back() + u)).norm());
      }
      grid.tau.push_back(tau);
      grid.pose.push_back(pose);
      grid.world.push_back(std::move(row));
      if (last) break;
      if (static_cast<int>(grid.tau.size()) > max_steps)
        throw Error(ErrorCode::InvalidArgument, where + ": more than " + std::to_string(max_steps) +
                                                    " time steps for tolerance " + std::to_string(eps) +
                                                    "; raise the tolerance (or max_steps)");
      tau = nextGridTime(tau, accel, mu, eps);
    }
  }

  // 4. Pieces per segment (condition (2)) and their subdivision points, which the caps share.
  std::vector<std::vector<int>> sub(segs.size());  // interior points from p to q
  for (std::size_t j = 0; j < segs.size(); ++j) {
    Segment& s = segs[j];
    const Grid& grid = grids[comp_of[s.p]];
    double twist = 0.0;
    for (std::size_t k = 0; k + 1 < grid.tau.size(); ++k) {
      const Vec e = grid.world[k][local[s.q]] - grid.world[k][local[s.p]];
      twist = std::max(twist, cellTwist(grid.tau[k + 1] - grid.tau[k], mu, (M * e).norm()));
    }
    const int m = piecesFor(twist, eps, max_steps, where + ", boundary segment " + std::to_string(j));
    for (int i = 1; i < m; ++i) {
      const double t = static_cast<double>(i) / m;
      const Vec x = (1 - t) * pt[s.p] + t * pt[s.q];
      Where w;
      const double r = s.rp + t * (s.rq - s.rp);
      if (s.edge >= 0) {
        w = Where{E[s.edge].vertices[0], E[s.edge].vertices[1], -1, r, 0.0, s.edge};
      } else {
        // On the chord of face s.face, exactly: on the segment between the chord's ends. (So
        // where a polySAM's spans meet in the same chord ends, their points on it lie on one
        // line, and coincide when the spans cut it alike, instead of lying a few ulps off each
        // other's chord.)
        w = Where{s.p, s.q, -1, t, 0.0, -1};
      }
      const int id = addPoint(x, w);
      sub[j].push_back(id);
      if (s.edge >= 0) on_edge[s.edge].push_back({r, id});
    }
  }
  for (auto& list : on_edge)
    std::sort(list.begin(), list.end(), [](const EdgePoint& x, const EdgePoint& y) { return x.r < y.r; });

  // Vertices of points at τ = 0 and τ = 1 (shared by caps and strips); fixed points keep one.
  const std::size_t np = pt.size();
  std::vector<int> id0(np, -1), id1(np, -1);
  std::vector<char> fixed(np, 0);
  for (std::size_t q = 0; q < np; ++q)
    fixed[q] = !gs.stationary && (M * start(pt[q]) + u).norm() <= kFixedSpeed * gs.speed;
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
  if (!out.joint_vertex.empty()) {
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
  // exact arrangement rounds into edges with four faces (or faces that cross). A segment is flat
  // when every row of its two ends lies within kOnLine ε of the line through its τ = 0 ends.
  // Flat segments that share points (a run of mesh edges along the axis) form a group, and the
  // whole group gets one line, through its two τ = 0 ends farthest apart, provided every row of
  // every end of the group lies within kOnLine ε of it: body vertices along the axis are rarely
  // exactly collinear (input noise of 1e-17), and a point shared by two segments placed on either
  // segment's own line would leave the other segment's strip a ribbon of slivers. All of the
  // group's vertices are then placed exactly on that line (ExactPosition on the two anchors): at
  // τ = 0 every point but the anchors (unless the previous span left it at the joint, or it was
  // already placed), at the interior rows, and at τ = 1, so that its triangles have no area and
  // drop out of the arrangement. A group that is not within reach of one line keeps one line per
  // segment (a point shared by two of them stays on the first). Vertices move by at most kOnLine ε.
  std::vector<std::array<int, 2>> line_of(np, {{-1, -1}});  // anchors (vertex ids) of the line
  auto onLine = [&](int q, const Vec& x) {
    const Vec& A = out.vertices[line_of[q][0]];
    const Vec d = out.vertices[line_of[q][1]] - A;
    return combination(line_of[q][0], line_of[q][1], -1, (x - A).dot(d) / d.squaredNorm(), 0.0);
  };
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
  // Places the points `pts` on the line through the τ = 0 vertices of points a and b.
  auto placeOnLine = [&](const std::vector<int>& pts, int a, int b) {
    const std::array<int, 2> anchors{{at0(a), at0(b)}};
    for (int q : pts)
      if (line_of[q][0] < 0) line_of[q] = anchors;
    for (int q : pts)
      if (q != a && q != b && id0[q] < 0 && line_of[q] == anchors) id0[q] = onLine(q, start(pt[q]));
    for (int q : pts)
      if (!fixed[q] && id1[q] < 0) id1[q] = onLine(q, end_pose(pt[q]));
  };
  {
    std::vector<int> flat_parent(np);
    std::iota(flat_parent.begin(), flat_parent.end(), 0);
    std::vector<char> flat(segs.size(), 0);
    for (std::size_t j = 0; j < segs.size(); ++j) {
      const Segment& s = segs[j];
      flat[j] = alongLine(grids[comp_of[s.p]], s.p, s.q, {s.p, s.q});
      if (flat[j]) flat_parent[findRoot(flat_parent, s.p)] = findRoot(flat_parent, s.q);
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
        std::vector<int> pts = ends;
        for (int j : group) pts.insert(pts.end(), sub[j].begin(), sub[j].end());
        placeOnLine(pts, a, b);
      } else {
        for (int j : group) {
          std::vector<int> pts{segs[j].p, segs[j].q};
          pts.insert(pts.end(), sub[j].begin(), sub[j].end());
          placeOnLine(pts, segs[j].p, segs[j].q);
        }
      }
    }
  }
  // A strip vertex at an interior row: on its line when it has one.
  auto rowVertex = [&](int q, const Vec& x) { return line_of[q][0] >= 0 ? onLine(q, x) : vertex(x); };

  // 5. Caps: Back (and Grazing) polygons at τ = 0 (reversed Front polygons when the span
  // continues a polySAM), Front polygons at τ = 1, with every point that lies on their sides,
  // fanned into triangles (`reversed`: against the polygon's winding).
  auto emitPolygon = [&](int f, std::vector<Corner> poly, bool at_end, bool reversed) {
    auto emit = [&](int a, int b, int c) {
      out.triangles.push_back(reversed ? std::array<int, 3>{{a, c, b}} : std::array<int, 3>{{a, b, c}});
      ++out.cap_triangles;
    };
    // Insert the points that subdivide the sides: along face edges, and along the chord.
    std::vector<Corner> full;
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Corner& x = poly[i];
      const Corner& y = poly[(i + 1) % n];
      full.push_back(x);
      if (x.zero && y.zero && part[f] == kSplit) {  // the chord
        const Segment& s = segs[chord_segment[f]];
        const auto& list = sub[chord_segment[f]];
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
        if (rx < ry) {
          for (const EdgePoint& ep : on_edge[e])
            if (ep.r > rx && ep.r < ry) full.push_back({ep.point, false, false});
        } else {
          for (auto it = on_edge[e].rbegin(); it != on_edge[e].rend(); ++it)
            if (it->r < rx && it->r > ry) full.push_back({it->point, false, false});
        }
        break;
      }
    }
    auto id = [&](int q) { return at_end ? at1(q) : at0(q); };
    const std::size_t m = full.size();
    const bool plain = std::all_of(full.begin(), full.end(), [](const Corner& c) { return c.true_corner; });
    if (m == 3) {
      emit(id(full[0].point), id(full[1].point), id(full[2].point));
      return;
    }
    if (plain && m == 4) {  // a convex quad: split along its shorter diagonal
      const double d02 = (pt[full[0].point] - pt[full[2].point]).squaredNorm();
      const double d13 = (pt[full[1].point] - pt[full[3].point]).squaredNorm();
      const int o = d02 <= d13 ? 0 : 1;
      const int a = id(full[o].point), b = id(full[o + 1].point), c = id(full[o + 2].point),
                d = id(full[(o + 3) % 4].point);
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
    const auto lA = barycentric(corners[0], f), lC = barycentric(corners[2], f);
    std::array<double, 3> l{};
    if (corners.size() >= 4) {
      for (int k = 0; k < 3; ++k) l[k] = 0.5 * (lA[k] + lC[k]);
    } else {
      const auto lB = barycentric(corners[1], f);
      for (int k = 0; k < 3; ++k) l[k] = 0.5 * (lA[k] + 0.5 * (lB[k] + lC[k]));
    }
    const int cv = combination(id(F[f][0]), id(F[f][1]), id(F[f][2]), l[1], l[2]);
    for (std::size_t i = 0; i < m; ++i) emit(cv, id(full[i].point), id(full[(i + 1) % m].point));
  };
  for (std::size_t f = 0; f < nf; ++f) {
    const int fi = static_cast<int>(f);
    if (part[f] == kSplit) {
      emitPolygon(fi, sidePolygon(fi, continues ? +1 : -1), false, continues);
      emitPolygon(fi, sidePolygon(fi, +1), true, false);
      continue;
    }
    const std::vector<Corner> whole{{F[f][0], true, false}, {F[f][1], true, false}, {F[f][2], true, false}};
    if (part[f] == kFront) {
      if (continues) emitPolygon(fi, whole, false, true);
      emitPolygon(fi, whole, true, false);
    } else if (!continues) {
      emitPolygon(fi, whole, false, false);
    }
  }

  // 6. Strips: vertices of the component points at the interior grid rows, then two triangles
  // per cell, oriented so that the strip's τ = 1 side runs against the Front polygon's.
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
  for (std::size_t j = 0; j < segs.size(); ++j) {
    const Segment& s = segs[j];
    const int c = comp_of[s.p];
    const Grid& grid = grids[c];
    const std::size_t K = grid.tau.size() - 1;
    const std::size_t m = sub[j].size() + 1;
    std::vector<int> prev, cur(m + 1);
    for (std::size_t k = 0; k <= K; ++k) {
      cur[0] = rows[c][k][local[s.p]];
      cur[m] = rows[c][k][local[s.q]];
      for (std::size_t i = 1; i < m; ++i) {
        const int q = sub[j][i - 1];
        cur[i] = k == 0 || fixed[q] ? at0(q) : k == K ? at1(q) : rowVertex(q, grid.pose[k](pt[q]));
      }
      if (k > 0)
        for (std::size_t i = 0; i < m; ++i) {
          const std::array<std::array<int, 3>, 2> cell{{{{prev[i], prev[i + 1], cur[i + 1]}},
                                                        {{prev[i], cur[i + 1], cur[i]}}}};
          for (const auto& t : cell) {
            if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;  // a fixed point's cell
            out.triangles.push_back(t);
            ++out.strip_triangles;
          }
        }
      prev = cur;
    }
  }

  // The joint for the next span (see Cycle::joint_vertex), or none.
  out.joint_vertex.clear();
  out.joint_edge.clear();
  if (end_given) {
    auto endVertex = [&](std::size_t q) { return fixed[q] ? id0[q] : id1[q]; };
    out.joint_vertex.resize(P.size());
    out.joint_edge.resize(ne);
    for (std::size_t q = 0; q < P.size(); ++q) out.joint_vertex[q] = endVertex(q);
    for (std::size_t q = P.size(); q < np; ++q)
      if (on_body[q].edge >= 0 && endVertex(q) >= 0)
        out.joint_edge[static_cast<std::size_t>(on_body[q].edge)].emplace_back(on_body[q].s, endVertex(q));
  }
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
