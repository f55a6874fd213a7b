// Mesh contact queries: Embree broad phase over swept slice boxes, exact feature solves on the
// candidate pairs (see collide.hpp).
#include <steady/collide/collide.hpp>

#include "internal.hpp"
#include "isolate.hpp"
#include "relative.hpp"

#include <embree3/rtcore.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <mutex>
#include <string>
#include <utility>

namespace steady {

using namespace detail;

// ---- shared internals (internal.hpp) -----------------------------------------------------------

namespace detail {

void checkMesh(const std::vector<Vec>& V, const Faces& F, const char* which) {
  const std::string w(which);
  if (V.empty() || F.empty())
    throw Error(ErrorCode::DegenerateInput, w + " mesh is empty (" + std::to_string(V.size()) + " vertices, " +
                                                std::to_string(F.size()) + " faces)");
  for (std::size_t i = 0; i < V.size(); ++i)
    if (!V[i].allFinite())
      throw Error(ErrorCode::NonFinite, w + " mesh: vertex " + std::to_string(i) + " is not finite");
  for (std::size_t f = 0; f < F.size(); ++f) {
    for (int k = 0; k < 3; ++k)
      if (F[f][k] < 0 || static_cast<std::size_t>(F[f][k]) >= V.size())
        throw Error(ErrorCode::InvalidArgument, w + " mesh: face " + std::to_string(f) + " refers to vertex " +
                                                    std::to_string(F[f][k]) + ", but there are " +
                                                    std::to_string(V.size()) + " vertices");
    const Vec n = (V[F[f][1]] - V[F[f][0]]).cross(V[F[f][2]] - V[F[f][0]]);
    const double scale = (V[F[f][1]] - V[F[f][0]]).squaredNorm() + (V[F[f][2]] - V[F[f][0]]).squaredNorm();
    if (!(n.norm() > 1e-14 * scale))
      throw Error(ErrorCode::DegenerateInput, w + " mesh: face " + std::to_string(f) +
                                                  " has zero area (collinear or repeated vertices); "
                                                  "remove it or repair the mesh");
  }
}

double boxDiagonal(const std::vector<Vec>& V) {
  Vec lo = V.front(), hi = V.front();
  for (const Vec& p : V) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

// Outward rounding of a double box to float.
namespace {
// One float step towards -infinity: std::nextafter(f, -inf) without the library call (which was
// a quarter of a first-contact query). +inf steps to the largest float; -inf and NaN stay.
float stepDown(float f) {
  if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
  if (!(std::abs(f) <= std::numeric_limits<float>::max())) return f > 0 ? std::numeric_limits<float>::max() : f;
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  u = f > 0 ? u - 1 : u + 1;
  std::memcpy(&f, &u, sizeof f);
  return f;
}
float stepUp(float f) { return -stepDown(-f); }
}  // namespace

void storeBounds(RTCBounds* b, const Vec& lo, const Vec& hi) {
  b->lower_x = stepDown(static_cast<float>(lo.x()));
  b->lower_y = stepDown(static_cast<float>(lo.y()));
  b->lower_z = stepDown(static_cast<float>(lo.z()));
  b->upper_x = stepUp(static_cast<float>(hi.x()));
  b->upper_y = stepUp(static_cast<float>(hi.y()));
  b->upper_z = stepUp(static_cast<float>(hi.z()));
}

// Mean over the faces of the largest side of each face's bounding box.
double meanFaceExtent(const std::vector<Vec>& V, const Faces& F) {
  double sum = 0;
  for (const auto& f : F) {
    const Vec lo = V[f[0]].cwiseMin(V[f[1]]).cwiseMin(V[f[2]]), hi = V[f[0]].cwiseMax(V[f[1]]).cwiseMax(V[f[2]]);
    sum += (hi - lo).maxCoeff();
  }
  return F.empty() ? 0.0 : sum / static_cast<double>(F.size());
}

// Closest point of triangle (a, b, c) to p (regions of the triangle's Voronoi diagram).
Vec closestOnTriangle(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
  const Vec ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Closest points of segments [p0, p1] and [q0, q1]; returns the distance.
double segmentDistance(const Vec& p0, const Vec& p1, const Vec& q0, const Vec& q1, Vec& cp, Vec& cq) {
  const Vec d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double c = d1.dot(r), b = d1.dot(d2), denom = a * e - b * b;
  double s = denom > 1e-300 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  cp = p0 + s * d1;
  cq = q0 + t * d2;
  return (cp - cq).norm();
}

void collectPairs(void* user, RTCCollision* collisions, unsigned n) {
  auto* sink = static_cast<PairSink*>(user);
  std::lock_guard<std::mutex> lock(sink->mutex);
  for (unsigned i = 0; i < n; ++i) sink->pairs.push_back({collisions[i].primID0, collisions[i].primID1});
}

RTCDevice newDevice() {
  RTCDevice d = rtcNewDevice(nullptr);
  if (!d) throw Error(ErrorCode::InvalidArgument, "Embree could not create a device (rtcNewDevice failed)");
  return d;
}

RTCDevice sharedDevice() {
  static const RTCDevice device = newDevice();
  return device;
}

// A user geometry of `count` primitives with the given bounds callback, committed into `scene`.
void addUserGeometry(RTCDevice device, RTCScene scene, unsigned count, RTCBoundsFunction fn, void* user) {
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(g, count);
  rtcSetGeometryUserData(g, user);
  rtcSetGeometryBoundsFunction(g, fn, user);
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
}

}  // namespace detail

const char* to_string(ContactType type) noexcept {
  switch (type) {
    case ContactType::VertexFace: return "vertex-face";
    case ContactType::FaceVertex: return "face-vertex";
    case ContactType::EdgeEdge: return "edge-edge";
  }
  return "unknown";
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// Sorts contact events by time (contactBefore: ties by features, then by every other field, so
// that the order, and which duplicate is kept, does not depend on the order they were found in)
// and drops duplicates of one event, the same feature pair found through adjacent triangles or
// on neighbouring intervals: events within 1e-9 relative in time, or with the same crossing sign
// and time brackets [t, t_latest] that meet (within that slack). The earliest is kept, its
// bracket widened to cover the duplicate's. (Brackets solved on different intervals differ:
// where rounding blurs the contact function over a band, as for nearly parallel edges, one solve
// may report the band's start and another a narrow bracket 2e-9 later inside the band; the
// window on t alone kept both, one crossing reported twice.)
void mergeEvents(std::vector<Contact>& out) {
  std::sort(out.begin(), out.end(), contactBefore);
  std::vector<Contact> merged;
  std::vector<double> reach;  // per kept event: the latest t_latest up to it
  for (const Contact& c : out) {
    const double slack = 1e-9 * (1 + std::abs(c.t));
    bool dup = false;
    for (std::size_t k = merged.size(); k-- > 0 && !dup;) {
      Contact& m = merged[k];
      if (c.t - m.t > slack && c.t > reach[k] + slack) break;  // (nothing up to k reaches c)
      if (m.type != c.type || m.a != c.a || m.b != c.b) continue;
      if (c.t - m.t <= slack || (m.crossing == c.crossing && c.t <= m.t_latest + slack)) {
        m.t_latest = std::max(m.t_latest, c.t_latest);
        for (std::size_t j = k; j < reach.size(); ++j) reach[j] = std::max(reach[j], m.t_latest);
        dup = true;
      }
    }
    if (dup) continue;
    merged.push_back(c);
    reach.push_back(std::max(reach.empty() ? -HUGE_VAL : reach.back(), c.t_latest));
  }
  out = std::move(merged);
}

// Whether point x (world) lies on triangle (p, q, r) within tol (sets the closest point). The
// root solve puts x on the plane up to rounding, about 1e-14 of the coordinates' magnitude; that
// much is added to tol.
bool onTriangle(const Vec& x, const Vec& p, const Vec& q, const Vec& r, double tol, Vec& cp) {
  cp = closestOnTriangle(x, p, q, r);
  const double slack = 1e-13 * (x.cwiseAbs().maxCoeff() + p.cwiseAbs().maxCoeff() + (q - p).norm() + (r - p).norm());
  return (x - cp).norm() <= tol + slack;
}

}  // namespace

// ---- one candidate pair -------------------------------------------------------------------------

namespace detail {

void solveTrianglePair(const SceneData& st, const PairSpan& ps, const MovingTriangle& m, std::size_t g, double a,
                       double hi, double tol, double margin, CollideStats& stats, std::vector<Contact>& out) {
    ++stats.pairs_solved;
    const auto& mf = m.v;
    const auto& sf = st.F[g];
    std::vector<ContactRoot> roots;
    auto make = [&](ContactType type, const ContactRoot& r) {
      Contact c;
      c.span = ps.span_index;
      c.span_time = r.lo;
      c.t = ps.t0 + r.lo * (ps.t1 - ps.t0);
      c.t_latest = ps.t0 + r.hi * (ps.t1 - ps.t0);
      c.type = type;
      c.crossing = r.crossing;
      c.certain = r.certain;
      return c;
    };
    // Feature culling. The broad phase placed this interval's vertices: over [a, b] moving vertex
    // v stays within rad[v] of mid[v], so a moving edge or face stays in the box of its vertices'
    // balls. Features whose boxes stay farther apart than the contact distance cannot meet.
    auto ballBox = [&](std::initializer_list<int> vs, Vec& box_lo, Vec& box_hi) {
      box_lo = Vec::Constant(std::numeric_limits<double>::infinity());
      box_hi = -box_lo;
      for (const int v : vs) {
        box_lo = box_lo.cwiseMin(m.mid[v] - Vec::Constant(m.rad[v]));
        box_hi = box_hi.cwiseMax(m.mid[v] + Vec::Constant(m.rad[v]));
      }
    };
    auto apart = [&](const Vec& alo, const Vec& ahi, const Vec& blo, const Vec& bhi) {
      return (alo.array() > bhi.array() + margin).any() || (blo.array() > ahi.array() + margin).any();
    };
    const Vec slo = st.V[sf[0]].cwiseMin(st.V[sf[1]]).cwiseMin(st.V[sf[2]]);
    const Vec shi = st.V[sf[0]].cwiseMax(st.V[sf[1]]).cwiseMax(st.V[sf[2]]);
    Vec mlo, mhi;
    ballBox({0, 1, 2}, mlo, mhi);
    // Finer culling by distances at the middle: a moving point stays within rad of its middle
    // position, so a feature that is farther than its largest rad (plus the contact distance and
    // a rounding margin of 1e-12 of the coordinates) from a static feature at the middle never
    // meets it; the roots it would give are rejected by the on-feature checks anyway.
    const double near = margin + 1e-12 * (mlo.cwiseAbs().cwiseMax(mhi.cwiseAbs()).maxCoeff() +
                                          slo.cwiseAbs().cwiseMax(shi.cwiseAbs()).maxCoeff());
    const double R = std::max({m.rad[0], m.rad[1], m.rad[2]});
    // Plane culling, cheaper than those distances and implied by them: the static face lies in
    // the slab [lo, hi] of its plane_range along its unit normal ns, and the moving triangle
    // over the interval within R of its middle triangle, whose own extent along the direction
    // nm (its normal as computed: any direction of length at most 1 + 1e-15 would do, as the
    // extent is measured, not assumed) is [mid_lo, mid_hi]. A point farther than r (plus near)
    // from a slab, along its direction, is farther than r from everything in it; so is a
    // segment whose two ends are, on the same side. Per moving vertex: its place outside the
    // static slab (above, below); per static vertex: outside the moving one.
    const Vec& ns = st.normal[g];
    const auto& range = st.plane_range[g];
    double above[3], below[3];
    for (int k = 0; k < 3; ++k) {
      const double d = ns.dot(m.mid[k]);
      above[k] = d - range[1];
      below[k] = range[0] - d;
    }
    const Vec nm = (m.mid[1] - m.mid[0]).cross(m.mid[2] - m.mid[0]).normalized();  // (0 when degenerate)
    const double p0 = nm.dot(m.mid[0]), p1 = nm.dot(m.mid[1]), p2 = nm.dot(m.mid[2]);
    const double mid_lo = std::min({p0, p1, p2}), mid_hi = std::max({p0, p1, p2});
    const double reach = R + near;  // (the moving triangle's reach over the interval, plus contact distance and rounding)
    double s_above[3], s_below[3];
    for (int k = 0; k < 3; ++k) {
      const double d = nm.dot(st.V[sf[k]]);
      s_above[k] = d - mid_hi;
      s_below[k] = mid_lo - d;
    }
    bool s_edge_off[3];  // per static edge j -> j + 1: both ends beyond the moving slab, on one side
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3;
      s_edge_off[j] = (s_above[j] > reach && s_above[j1] > reach) || (s_below[j] > reach && s_below[j1] > reach);
    }
    // Moving vertices against the static face's plane.
    for (int k = 0; k < 3; ++k) {
      if (above[k] > m.rad[k] + near || below[k] > m.rad[k] + near) continue;
      Vec vlo, vhi;
      ballBox({k}, vlo, vhi);
      if (apart(vlo, vhi, slo, shi)) continue;
      if ((m.mid[k] - closestOnTriangle(m.mid[k], st.V[sf[0]], st.V[sf[1]], st.V[sf[2]])).norm() > m.rad[k] + near)
        continue;
      roots.clear();
      ++stats.feature_solves;
      ps.fwd->pointPlane(m.W0[k], st.normal[g], st.offset[g], a, hi, roots);
      for (const ContactRoot& r : roots) {
        const Vec x = ps.fwd->power(r.t).applyPoint(m.W0[k]);
        Vec cp;
        if (!onTriangle(x, st.V[sf[0]], st.V[sf[1]], st.V[sf[2]], tol, cp) && r.certain) continue;
        Contact c = make(ContactType::VertexFace, r);
        c.a = {mf[k], -1};
        c.b = {static_cast<int>(g), -1};
        c.point = cp;
        c.normal = st.normal[g];
        out.push_back(c);
      }
    }
    // Static vertices against the moving face (in the frame of the span start, on the inverse span).
    const Vec n0 = (m.W0[1] - m.W0[0]).cross(m.W0[2] - m.W0[0]);
    const double h0 = n0.dot(m.W0[0]);
    for (int k = 0; k < 3; ++k) {
      if (s_above[k] > reach || s_below[k] > reach) continue;
      if (apart(st.V[sf[k]], st.V[sf[k]], mlo, mhi)) continue;
      if ((st.V[sf[k]] - closestOnTriangle(st.V[sf[k]], m.mid[0], m.mid[1], m.mid[2])).norm() > reach) continue;
      roots.clear();
      ++stats.feature_solves;
      ps.inv->pointPlane(st.V[sf[k]], n0, h0, a, hi, roots);
      for (const ContactRoot& r : roots) {
        const Affine3 Pt = ps.fwd->power(r.t);
        const Vec X0 = Pt.applyPoint(m.W0[0]), X1 = Pt.applyPoint(m.W0[1]), X2 = Pt.applyPoint(m.W0[2]);
        Vec cp;
        if (!onTriangle(st.V[sf[k]], X0, X1, X2, tol, cp) && r.certain) continue;
        Contact c = make(ContactType::FaceVertex, r);
        c.a = {m.face, -1};
        c.b = {sf[k], -1};
        c.point = st.V[sf[k]];
        c.normal = (X1 - X0).cross(X2 - X0).normalized();
        out.push_back(c);
      }
    }
    // Edges against edges. An edge shared by two faces is walked in opposite directions by them,
    // which flips the coplanarity function's sign: the normal and crossing reported are those of
    // both edges taken from their smaller vertex index to the larger, so that one feature pair
    // gets the same normal and crossing sign whichever triangles found it.
    for (int i = 0; i < 3; ++i) {
      const int i1 = (i + 1) % 3;
      const int ma = mf[i], mb = mf[i1];
      const double ri = std::max(m.rad[i], m.rad[i1]) + near;
      if ((above[i] > ri && above[i1] > ri) || (below[i] > ri && below[i1] > ri)) continue;
      Vec elo, ehi;
      ballBox({i, i1}, elo, ehi);
      for (int j = 0; j < 3; ++j) {
        const int j1 = (j + 1) % 3;
        const int sa = sf[j], sb = sf[j1];
        if (s_edge_off[j]) continue;
        if (apart(elo, ehi, st.V[sa].cwiseMin(st.V[sb]), st.V[sa].cwiseMax(st.V[sb]))) continue;
        Vec cp0, cq0;
        if (segmentDistance(m.mid[i], m.mid[i1], st.V[sa], st.V[sb], cp0, cq0) > ri)
          continue;
        roots.clear();
        ++stats.feature_solves;
        ps.fwd->edgeEdge(m.W0[i], m.W0[i1], st.V[sa], st.V[sb], a, hi, roots);
        for (const ContactRoot& r : roots) {
          const Affine3 Pt = ps.fwd->power(r.t);
          const Vec x0 = Pt.applyPoint(m.W0[i]), x1 = Pt.applyPoint(m.W0[i1]);
          Vec cp, cq;
          const double scale = x0.cwiseAbs().maxCoeff() + (x1 - x0).norm() + st.V[sa].cwiseAbs().maxCoeff() +
                               (st.V[sb] - st.V[sa]).norm();
          if (segmentDistance(x0, x1, st.V[sa], st.V[sb], cp, cq) > tol + 1e-13 * scale && r.certain) continue;
          Contact c = make(ContactType::EdgeEdge, r);
          c.a = {std::min(ma, mb), std::max(ma, mb)};
          c.b = {std::min(sa, sb), std::max(sa, sb)};
          c.point = 0.5 * (cp + cq);
          // Both edges taken from their smaller vertex index to the larger (see above).
          const bool flip = (ma > mb) != (sa > sb);
          const Vec n = (x1 - x0).cross(st.V[sb] - st.V[sa]);
          c.normal = n.norm() > 0 ? (flip ? -n : n).normalized() : Vec::Zero();
          if (flip) c.crossing = -c.crossing;
          out.push_back(c);
        }
      }
    }
}

}  // namespace detail

// ---- the static scene ---------------------------------------------------------------------------

StaticScene::StaticScene(std::vector<Vec> vertices, Faces faces) : impl_(std::make_unique<Impl>()) {
  checkMesh(vertices, faces, "the static");
  Impl& s = *impl_;
  s.V = std::move(vertices);
  s.F = std::move(faces);
  s.normal.resize(s.F.size());
  s.offset.resize(s.F.size());
  s.plane_range.resize(s.F.size());
  for (std::size_t f = 0; f < s.F.size(); ++f) {
    const Vec& a = s.V[s.F[f][0]];
    s.normal[f] = (s.V[s.F[f][1]] - a).cross(s.V[s.F[f][2]] - a).normalized();
    s.offset[f] = s.normal[f].dot(a);
    const double b1 = s.normal[f].dot(s.V[s.F[f][1]]), b2 = s.normal[f].dot(s.V[s.F[f][2]]);
    s.plane_range[f] = {std::min({s.offset[f], b1, b2}), std::max({s.offset[f], b1, b2})};
  }
  s.diag = boxDiagonal(s.V);
  s.mean_extent = meanFaceExtent(s.V, s.F);
  s.lo = s.hi = s.V.front();
  for (const Vec& p : s.V) {
    s.lo = s.lo.cwiseMin(p);
    s.hi = s.hi.cwiseMax(p);
  }
  s.device = newDevice();
  s.scene = rtcNewScene(s.device);
  rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_HIGH);
  addUserGeometry(s.device, s.scene, static_cast<unsigned>(s.F.size()), &SceneData::bounds, static_cast<SceneData*>(&s));
  buildStaticTree(s);
}

StaticScene::~StaticScene() = default;
StaticScene::StaticScene(StaticScene&&) noexcept = default;
StaticScene& StaticScene::operator=(StaticScene&&) noexcept = default;

std::size_t StaticScene::faceCount() const { return impl_->F.size(); }

// ---- one query ------------------------------------------------------------------------------------

namespace {

// Per-span data of the moving mesh.
struct SpanData {
  const Span3* span;
  double t0, t1;        // key times of the span
  SpanRoots fwd;        // the span, for moving vertices and edges
  SpanRoots inv;        // its inverse, for static vertices against moving faces
  std::vector<Vec> W0;  // moving vertices at span time 0 (world)
};

// Broad-phase state of one time interval: swept boxes of the moving triangles that may meet the
// static scene, as an Embree user geometry.
struct IntervalBoxes {
  std::vector<unsigned> faces;  // moving faces kept (their box meets the static scene's box)
  std::vector<float> box;       // 6 floats per kept face
  double path_sum = 0;          // sum over kept faces of their largest vertex path radius
  static void bounds(const RTCBoundsFunctionArguments* args) {
    const auto* self = static_cast<const IntervalBoxes*>(args->geometryUserPtr);
    const float* q = &self->box[6 * static_cast<std::size_t>(args->primID)];
    RTCBounds* b = args->bounds_o;
    b->lower_x = q[0], b->lower_y = q[1], b->lower_z = q[2], b->upper_x = q[3], b->upper_y = q[4], b->upper_z = q[5];
  }
};

// The span of A^-1, whose log must be exactly -[M | u] of the span's. The EAR log of A^-1 takes
// the default half-turn convention, which at an exact half turn turns the same way as the span
// itself (a mirrored trajectory); so build it under both conventions and keep the one whose
// log is -M. Elsewhere both agree.
Span3 inverseSpan(const Span3& sp) {
  const Affine3 inv = sp.relative().inverse();
  EarOptions cw;
  cw.half_turn = HalfTurn::Clockwise;
  Span3 a(inv), b(inv, cw);
  return (a.log().M + sp.log().M).norm() <= (b.log().M + sp.log().M).norm() ? a : b;
}

}  // namespace

namespace detail {
void mergeContactEvents(std::vector<Contact>& out) { mergeEvents(out); }
Span3 inverseOf(const Span3& sp) { return inverseSpan(sp); }
}  // namespace detail

namespace {

struct Query {
  const SceneData& st;
  const std::vector<Vec>& V;
  const Faces& F;
  const Motion3& motion;
  const CollideOptions& o;
  std::vector<SpanData> spans;
  double tol;  // contact distance
  CollideStats stats;
  std::vector<Vec> mid;      // per vertex: position at the middle of the current interval
  std::vector<double> rad;   // and its path-length radius
  std::vector<unsigned> placed;  // per vertex: the epoch in which mid/rad were last computed
  unsigned epoch = 0;
  double feature = 0;        // typical triangle size of the two meshes (larger mean box side)
  double body_diag = 0;      // bounding-box diagonal of the moving mesh
  Vec body_lo, body_hi;      // bounding box of the moving mesh (body coordinates)

  RTCScene moving_scene = nullptr;        // the moving boxes of the current interval
  RTCGeometry moving_geometry = nullptr;  // (created on first use, reused by every interval)

  Query(const Query&) = delete;
  Query& operator=(const Query&) = delete;
  ~Query() {
    if (moving_geometry) rtcReleaseGeometry(moving_geometry);
    if (moving_scene) rtcReleaseScene(moving_scene);
  }

  Query(const SceneData& s, const std::vector<Vec>& verts, const Faces& faces, const Motion3& m,
        const CollideOptions& opt)
      : st(s), V(verts), F(faces), motion(m), o(opt) {
    if (o.slices < 1 || o.slices > 128)
      throw Error(ErrorCode::InvalidArgument, "CollideOptions::slices must be in 1..128, got " + std::to_string(o.slices));
    if (!(o.contact_tolerance >= 0) || !std::isfinite(o.contact_tolerance))
      throw Error(ErrorCode::InvalidArgument, "CollideOptions::contact_tolerance must be finite and >= 0");
    checkMesh(V, F, "the moving");
    tol = o.contact_tolerance * std::max(st.diag, boxDiagonal(V));
    const std::size_t nv = V.size();
    spans.reserve(motion.spanCount());
    for (std::size_t i = 0; i < motion.spanCount(); ++i) {
      const Span3& sp = motion.span(i);
      SpanData d{&sp, motion.spanBegin(i), motion.spanEnd(i), SpanRoots(sp, o.roots),
                 SpanRoots(inverseSpan(sp), o.roots), {}};
      d.W0.resize(nv);
      for (std::size_t v = 0; v < nv; ++v) d.W0[v] = sp.start().applyPoint(V[v]);
      spans.push_back(std::move(d));
    }
    mid.resize(nv);
    rad.resize(nv);
    placed.assign(nv, 0);
    body_lo = body_hi = V.front();
    for (const Vec& p : V) {
      body_lo = body_lo.cwiseMin(p);
      body_hi = body_hi.cwiseMax(p);
    }
    feature = std::max(st.mean_extent, meanFaceExtent(V, F));
    body_diag = (body_hi - body_lo).norm();
  }

  // Whether the whole moving mesh may meet the static scene's box over span time [a, b]. The
  // mesh lies in its body box; at the middle pose the box is a parallelepiped spanned by the
  // images of its corners, and every point of it moves at most its path radius, which (the
  // speed |v| being convex in the position) is largest at a corner.
  bool mayReachScene(const SpanData& d, double a, double b) const {
    const IntervalFrame fr = frame(d, a, b);
    Vec lo = Vec::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    double reach = 0;
    for (int k = 0; k < 8; ++k) {
      const Vec c((k & 1) ? body_hi.x() : body_lo.x(), (k & 2) ? body_hi.y() : body_lo.y(),
                  (k & 4) ? body_hi.z() : body_lo.z());
      const Vec x0 = d.span->start().applyPoint(c), x = fr.P.applyPoint(x0);
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
      reach = std::max(reach, d.span->velocity(x).norm() * fr.grow + 1e3 * positionSlack(x, x0));
    }
    return !((lo.array() - reach > st.hi.array()).any() || (hi.array() + reach < st.lo.array()).any());
  }

  // Rounding margin of a vertex position computed from its span-start position.
  static double positionSlack(const Vec& x, const Vec& x0) { return 1e-14 * (x.norm() + x0.norm()); }

  // Swept box of moving face f over an interval, from its vertices' middle positions and path
  // radii (mid, rad), rounded outward to float as Embree sees it, unless the box misses the
  // static scene's box (then false: the face cannot meet the scene). `path` is the face's
  // largest vertex path radius. (Always inlined: GCC 12 stopped inlining it into sweptBoxes and
  // subsetBoxes when interval() grew by the sorting of its pairs, which made plain first
  // contacts of armadillo and bunny00 5-10% slower.)
  [[gnu::always_inline]] bool faceBox(std::size_t f, RTCBounds& bb, double& path) const {
    Vec lo = Vec::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    path = 0;
    for (int c = 0; c < 3; ++c) {
      const int vi = F[f][c];
      lo = lo.cwiseMin(mid[vi] - Vec::Constant(rad[vi]));
      hi = hi.cwiseMax(mid[vi] + Vec::Constant(rad[vi]));
      path = std::max(path, rad[vi]);
    }
    if ((lo.array() > st.hi.array()).any() || (hi.array() < st.lo.array()).any()) return false;
    storeBounds(&bb, lo, hi);
    return true;
  }

  // The middle pose of span time [a, b] and the factor that turns a speed at the middle into a
  // conservative path radius over [a, b].
  struct IntervalFrame {
    Affine3 P;
    double grow;
  };
  IntervalFrame frame(const SpanData& d, double a, double b) const {
    const double r = 0.5 * (b - a);
    return {d.fwd.power(0.5 * (a + b)), r * detail::phi1(r * d.fwd.logNorm()) * detail::kBoundSlack};
  }
  void placeVertex(const SpanData& d, const IntervalFrame& fr, std::size_t v) {
    mid[v] = fr.P.applyPoint(d.W0[v]);
    // Path-length bound plus a rounding margin for the position itself.
    rad[v] = d.span->velocity(mid[v]).norm() * fr.grow + positionSlack(mid[v], d.W0[v]);
  }

  // Places the vertices of face f not yet placed in the current epoch.
  void placeFace(const SpanData& d, const IntervalFrame& fr, unsigned f) {
    for (int c = 0; c < 3; ++c) {
      const auto vi = static_cast<std::size_t>(F[f][c]);
      if (placed[vi] != epoch) {
        placeVertex(d, fr, vi);
        placed[vi] = epoch;
      }
    }
  }

  static void pushBox(IntervalBoxes& out, unsigned f, const RTCBounds& bb, double path) {
    out.path_sum += path;
    out.faces.push_back(f);
    out.box.insert(out.box.end(), {bb.lower_x, bb.lower_y, bb.lower_z, bb.upper_x, bb.upper_y, bb.upper_z});
  }

  // Swept boxes of the moving faces over span time [a, b] of span d, keeping the faces whose box
  // meets the static scene's bounding box.
  void sweptBoxes(const SpanData& d, double a, double b, IntervalBoxes& out) {
    const IntervalFrame fr = frame(d, a, b);
    for (std::size_t v = 0; v < V.size(); ++v) placeVertex(d, fr, v);
    for (std::size_t f = 0; f < F.size(); ++f) {
      RTCBounds bb;
      double path;
      if (faceBox(f, bb, path)) pushBox(out, static_cast<unsigned>(f), bb, path);
    }
  }

  // Swept boxes over span time [a, b] of the faces a parent interval kept: the true sweep over
  // [a, b] lies inside the parent's conservative box, so a face the parent dropped stays out.
  void subsetBoxes(const SpanData& d, double a, double b, const std::vector<unsigned>& faces, IntervalBoxes& out) {
    const IntervalFrame fr = frame(d, a, b);
    ++epoch;
    for (const unsigned f : faces) {
      placeFace(d, fr, f);
      RTCBounds bb;
      double path;
      if (faceBox(f, bb, path)) pushBox(out, f, bb, path);
    }
  }

  // The candidate pairs of a half [a, b] of a halved interval, from its parent's. The true sweep
  // of a face over the half lies inside the parent's conservative box, so only the parent's
  // pairs can meet; each is kept when the half's own (tighter) box of the moving face still
  // overlaps the static triangle's box. No Embree query: this touches only the parent's pairs.
  std::vector<PairHit> refinePairs(const SpanData& d, double a, double b, const IntervalBoxes& parent,
                                   const std::vector<PairHit>& parent_pairs, IntervalBoxes& out) {
    const auto start = Clock::now();
    const IntervalFrame fr = frame(d, a, b);
    ++epoch;
    std::vector<int> slot(parent.faces.size(), -1);  // parent index -> index into out, or -2: culled
    std::vector<PairHit> pairs;
    for (const PairHit& p : parent_pairs) {
      int& k = slot[p.moving];
      if (k == -1) {
        const unsigned f = parent.faces[p.moving];
        placeFace(d, fr, f);
        RTCBounds bb;
        double path;
        if (!faceBox(f, bb, path)) {
          k = -2;
        } else {
          k = static_cast<int>(out.faces.size());
          pushBox(out, f, bb, path);
        }
      }
      if (k < 0) continue;
      const auto& g = st.F[p.fixed];
      const Vec lo = st.V[g[0]].cwiseMin(st.V[g[1]]).cwiseMin(st.V[g[2]]);
      const Vec hi = st.V[g[0]].cwiseMax(st.V[g[1]]).cwiseMax(st.V[g[2]]);
      RTCBounds sb;
      storeBounds(&sb, lo, hi);  // the static box exactly as the scene's BVH has it
      const float* q = &out.box[6 * static_cast<std::size_t>(k)];
      if (q[0] <= sb.upper_x && q[1] <= sb.upper_y && q[2] <= sb.upper_z && sb.lower_x <= q[3] &&
          sb.lower_y <= q[4] && sb.lower_z <= q[5])
        pairs.push_back({static_cast<unsigned>(k), p.fixed});
    }
    stats.candidate_pairs += pairs.size();
    stats.broad_seconds += seconds(start, Clock::now());
    return pairs;
  }

  // Candidate pairs (index into out.faces, static face) of the interval.
  std::vector<PairHit> collide(IntervalBoxes& boxes) {
    const auto start = Clock::now();
    PairSink sink;
    if (!boxes.faces.empty()) {
      // One scene and geometry per query, rebuilt for each interval: Embree keeps the scene's
      // memory between commits (a new scene per interval cost page faults on every build).
      if (!moving_scene) {
        moving_scene = rtcNewScene(st.device);
        rtcSetSceneBuildQuality(moving_scene, RTC_BUILD_QUALITY_LOW);
        moving_geometry = rtcNewGeometry(st.device, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryBoundsFunction(moving_geometry, &IntervalBoxes::bounds, nullptr);
        rtcAttachGeometry(moving_scene, moving_geometry);
      }
      rtcSetGeometryUserPrimitiveCount(moving_geometry, static_cast<unsigned>(boxes.faces.size()));
      rtcSetGeometryUserData(moving_geometry, &boxes);
      rtcCommitGeometry(moving_geometry);
      rtcCommitScene(moving_scene);
      rtcCollide(moving_scene, st.scene, &collectPairs, &sink);
    }
    stats.candidate_pairs += sink.pairs.size();
    stats.broad_seconds += seconds(start, Clock::now());
    return std::move(sink.pairs);
  }

  double globalTime(const SpanData& d, double s) const { return d.t0 + s * (d.t1 - d.t0); }

  // Solves one candidate pair on [a, b] of span d; calls emit(contact) for every feature contact
  // found with span time <= limit.
  template <class Emit>
  void solvePair(std::size_t span_index, const SpanData& d, double a, double b, std::size_t f, std::size_t g,
                 double limit, Emit&& emit) {
    const double hi = std::min(b, limit);
    if (hi < a) {
      ++stats.pairs_solved;
      return;
    }
    MovingTriangle m;
    m.face = static_cast<int>(f);
    m.v = F[f];
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(F[f][k]);
      m.W0[k] = d.W0[v];
      m.mid[k] = mid[v];
      m.rad[k] = rad[v];
    }
    found.clear();
    const PairSpan ps{span_index, d.t0, d.t1, &d.fwd, &d.inv};
    solveTrianglePair(st, ps, m, g, a, hi, tol, tol + 1e-12 * (st.diag + body_diag), stats, found);
    for (const Contact& c : found) emit(c);
  }
  std::vector<Contact> found;  // scratch of solvePair

  enum class Mode { First, All, Any };

  struct Search {
    Mode mode;
    std::optional<Contact> best;
    std::vector<Contact> out;
    bool done = false;
  };

  // Halving of an interval stops at this depth below the options' slices (2^10 more).
  static constexpr int kMaxDepth = 10;
  // An interval is halved when its candidate pairs exceed this many per kept moving face (and
  // its boxes are still partly path, see kPathFloor): halving shrinks them.
  static constexpr double kSplitRatio = 4.0;
  // An interval is halved before its Embree query while the faces' mean path diameter exceeds
  // this many typical triangle sizes.
  static constexpr double kPathRatio = 2.0;
  // ... and after it (too many pairs) only while the path is at least this many triangle sizes:
  // below, the boxes are mostly the triangles themselves and halving no longer thins the pairs.
  static constexpr double kPathFloor = 0.25;
  static double meanPathDiameter(const IntervalBoxes& b) {
    return b.faces.empty() ? 0.0 : 2 * b.path_sum / static_cast<double>(b.faces.size());
  }

  // Processes span time [a, b] of span i in time order: the moving faces' swept boxes, then
  // either halves the interval or solves the candidate pairs. It halves before any Embree query
  // while the boxes are mostly path (the faces' mean path diameter above kPathRatio triangle
  // sizes: a query would return pairs by the hundred thousand), and after one when the query
  // returns more than kSplitRatio pairs per face. A half starts from its parent's faces, or from
  // its parent's pairs when the parent ran a query.
  void interval(std::size_t i, double a, double b, int depth, Search& S, const IntervalBoxes* parent = nullptr,
                const std::vector<PairHit>* parent_pairs = nullptr) {
    const SpanData& d = spans[i];
    if (S.done) return;
    if (S.mode != Mode::All && S.best && globalTime(d, a) > S.best->t) {
      S.done = true;
      return;
    }
    IntervalBoxes boxes;
    std::vector<PairHit> pairs;
    const double m = 0.5 * (a + b);
    if (parent_pairs) {
      pairs = refinePairs(d, a, b, *parent, *parent_pairs, boxes);
    } else {
      const auto t_start = Clock::now();
      if (parent) {
        subsetBoxes(d, a, b, parent->faces, boxes);
      } else if (mayReachScene(d, a, b)) {
        sweptBoxes(d, a, b, boxes);
      }
      stats.broad_seconds += seconds(t_start, Clock::now());
      if (boxes.faces.empty()) return;
      if (depth < kMaxDepth && meanPathDiameter(boxes) > kPathRatio * feature) {
        interval(i, a, m, depth + 1, S, &boxes);
        interval(i, m, b, depth + 1, S, &boxes);
        return;
      }
      pairs = collide(boxes);
    }
    if (pairs.empty()) return;
    if (depth < kMaxDepth && static_cast<double>(pairs.size()) > kSplitRatio * static_cast<double>(boxes.faces.size()) &&
        meanPathDiameter(boxes) > kPathFloor * feature) {
      stats.candidate_pairs -= pairs.size();  // superseded by the halves' pairs
      interval(i, a, m, depth + 1, S, &boxes, &pairs);
      interval(i, m, b, depth + 1, S, &boxes, &pairs);
      return;
    }
    // The pairs arrive in the order of Embree's threads (refinePairs keeps its parent's order):
    // put them in order of moving and static face before solving, since each solve shortens its
    // interval to the best contact found so far, so that the order decides the bits of the
    // answer. (Sorted here, not after each Embree query: most pairs of wide intervals are
    // refined away.)
    for (PairHit& p : pairs) p.moving = boxes.faces[p.moving];
    sortPairs(pairs);
    const auto n_start = Clock::now();
    for (const PairHit& p : pairs) {
      const double limit = S.mode != Mode::All && S.best && S.best->span == i ? S.best->span_time : b;
      solvePair(i, d, a, b, p.moving, p.fixed, limit, [&](const Contact& c) {
        if (S.mode == Mode::All) {
          S.out.push_back(c);
        } else if (!S.best || contactBefore(c, *S.best)) {
          S.best = c;
        }
      });
      if (S.mode == Mode::Any && S.best) {
        S.done = true;
        break;
      }
    }
    stats.narrow_seconds += seconds(n_start, Clock::now());
  }

  std::vector<Contact> run(Mode mode) {
    Search S{mode, std::nullopt, {}, false};
    for (std::size_t i = 0; i < spans.size() && !S.done; ++i)
      for (int k = 0; k < o.slices && !S.done; ++k)
        interval(i, static_cast<double>(k) / o.slices, static_cast<double>(k + 1) / o.slices, 0, S);
    if (mode != Mode::All) {
      if (S.best) S.out.push_back(*S.best);
    } else {
      mergeEvents(S.out);
    }
    return S.out;
  }
};

}  // namespace

// ---- two moving meshes -----------------------------------------------------------------------------

namespace {

// Positions of one moving mesh's vertices at the start of each of its spans (computed on demand).
struct MovingSide {
  const std::vector<Vec>& V;
  const Faces& F;
  const Motion3& motion;
  std::vector<std::vector<Vec>> start;  // per span
  std::vector<double> mu;               // spectral bound of each span's M
  MovingSide(const MovingMesh& m) : V(m.vertices), F(m.faces), motion(m.motion) {
    start.resize(motion.spanCount());
    mu.assign(motion.spanCount(), -1.0);
  }
  const std::vector<Vec>& at(std::size_t i) {
    if (start[i].empty()) {
      start[i].resize(V.size());
      for (std::size_t v = 0; v < V.size(); ++v) start[i][v] = motion.span(i).start().applyPoint(V[v]);
      mu[i] = detail::spectralBound(motion.span(i).log().M);
    }
    return start[i];
  }
};

// One interval of the merged key times on which a and b each follow one span.
struct TwoInterval {
  double ta, tb;
  std::size_t ia, ib;  // spans
  double sa0, da, sb0, db;  // span parameters sa = sa0 + da tau, sb = sb0 + db tau
};

struct TwoQuery {
  MovingSide A, B;
  const CollideOptions& o;
  int K;
  double tol;
  std::vector<TwoInterval> iv;
  std::vector<detail::RelativeRoots> ab, ba;  // per interval: a against b, b against a
  std::vector<float> boxA, boxB;               // 6 floats per primitive, slice-major
  CollideStats stats;

  TwoQuery(const MovingMesh& a, const MovingMesh& b, const CollideOptions& opt) : A(a), B(b), o(opt), K(opt.slices) {
    if (o.slices < 1 || o.slices > 128)
      throw Error(ErrorCode::InvalidArgument, "CollideOptions::slices must be in 1..128, got " + std::to_string(o.slices));
    if (!(o.contact_tolerance >= 0) || !std::isfinite(o.contact_tolerance))
      throw Error(ErrorCode::InvalidArgument, "CollideOptions::contact_tolerance must be finite and >= 0");
    checkMesh(A.V, A.F, "the first moving");
    checkMesh(B.V, B.F, "the second moving");
    tol = o.contact_tolerance * std::max(boxDiagonal(A.V), boxDiagonal(B.V));
    const double t0 = std::max(A.motion.beginTime(), B.motion.beginTime());
    const double t1 = std::min(A.motion.endTime(), B.motion.endTime());
    if (!(t1 > t0))
      throw Error(ErrorCode::InvalidArgument, "the two motions share no time: [" + std::to_string(A.motion.beginTime()) +
                                                  ", " + std::to_string(A.motion.endTime()) + "] and [" +
                                                  std::to_string(B.motion.beginTime()) + ", " +
                                                  std::to_string(B.motion.endTime()) + "]");
    std::vector<double> times{t0, t1};
    for (const Motion3* m : {&A.motion, &B.motion})
      for (std::size_t i = 0; i <= m->spanCount(); ++i) {
        const double t = i < m->spanCount() ? m->spanBegin(i) : m->endTime();
        if (t > t0 && t < t1) times.push_back(t);
      }
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    for (std::size_t j = 0; j + 1 < times.size(); ++j) {
      TwoInterval w;
      w.ta = times[j];
      w.tb = times[j + 1];
      const double mid = 0.5 * (w.ta + w.tb);
      w.ia = A.motion.spanIndex(mid);
      w.ib = B.motion.spanIndex(mid);
      const double la = A.motion.spanEnd(w.ia) - A.motion.spanBegin(w.ia);
      const double lb = B.motion.spanEnd(w.ib) - B.motion.spanBegin(w.ib);
      w.sa0 = (w.ta - A.motion.spanBegin(w.ia)) / la;
      w.da = (w.tb - w.ta) / la;
      w.sb0 = (w.ta - B.motion.spanBegin(w.ib)) / lb;
      w.db = (w.tb - w.ta) / lb;
      A.at(w.ia);
      B.at(w.ib);
      iv.push_back(w);
      ab.emplace_back(A.motion.span(w.ia), w.sa0, w.da, A.mu[w.ia], B.motion.span(w.ib), w.sb0, w.db, B.mu[w.ib], o.roots);
      ba.emplace_back(B.motion.span(w.ib), w.sb0, w.db, B.mu[w.ib], A.motion.span(w.ia), w.sa0, w.da, A.mu[w.ia], o.roots);
    }
    buildBoxes();
  }

  // Swept boxes of both meshes per (interval, slice), offset along x by slice so that boxes of
  // different slices never overlap (then rtcCollide only pairs boxes of the same slice).
  void buildBoxes() {
    const std::size_t slices = iv.size() * static_cast<std::size_t>(K);
    std::vector<double> lo[2], hi[2];
    double extent = 1.0;
    for (int side = 0; side < 2; ++side) {
      MovingSide& m = side == 0 ? A : B;
      const std::size_t nf = m.F.size(), nv = m.V.size();
      lo[side].assign(slices * nf * 3, 0.0);
      hi[side].assign(slices * nf * 3, 0.0);
      std::vector<Vec> mid(nv);
      std::vector<double> rad(nv);
      for (std::size_t j = 0; j < iv.size(); ++j) {
        const TwoInterval& w = iv[j];
        const std::size_t span = side == 0 ? w.ia : w.ib;
        const double s0 = side == 0 ? w.sa0 : w.sb0, d = side == 0 ? w.da : w.db;
        const Span3& sp = m.motion.span(span);
        const auto& W0 = m.start[span];
        const double r = 0.5 / K * d;  // half-slice, in span parameter
        const double grow = r * detail::phi1(r * m.mu[span]) * detail::kBoundSlack;
        for (int k = 0; k < K; ++k) {
          const Affine3 P = sp.power(s0 + d * (k + 0.5) / K);
          for (std::size_t v = 0; v < nv; ++v) {
            mid[v] = P.applyPoint(W0[v]);
            rad[v] = sp.velocity(mid[v]).norm() * grow + 1e-14 * (mid[v].norm() + W0[v].norm());
          }
          const std::size_t slice = j * static_cast<std::size_t>(K) + static_cast<std::size_t>(k);
          for (std::size_t f = 0; f < nf; ++f) {
            Vec l = Vec::Constant(std::numeric_limits<double>::infinity()), h = -l;
            for (int c = 0; c < 3; ++c) {
              const int vi = m.F[f][c];
              l = l.cwiseMin(mid[vi] - Vec::Constant(rad[vi]));
              h = h.cwiseMax(mid[vi] + Vec::Constant(rad[vi]));
            }
            for (int c = 0; c < 3; ++c) {
              lo[side][(slice * nf + f) * 3 + c] = l[c];
              hi[side][(slice * nf + f) * 3 + c] = h[c];
              extent = std::max({extent, std::abs(l[c]), std::abs(h[c])});
            }
          }
        }
      }
    }
    const double step = 2 * extent + 1;
    for (int side = 0; side < 2; ++side) {
      std::vector<float>& out = side == 0 ? boxA : boxB;
      const std::size_t n = lo[side].size() / 3, nf = (side == 0 ? A : B).F.size();
      out.resize(n * 6);
      for (std::size_t p = 0; p < n; ++p) {
        const double shift = static_cast<double>(p / nf) * step;
        RTCBounds b;
        storeBounds(&b, Vec(lo[side][3 * p] + shift, lo[side][3 * p + 1], lo[side][3 * p + 2]),
                    Vec(hi[side][3 * p] + shift, hi[side][3 * p + 1], hi[side][3 * p + 2]));
        float* q = &out[6 * p];
        q[0] = b.lower_x, q[1] = b.lower_y, q[2] = b.lower_z, q[3] = b.upper_x, q[4] = b.upper_y, q[5] = b.upper_z;
      }
    }
  }

  static void boxBounds(const RTCBoundsFunctionArguments* args) {
    const float* q = static_cast<const float*>(args->geometryUserPtr) + 6 * static_cast<std::size_t>(args->primID);
    RTCBounds* b = args->bounds_o;
    b->lower_x = q[0], b->lower_y = q[1], b->lower_z = q[2], b->upper_x = q[3], b->upper_y = q[4], b->upper_z = q[5];
  }

  std::vector<PairHit> broadPhase() {
    const auto start = Clock::now();
    const std::size_t na = boxA.size() / 6, nb = boxB.size() / 6;
    if (na > std::numeric_limits<unsigned>::max() || nb > std::numeric_limits<unsigned>::max())
      throw Error(ErrorCode::InvalidArgument, "too many primitives for one query (faces x intervals x slices > 2^32); "
                                              "lower CollideOptions::slices");
    RTCDevice device = sharedDevice();
    RTCScene sa = rtcNewScene(device), sb = rtcNewScene(device);
    PairSink sink;
    addUserGeometry(device, sa, static_cast<unsigned>(na), &TwoQuery::boxBounds, boxA.data());
    addUserGeometry(device, sb, static_cast<unsigned>(nb), &TwoQuery::boxBounds, boxB.data());
    rtcCollide(sa, sb, &collectPairs, &sink);
    rtcReleaseScene(sa);
    rtcReleaseScene(sb);
    // In time order (primitives are slice-major), and within a slice by moving and static face:
    // the solves below shorten their interval to the best contact found so far, so their order
    // decides the bits of the answer and must not be the order of Embree's threads.
    sortPairs(sink.pairs);
    stats.candidate_pairs = sink.pairs.size();
    stats.broad_seconds += seconds(start, Clock::now());
    return std::move(sink.pairs);
  }

  template <class Emit>
  void solvePair(std::size_t j, double lo, double hi, std::size_t f, std::size_t g, Emit&& emit) {
    ++stats.pairs_solved;
    const TwoInterval& w = iv[j];
    const auto& fa = A.F[f];
    const auto& fb = B.F[g];
    const auto& WA = A.start[w.ia];
    const auto& WB = B.start[w.ib];
    std::vector<ContactRoot> roots;
    auto make = [&](ContactType type, const ContactRoot& r) {
      Contact c;
      c.t = w.ta + r.lo * (w.tb - w.ta);
      c.t_latest = w.ta + r.hi * (w.tb - w.ta);
      c.span = w.ia;
      c.span_time = w.sa0 + w.da * r.lo;
      c.type = type;
      c.crossing = r.crossing;
      c.certain = r.certain;
      return c;
    };
    auto plane = [](const Vec& p, const Vec& q, const Vec& r, Vec& n) {
      n = (q - p).cross(r - p);
      return n.dot(p);
    };
    Vec n;
    // Vertices of a against the face of b, and vertices of b against the face of a.
    for (int side = 0; side < 2; ++side) {
      const auto& fv = side == 0 ? fa : fb;  // vertices from this face
      const auto& ff = side == 0 ? fb : fa;  // against this face
      const auto& Wv = side == 0 ? WA : WB;
      const auto& Wf = side == 0 ? WB : WA;
      const double h = plane(Wf[ff[0]], Wf[ff[1]], Wf[ff[2]], n);
      const detail::RelativeRoots& rel = side == 0 ? ab[j] : ba[j];
      for (int k = 0; k < 3; ++k) {
        roots.clear();
        ++stats.feature_solves;
        rel.pointPlane(Wv[fv[k]], n, h, lo, hi, roots);
        for (const ContactRoot& r : roots) {
          const Affine3 Pv = rel.poseA(r.t), Pf = rel.poseB(r.t);
          const Vec x = Pv.applyPoint(Wv[fv[k]]);
          Vec cp;
          if (!onTriangle(x, Pf.applyPoint(Wf[ff[0]]), Pf.applyPoint(Wf[ff[1]]), Pf.applyPoint(Wf[ff[2]]), tol, cp) && r.certain)
            continue;
          Contact c = make(side == 0 ? ContactType::VertexFace : ContactType::FaceVertex, r);
          c.a = side == 0 ? std::array<int, 2>{fv[k], -1} : std::array<int, 2>{static_cast<int>(f), -1};
          c.b = side == 0 ? std::array<int, 2>{static_cast<int>(g), -1} : std::array<int, 2>{fv[k], -1};
          c.point = cp;
          c.normal = (Pf.applyPoint(Wf[ff[1]]) - Pf.applyPoint(Wf[ff[0]]))
                         .cross(Pf.applyPoint(Wf[ff[2]]) - Pf.applyPoint(Wf[ff[0]]))
                         .normalized();
          emit(c);
        }
      }
    }
    for (int i = 0; i < 3; ++i) {
      const int a0 = fa[i], a1 = fa[(i + 1) % 3];
      for (int k = 0; k < 3; ++k) {
        const int b0 = fb[k], b1 = fb[(k + 1) % 3];
        roots.clear();
        ++stats.feature_solves;
        ab[j].edgeEdge(WA[a0], WA[a1], WB[b0], WB[b1], lo, hi, roots);
        for (const ContactRoot& r : roots) {
          const Affine3 PA = ab[j].poseA(r.t), PB = ab[j].poseB(r.t);
          const Vec x0 = PA.applyPoint(WA[a0]), x1 = PA.applyPoint(WA[a1]);
          const Vec y0 = PB.applyPoint(WB[b0]), y1 = PB.applyPoint(WB[b1]);
          Vec cp, cq;
          if (segmentDistance(x0, x1, y0, y1, cp, cq) > tol + 1e-13 * (x0.cwiseAbs().maxCoeff() + (x1 - x0).norm() + y0.cwiseAbs().maxCoeff() + (y1 - y0).norm()) && r.certain)
            continue;
          Contact c = make(ContactType::EdgeEdge, r);
          c.a = {std::min(a0, a1), std::max(a0, a1)};
          c.b = {std::min(b0, b1), std::max(b0, b1)};
          c.point = 0.5 * (cp + cq);
          // Both edges taken from their smaller vertex index to the larger (see solveTrianglePair).
          const bool flip = (a0 > a1) != (b0 > b1);
          const Vec nn = (x1 - x0).cross(y1 - y0);
          c.normal = nn.norm() > 0 ? (flip ? -nn : nn).normalized() : Vec::Zero();
          if (flip) c.crossing = -c.crossing;
          emit(c);
        }
      }
    }
  }

  std::vector<Contact> run(bool first_only) {
    std::vector<PairHit> pairs = broadPhase();
    const auto start = Clock::now();
    std::vector<Contact> out;
    std::optional<Contact> best;
    const std::size_t nf = A.F.size();
    for (const PairHit& p : pairs) {
      const std::size_t slice = p.moving / nf, f = p.moving % nf;
      const std::size_t j = slice / static_cast<std::size_t>(K), k = slice % static_cast<std::size_t>(K);
      const double lo = static_cast<double>(k) / K, hi = static_cast<double>(k + 1) / K;
      const double t_lo = iv[j].ta + lo * (iv[j].tb - iv[j].ta);
      if (first_only && best && t_lo > best->t) break;
      double limit = hi;
      if (first_only && best) limit = std::min(hi, (best->t - iv[j].ta) / (iv[j].tb - iv[j].ta));
      if (limit < lo) continue;
      solvePair(j, lo, limit, f, p.fixed % B.F.size(), [&](const Contact& c) {
        if (!first_only) out.push_back(c);
        else if (!best || contactBefore(c, *best)) best = c;
      });
    }
    if (first_only && best) out.push_back(*best);
    if (!first_only) mergeEvents(out);
    stats.narrow_seconds += seconds(start, Clock::now());
    return out;
  }
};

}  // namespace

std::optional<Contact> firstContact(const MovingMesh& a, const MovingMesh& b, const CollideOptions& options,
                                    CollideStats* stats) {
  TwoQuery q(a, b, options);
  std::vector<Contact> c = q.run(true);
  if (stats) *stats = q.stats;
  if (c.empty()) return std::nullopt;
  return c.front();
}

std::vector<Contact> contacts(const MovingMesh& a, const MovingMesh& b, const CollideOptions& options,
                              CollideStats* stats) {
  TwoQuery q(a, b, options);
  std::vector<Contact> c = q.run(false);
  if (stats) *stats = q.stats;
  return c;
}

std::optional<Contact> StaticScene::firstContact(const std::vector<Vec>& vertices, const Faces& faces,
                                                 const Motion3& motion, const CollideOptions& options,
                                                 CollideStats* stats) const {
  Query q(*impl_, vertices, faces, motion, options);
  std::vector<Contact> c = q.run(Query::Mode::First);
  if (stats) *stats = q.stats;
  if (c.empty()) return std::nullopt;
  return c.front();
}

std::vector<Contact> StaticScene::contacts(const std::vector<Vec>& vertices, const Faces& faces,
                                           const Motion3& motion, const CollideOptions& options,
                                           CollideStats* stats) const {
  Query q(*impl_, vertices, faces, motion, options);
  std::vector<Contact> c = q.run(Query::Mode::All);
  if (stats) *stats = q.stats;
  return c;
}

bool StaticScene::touches(const std::vector<Vec>& vertices, const Faces& faces, const Motion3& motion,
                          const CollideOptions& options) const {
  Query q(*impl_, vertices, faces, motion, options);
  return !q.run(Query::Mode::Any).empty();
}

}  // namespace steady
