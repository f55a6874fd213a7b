// Minimum distance between two meshes over a motion (see collide.hpp, Clearance): branch and
// bound over time. At the middle of a time interval the distance is computed exactly (closest
// triangle pairs through Embree point queries); over the interval no point moves farther than
// its path radius (the span bound of span_roots.hpp), so the distance anywhere in the interval
// is at least the middle distance minus the two meshes' largest path radii. The interval with
// the smallest such lower bound is halved until the bracket [lower, upper] is narrow enough.
#include <steady/collide/collide.hpp>

#include "internal.hpp"
#include "isolate.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <string>

namespace steady {

using namespace detail;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Whether segment [p, q] meets triangle (a, b, c); sets x to a common point.
bool segmentMeetsTriangle(const Vec& p, const Vec& q, const Vec& a, const Vec& b, const Vec& c, Vec& x) {
  const Vec n = (b - a).cross(c - a);
  const double dp = n.dot(p - a), dq = n.dot(q - a);
  if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0)) return false;
  if (dp == dq) return false;  // parallel to the plane: coplanar contacts show up as edge distances 0
  x = p + (dp / (dp - dq)) * (q - p);
  // Inside test by the signs of the sub-triangle normals along n.
  const double s0 = n.dot((b - a).cross(x - a)), s1 = n.dot((c - b).cross(x - b)), s2 = n.dot((a - c).cross(x - c));
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

// Distance of triangles A and B (0 when they meet) and a closest pair of points. For disjoint
// triangles the closest pair is a vertex against the other triangle or an edge against an edge.
double triangleDistance(const Vec* A, const Vec* B, Vec& pa, Vec& pb) {
  for (int i = 0; i < 3; ++i) {
    Vec x = Vec::Zero();
    if (segmentMeetsTriangle(A[i], A[(i + 1) % 3], B[0], B[1], B[2], x) ||
        segmentMeetsTriangle(B[i], B[(i + 1) % 3], A[0], A[1], A[2], x)) {
      pa = pb = x;
      return 0.0;
    }
  }
  double best = kInf;
  auto consider = [&](double d, const Vec& x, const Vec& y) {
    if (d < best) {
      best = d;
      pa = x;
      pb = y;
    }
  };
  for (int i = 0; i < 3; ++i) {
    const Vec qb = closestOnTriangle(A[i], B[0], B[1], B[2]);
    consider((A[i] - qb).norm(), A[i], qb);
    const Vec qa = closestOnTriangle(B[i], A[0], A[1], A[2]);
    consider((B[i] - qa).norm(), qa, B[i]);
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Vec x = Vec::Zero(), y = Vec::Zero();
      const double d = segmentDistance(A[i], A[(i + 1) % 3], B[j], B[(j + 1) % 3], x, y);
      consider(d, x, y);
    }
  return best;
}

// A mesh at one pose (world vertex positions) as an Embree user geometry.
struct Posed {
  const std::vector<Vec>* W;
  const Faces* F;
  static void bounds(const RTCBoundsFunctionArguments* args) {
    const auto* self = static_cast<const Posed*>(args->geometryUserPtr);
    const auto& f = (*self->F)[args->primID];
    const std::vector<Vec>& W = *self->W;
    storeBounds(args->bounds_o, W[f[0]].cwiseMin(W[f[1]]).cwiseMin(W[f[2]]), W[f[0]].cwiseMax(W[f[1]]).cwiseMax(W[f[2]]));
  }
};

// The nearest-triangle search of one triangle of mesh a against the BVH of mesh b.
struct Nearest {
  const std::vector<Vec>* WB;
  const Faces* FB;
  Vec A[3];
  Vec centroid;
  double rho = 0;  // largest distance from the centroid to the triangle
  double best = kInf;
  Vec pa, pb;
  int face_a = -1;

  // Every triangle of b within `best` of triangle A has a point within best + rho of the
  // centroid: the query radius, rounded up for the float query point and radius.
  float radius() const {
    if (!(best < kInf)) return std::numeric_limits<float>::infinity();
    const double r = best + rho;
    return std::nextafter(static_cast<float>(r + 1e-6 * (r + centroid.cwiseAbs().maxCoeff())),
                          std::numeric_limits<float>::infinity());
  }
  static bool visit(RTCPointQueryFunctionArguments* args) {
    auto* s = static_cast<Nearest*>(args->userPtr);
    const auto& g = (*s->FB)[args->primID];
    const Vec B[3] = {(*s->WB)[g[0]], (*s->WB)[g[1]], (*s->WB)[g[2]]};
    Vec x = Vec::Zero(), y = Vec::Zero();
    const double d = triangleDistance(s->A, B, x, y);
    if (d >= s->best) return false;
    s->best = d;
    s->pa = x;
    s->pb = y;
    args->query->radius = s->radius();
    return true;
  }
};

struct Distance {
  double d = kInf;
  Vec pa = Vec::Zero(), pb = Vec::Zero();
  int face_a = -1;  // the triangle of a that attains it
};

// Exact distance between mesh a (world positions WA) and mesh b (world positions WB, in the BVH
// scene_b). Triangle `first` of a is searched first so that a good bound prunes the others.
Distance meshDistance(const std::vector<Vec>& WA, const Faces& FA, RTCScene scene_b, const std::vector<Vec>& WB,
                      const Faces& FB, int first) {
  Nearest s;
  s.WB = &WB;
  s.FB = &FB;
  Distance out;
  const std::size_t n = FA.size();
  const std::size_t start = first >= 0 && static_cast<std::size_t>(first) < n ? static_cast<std::size_t>(first) : 0;
  for (std::size_t k = 0; k < n && out.d > 0; ++k) {
    const std::size_t f = (start + k) % n;
    for (int c = 0; c < 3; ++c) s.A[c] = WA[FA[f][c]];
    s.centroid = (s.A[0] + s.A[1] + s.A[2]) / 3.0;
    s.rho = std::max({(s.A[0] - s.centroid).norm(), (s.A[1] - s.centroid).norm(), (s.A[2] - s.centroid).norm()});
    s.best = out.d;
    RTCPointQuery q;
    q.x = static_cast<float>(s.centroid.x());
    q.y = static_cast<float>(s.centroid.y());
    q.z = static_cast<float>(s.centroid.z());
    q.time = 0.0f;
    q.radius = s.radius();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene_b, &q, &context, &Nearest::visit, &s);
    if (s.best < out.d) {
      out.d = s.best;
      out.pa = s.pa;
      out.pb = s.pb;
      out.face_a = static_cast<int>(f);
    }
  }
  return out;
}

// One side of the query: a mesh that moves along a motion, or stands still (motion null).
struct Side {
  const std::vector<Vec>& V;
  const Faces& F;
  const Motion3* motion;
  std::map<std::size_t, double> mu;  // spectral bound of each span's M, computed on demand

  double logNorm(std::size_t span) {
    auto it = mu.find(span);
    if (it == mu.end()) it = mu.emplace(span, spectralBound(motion->span(span).log().M)).first;
    return it->second;
  }

  // Places the mesh at the middle of motion times [t0, t1] (inside one span): returns its world
  // positions (W, or the mesh itself when it stands still) and sets reach to the largest distance
  // any of its points travels from there within [t0, t1].
  const std::vector<Vec>& place(double t0, double t1, std::vector<Vec>& W, double& reach) {
    reach = 0;
    if (!motion) return V;
    const std::size_t i = motion->spanIndex(0.5 * (t0 + t1));
    const double b = motion->spanBegin(i), len = motion->spanEnd(i) - b;
    const double s0 = (t0 - b) / len, s1 = (t1 - b) / len, r = 0.5 * (s1 - s0);
    const Span3& span = motion->span(i);
    const Affine3 P = span.pose(0.5 * (s0 + s1));
    const double grow = r * phi1(r * logNorm(i)) * kBoundSlack;
    W.resize(V.size());
    for (std::size_t v = 0; v < V.size(); ++v) {
      W[v] = P.applyPoint(V[v]);
      reach = std::max(reach, span.velocity(W[v]).norm() * grow + 1e-14 * (W[v].norm() + V[v].norm()));
    }
    return W;
  }
};

struct Leaf {
  double lower;  // no distance in [t0, t1] is below it
  double t0, t1;
  bool operator>(const Leaf& o) const { return lower > o.lower; }
};

// The search. `scene_b` is the BVH of a static b; a moving b gets a BVH per evaluation.
Clearance search(Side& a, Side& b, RTCScene static_b, double t0, double t1, const ClearanceOptions& o,
                 std::optional<double> contact_time) {
  if (!(o.relative_gap >= 0) || !(o.absolute_gap >= 0) || !std::isfinite(o.relative_gap) ||
      !std::isfinite(o.absolute_gap) || (o.relative_gap == 0 && o.absolute_gap == 0))
    throw Error(ErrorCode::InvalidArgument,
                "ClearanceOptions: relative_gap and absolute_gap must be finite, >= 0 and not both 0");
  if (o.max_evaluations < 1) throw Error(ErrorCode::InvalidArgument, "ClearanceOptions::max_evaluations must be >= 1");
  const double D = std::max(boxDiagonal(a.V), boxDiagonal(b.V));
  std::vector<Vec> WA, WB;
  Clearance out;
  out.upper = kInf;
  int hint = -1;

  // The exact distance at the middle of [s0, s1]; returns the interval's lower bound.
  auto evaluate = [&](double s0, double s1) {
    double reach_a, reach_b;
    const std::vector<Vec>& PA = a.place(s0, s1, WA, reach_a);
    const std::vector<Vec>& PB = b.place(s0, s1, WB, reach_b);
    const double reach = reach_a + reach_b;
    Distance d;
    if (static_b) {
      d = meshDistance(PA, a.F, static_b, PB, b.F, hint);
    } else {
      RTCScene scene = rtcNewScene(sharedDevice());
      rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
      Posed posed{&PB, &b.F};
      addUserGeometry(sharedDevice(), scene, static_cast<unsigned>(b.F.size()), &Posed::bounds, &posed);
      d = meshDistance(PA, a.F, scene, PB, b.F, hint);
      rtcReleaseScene(scene);
    }
    ++out.evaluations;
    hint = d.face_a;
    if (d.d < out.upper) {
      out.upper = d.d;
      out.t = 0.5 * (s0 + s1);
      out.point_a = d.pa;
      out.point_b = d.pb;
    }
    return d.d - reach;
  };

  if (contact_time) {  // they touch: the minimum is 0, attained within the contact tolerance
    evaluate(*contact_time, *contact_time);
    out.lower = 0.0;
    return out;
  }

  // The two ends (a minimum is often there), then every span of either motion in 8 pieces.
  evaluate(t0, t0);
  evaluate(t1, t1);
  std::vector<double> times{t0, t1};
  for (const Side* s : {&a, &b})
    if (s->motion)
      for (std::size_t i = 1; i < s->motion->spanCount(); ++i) {
        const double t = s->motion->spanBegin(i);
        if (t > t0 && t < t1) times.push_back(t);
      }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  std::priority_queue<Leaf, std::vector<Leaf>, std::greater<Leaf>> leaves;
  for (std::size_t j = 0; j + 1 < times.size(); ++j)
    for (int k = 0; k < 8; ++k) {
      const double s0 = times[j] + (times[j + 1] - times[j]) * k / 8, s1 = times[j] + (times[j + 1] - times[j]) * (k + 1) / 8;
      leaves.push({evaluate(s0, s1), s0, s1});
    }
  while (true) {
    const Leaf top = leaves.top();
    const double gap = std::max(o.absolute_gap * D, o.relative_gap * out.upper);
    // Halving stops at a width where the times no longer separate (then the bracket is final).
    const bool tiny = top.t1 - top.t0 <= 1e-15 * std::max(1.0, std::abs(top.t0));
    if (out.upper - top.lower <= gap || out.evaluations >= o.max_evaluations || tiny) {
      out.lower = std::clamp(top.lower, 0.0, out.upper);
      return out;
    }
    leaves.pop();
    const double m = 0.5 * (top.t0 + top.t1);
    leaves.push({evaluate(top.t0, m), top.t0, m});
    leaves.push({evaluate(m, top.t1), m, top.t1});
  }
}

}  // namespace

Clearance StaticScene::clearance(const std::vector<Vec>& vertices, const Faces& faces, const Motion3& motion,
                                 const ClearanceOptions& options) const {
  const auto contact = firstContact(vertices, faces, motion);  // also checks the mesh
  Side a{vertices, faces, &motion, {}};
  Side b{impl_->V, impl_->F, nullptr, {}};
  return search(a, b, impl_->scene, motion.beginTime(), motion.endTime(), options,
                contact ? std::optional<double>(contact->t) : std::nullopt);
}

Clearance clearance(const MovingMesh& a, const MovingMesh& b, const ClearanceOptions& options) {
  const auto contact = firstContact(a, b);  // also checks the meshes and the shared time
  Side sa{a.vertices, a.faces, &a.motion, {}};
  Side sb{b.vertices, b.faces, &b.motion, {}};
  const double t0 = std::max(a.motion.beginTime(), b.motion.beginTime());
  const double t1 = std::min(a.motion.endTime(), b.motion.endTime());
  return search(sa, sb, nullptr, t0, t1, options, contact ? std::optional<double>(contact->t) : std::nullopt);
}

}  // namespace steady
