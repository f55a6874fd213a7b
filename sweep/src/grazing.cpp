// The grazing set of a body on one span (see grazing.hpp for the method).
#include <steady/sweep/grazing.hpp>

#include <steady/core/error.hpp>

#include <Eigen/Geometry>  // cross products

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace steady::sweep {

namespace {

using Vec = Eigen::Vector3d;

int sgn(double x) { return (x > 0) - (x < 0); }

// Edge-parameter distance below which the zeros of the two faces of an edge are one point.
constexpr double kMergeParameter = 1e-12;

}  // namespace

const char* to_string(FaceClass c) noexcept {
  switch (c) {
    case FaceClass::Front: return "front";
    case FaceClass::Back: return "back";
    case FaceClass::Grazing: return "grazing";
    case FaceClass::Split: return "split";
  }
  return "?";
}

const char* to_string(SegmentKind k) noexcept {
  switch (k) {
    case SegmentKind::Face: return "face";
    case SegmentKind::Silhouette: return "silhouette";
    case SegmentKind::GrazingBoundary: return "grazing-boundary";
  }
  return "?";
}

GrazingSet grazingSet(const Body& body, const Span3& span, const GrazingOptions& options) {
  if (!(std::isfinite(options.tolerance) && options.tolerance >= 0))
    throw Error(ErrorCode::InvalidArgument, "GrazingOptions::tolerance must be finite and >= 0, got " +
                                                std::to_string(options.tolerance));
  if (!(std::isfinite(options.stationary_tolerance) && options.stationary_tolerance >= 0))
    throw Error(ErrorCode::InvalidArgument, "GrazingOptions::stationary_tolerance must be finite and >= 0, got " +
                                                std::to_string(options.stationary_tolerance));
  const auto& P = body.vertices();
  const auto& F = body.faces();
  const auto& E = body.edges();
  const auto& FE = body.faceEdges();
  const std::size_t nv = P.size(), nf = F.size(), ne = E.size();
  const Affine3& B = span.start();
  const Eigen::Matrix3d& M = span.log().M;
  const Vec& u = span.log().u;

  // 1. Pose at span time 0 and the velocity of every vertex.
  std::vector<Vec> W(nv), vel(nv);
  double speed = 0.0, magnitude = 0.0;
  Vec lo = Vec::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  const double normM = M.norm(), normU = u.norm();
  for (std::size_t i = 0; i < nv; ++i) {
    W[i] = B(P[i]);
    vel[i] = M * W[i] + u;
    speed = std::max(speed, vel[i].norm());
    magnitude = std::max(magnitude, normM * W[i].norm() + normU);
    lo = lo.cwiseMin(W[i]);
    hi = hi.cwiseMax(W[i]);
  }
  if (!std::isfinite(speed) || !std::isfinite(magnitude))
    throw Error(ErrorCode::NonFinite, "grazingSet: the posed body or its velocities are not finite "
                                      "(the span's start pose or log overflows on this body); "
                                      "rescale the scene");
  const double rounding = 64.0 * std::numeric_limits<double>::epsilon() * magnitude;

  GrazingSet out;
  out.speed = speed;
  out.eps_g = options.tolerance * speed + rounding;
  out.faces.assign(nf, FaceClass::Grazing);
  if (speed <= std::max(rounding, options.stationary_tolerance * (hi - lo).norm())) {
    out.stationary = true;
    return out;
  }
  const double eps = out.eps_g;

  // 2. Unit world normals at time 0, corner values of g_f (snapped), face classes.
  std::vector<Vec> n(nf);
  std::vector<std::array<double, 3>> g(nf);
  std::vector<std::array<int, 3>> s(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const Vec &a = W[F[f][0]], &b = W[F[f][1]], &c = W[F[f][2]];
    n[f] = (b - a).cross(c - a).normalized();
    int pos = 0, neg = 0;
    for (int k = 0; k < 3; ++k) {
      double x = n[f].dot(vel[F[f][k]]);
      if (std::abs(x) <= eps) x = 0.0;
      g[f][k] = x;
      s[f][k] = sgn(x);
      pos += s[f][k] > 0;
      neg += s[f][k] < 0;
    }
    out.faces[f] = pos && neg ? FaceClass::Split
                   : pos      ? FaceClass::Front
                   : neg      ? FaceClass::Back
                              : FaceClass::Grazing;
  }
  out.corner_values = g;
  auto corner = [&](int f, int v) {
    for (int k = 0; k < 3; ++k)
      if (F[f][k] == v) return k;
    return -1;
  };

  // Points, created on demand so that every segment meeting there shares the index.
  std::vector<int> vertex_point(nv, -1);
  auto vertexPoint = [&](int v) {
    if (vertex_point[v] < 0) {
      GrazingPoint q;
      q.body = P[v];
      q.world = W[v];
      q.vertex = v;
      vertex_point[v] = static_cast<int>(out.points.size());
      out.points.push_back(q);
    }
    return vertex_point[v];
  };
  auto edgePoint = [&](int e, double r) {
    const int a = E[e].vertices[0], b = E[e].vertices[1];
    GrazingPoint q;
    q.body = (1 - r) * P[a] + r * P[b];
    q.world = (1 - r) * W[a] + r * W[b];
    q.edge = e;
    q.parameter = r;
    out.points.push_back(q);
    return static_cast<int>(out.points.size()) - 1;
  };

  // 3. Edges: the zeros of each face's g along the edge, silhouette pieces, grazing boundaries.
  std::vector<std::array<int, 2>> root_point(ne, {{-1, -1}});  // zero of g_{faces[side]} on e
  for (std::size_t e = 0; e < ne; ++e) {
    const int a = E[e].vertices[0], b = E[e].vertices[1];
    const int ei = static_cast<int>(e);
    std::array<int, 2> sa{}, sb{}, interior{};
    std::array<double, 2> root{{-1, -1}};
    for (int i = 0; i < 2; ++i) {
      const int f = E[e].faces[i];
      const int ka = corner(f, a), kb = corner(f, b);
      sa[i] = s[f][ka];
      sb[i] = s[f][kb];
      if (sa[i] * sb[i] < 0) root[i] = g[f][ka] / (g[f][ka] - g[f][kb]);
      // Sign along the edge where g_f has no interior zero: the nonzero end, else (g_f = 0 on
      // the whole edge) the sign of the face's third corner, i.e. of the face next to the edge.
      interior[i] = sa[i] ? sa[i] : sb[i] ? sb[i] : s[f][3 - ka - kb];
    }
    // Breakpoints along the edge: its ends and the interior zeros (merged when they coincide).
    struct Break {
      double r;
      int point;
    };
    std::vector<Break> br;
    br.push_back({0.0, -1});
    if (root[0] >= 0 && root[1] >= 0 && std::abs(root[0] - root[1]) <= kMergeParameter) {
      const int q = edgePoint(ei, 0.5 * (root[0] + root[1]));
      root_point[e] = {{q, q}};
      br.push_back({out.points[q].parameter, q});
    } else {
      for (int i = 0; i < 2; ++i)
        if (root[i] >= 0) {
          root_point[e][i] = edgePoint(ei, root[i]);
          br.push_back({root[i], root_point[e][i]});
        }
      std::sort(br.begin() + 1, br.end(), [](const Break& x, const Break& y) { return x.r < y.r; });
    }
    br.push_back({1.0, -1});
    for (std::size_t j = 0; j + 1 < br.size(); ++j) {
      const double mid = 0.5 * (br[j].r + br[j + 1].r);
      int side[2];
      for (int i = 0; i < 2; ++i) side[i] = root[i] >= 0 ? (mid < root[i] ? sa[i] : sb[i]) : interior[i];
      if (side[0] * side[1] >= 0) continue;
      const int p = br[j].point >= 0 ? br[j].point : vertexPoint(a);
      const int q = br[j + 1].point >= 0 ? br[j + 1].point : vertexPoint(b);
      GrazingSegment seg;
      seg.kind = SegmentKind::Silhouette;
      seg.edge = ei;
      // faces[0] lies on the left of a -> b: run a -> b when it is the front face.
      seg.points = side[0] > 0 ? std::array<int, 2>{{p, q}} : std::array<int, 2>{{q, p}};
      out.segments.push_back(seg);
    }
    const bool g0 = out.faces[E[e].faces[0]] == FaceClass::Grazing;
    const bool g1 = out.faces[E[e].faces[1]] == FaceClass::Grazing;
    const bool bend = n[E[e].faces[0]].cross(n[E[e].faces[1]]).norm() > 1e-9 ||
                      n[E[e].faces[0]].dot(n[E[e].faces[1]]) < 0;
    if (g0 != g1 || (g0 && g1 && bend)) {
      GrazingSegment seg;
      seg.kind = SegmentKind::GrazingBoundary;
      seg.edge = ei;
      seg.face = g0 ? E[e].faces[0] : E[e].faces[1];
      // Along the grazing face's winding: faces[0] runs a -> b, faces[1] runs b -> a.
      seg.points = g0 ? std::array<int, 2>{{vertexPoint(a), vertexPoint(b)}}
                      : std::array<int, 2>{{vertexPoint(b), vertexPoint(a)}};
      out.segments.push_back(seg);
    }
  }

  // 4. Face segments: the zero chord of g_f in every split face.
  for (std::size_t f = 0; f < nf; ++f) {
    if (out.faces[f] != FaceClass::Split) continue;
    int pts[2], count = 0;
    int front = -1;
    for (int k = 0; k < 3; ++k) {
      if (s[f][k] > 0) front = k;
      if (s[f][k] == 0) pts[count++] = vertexPoint(F[f][k]);
      if (s[f][k] * s[f][(k + 1) % 3] < 0) {
        const int e = FE[f][k];
        pts[count++] = root_point[e][E[e].faces[0] == static_cast<int>(f) ? 0 : 1];
      }
    }
    // A split face has one + and one - corner: exactly two zeros on its boundary.
    if (count != 2 || pts[0] < 0 || pts[1] < 0)
      throw Error(ErrorCode::DegenerateInput, "grazingSet: internal inconsistency at face " + std::to_string(f) +
                                                  " (found " + std::to_string(count) + " zeros); please report");
    const Vec &x = out.points[pts[0]].world, &y = out.points[pts[1]].world;
    const Vec& front_corner = W[F[f][front]];
    GrazingSegment seg;
    seg.kind = SegmentKind::Face;
    seg.face = static_cast<int>(f);
    // Front corner on the left of x -> y seen from outside: (n x (y - x)) . (front - x) > 0.
    seg.points = n[f].cross(y - x).dot(front_corner - x) > 0 ? std::array<int, 2>{{pts[0], pts[1]}}
                                                              : std::array<int, 2>{{pts[1], pts[0]}};
    out.segments.push_back(seg);
  }

  // 5. Chain the segments at shared points. Chains start at points of odd degree (open ends)
  // first; what remains has even degree everywhere, so every walk closes.
  const std::size_t np = out.points.size(), ns = out.segments.size();
  std::vector<std::vector<int>> incident(np);
  for (std::size_t j = 0; j < ns; ++j)
    for (int q : out.segments[j].points) incident[q].push_back(static_cast<int>(j));
  for (const auto& inc : incident) out.generic = out.generic && inc.size() == 2;
  std::vector<char> used(ns, 0);
  std::vector<std::size_t> cursor(np, 0);
  auto nextUnused = [&](int q) {
    while (cursor[q] < incident[q].size() && used[incident[q][cursor[q]]]) ++cursor[q];
    return cursor[q] < incident[q].size() ? incident[q][cursor[q]] : -1;
  };
  auto walk = [&](int start) {
    GrazingLoop loop;
    loop.points.push_back(start);
    int at = start;
    for (int j = nextUnused(at); j >= 0; j = nextUnused(at)) {
      used[j] = 1;
      const auto& sp = out.segments[j].points;
      at = sp[0] == at ? sp[1] : sp[0];
      loop.segments.push_back(j);
      loop.points.push_back(at);
    }
    loop.closed = at == start;
    for (int q : loop.points) loop.polyline.push_back(out.points[q].body);
    out.loops.push_back(std::move(loop));
  };
  for (std::size_t q = 0; q < np; ++q)
    while (incident[q].size() % 2 == 1 && nextUnused(static_cast<int>(q)) >= 0) walk(static_cast<int>(q));
  for (std::size_t j = 0; j < ns; ++j)
    if (!used[j]) walk(out.segments[j].points[0]);
  return out;
}

}  // namespace steady::sweep
