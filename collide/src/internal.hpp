#pragma once
// Internals shared by the collide sources: mesh checks, small geometry, the Embree plumbing and
// the static scene's data. Not installed.
#include <steady/collide/collide.hpp>
#include <steady/core/error.hpp>

#include <embree3/rtcore.h>

#include <Eigen/Core>

#include <array>
#include <mutex>
#include <vector>

namespace steady::detail {

using Vec = Eigen::Vector3d;
using Faces = std::vector<std::array<int, 3>>;

/// Throws Error(DegenerateInput) for an empty mesh or a zero-area face, Error(NonFinite) for a
/// non-finite vertex, Error(InvalidArgument) for a face index out of range. `which` names the
/// mesh in the message ("the static", "the moving", ...).
void checkMesh(const std::vector<Vec>& V, const Faces& F, const char* which);
/// Diagonal of the bounding box of a non-empty point set.
double boxDiagonal(const std::vector<Vec>& V);
/// Outward rounding of a double box to float, as Embree stores it.
void storeBounds(RTCBounds* b, const Vec& lo, const Vec& hi);
/// Mean over the faces of the largest side of each face's bounding box.
double meanFaceExtent(const std::vector<Vec>& V, const Faces& F);
/// Closest point of triangle (a, b, c) to p.
Vec closestOnTriangle(const Vec& p, const Vec& a, const Vec& b, const Vec& c);
/// Closest points cp, cq of segments [p0, p1] and [q0, q1]; returns their distance.
double segmentDistance(const Vec& p0, const Vec& p1, const Vec& q0, const Vec& q1, Vec& cp, Vec& cq);

/// A node of the static scene's own box hierarchy (used by the prepared-mesh queries, which
/// descend it together with the moving mesh's hierarchy): up to four children side by side, their
/// boxes by coordinate (the faces' boxes rounded outward to float, so that one pass of compares
/// tests all four). Child k is node child[k] when child[k] >= 0, face -1 - child[k] when < 0; an
/// empty slot has an inverted box (lo = +inf, hi = -inf), which meets nothing. size[k] is the
/// largest side of box k. A reference to child k of node i is the number 4 i + k; the root's
/// box is child 0 of node 0.
struct alignas(16) StaticNode {
  float lo[3][4], hi[3][4];
  float size[4];
  int child[4];
};

/// The static scene's data (StaticScene::Impl adds nothing: it only names it for the header).
struct SceneData {
  std::vector<Vec> V;
  Faces F;
  std::vector<Vec> normal;  // unit face normals
  std::vector<double> offset;  // normal . x = offset on the face's plane
  // The least and greatest of normal . x over the face's corners (offset up to rounding): the
  // face's extent along its normal, read by the prepared queries' plane test without the face's
  // vertices.
  std::vector<std::array<double, 2>> plane_range;
  double diag = 0;
  double mean_extent = 0;  // mean over faces of the largest side of the face's box
  Vec lo, hi;  // bounding box
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<StaticNode> tree;  // box hierarchy over the faces (see StaticNode)

  SceneData() = default;
  SceneData(const SceneData&) = delete;
  SceneData& operator=(const SceneData&) = delete;
  ~SceneData() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  static void bounds(const RTCBoundsFunctionArguments* args) {
    const auto* self = static_cast<const SceneData*>(args->geometryUserPtr);
    const auto& f = self->F[args->primID];
    const Vec lo = self->V[f[0]].cwiseMin(self->V[f[1]]).cwiseMin(self->V[f[2]]);
    const Vec hi = self->V[f[0]].cwiseMax(self->V[f[1]]).cwiseMax(self->V[f[2]]);
    storeBounds(args->bounds_o, lo, hi);
  }
};

/// Builds SceneData::tree: median splits along the longest axis of the face centroids down to
/// one face, each node then taking its grandchildren as its four children.
void buildStaticTree(SceneData& s);

/// One moving triangle prepared for the exact solves of an interval of a span: its vertex indices
/// and face index, its vertices at span time 0 (world), at the interval's middle, and a radius
/// each vertex stays within over the interval (path length plus rounding).
struct MovingTriangle {
  std::array<int, 3> v{};
  int face = 0;
  std::array<Vec, 3> W0, mid;
  std::array<double, 3> rad{};
};

/// The span a pair is solved on: its index and key times, and the root solvers of the span
/// (moving features) and of its inverse (static vertices against moving faces).
struct PairSpan {
  std::size_t span_index;
  double t0, t1;
  const SpanRoots* fwd;
  const SpanRoots* inv;
};

/// Solves moving triangle m against static face g over span time [a, hi] (inside the interval m
/// was placed for) and appends every feature contact found to out. Features whose swept boxes
/// stay farther apart than `margin` are skipped; `tol` is the contact distance.
void solveTrianglePair(const SceneData& st, const PairSpan& ps, const MovingTriangle& m, std::size_t g, double a,
                       double hi, double tol, double margin, CollideStats& stats, std::vector<Contact>& out);

/// Sorts contact events by time and merges duplicates of one event.
void mergeContactEvents(std::vector<Contact>& out);
/// The span of the inverse relative affinity, with log exactly -log (see collide.cpp).
Span3 inverseOf(const Span3& sp);

struct PairHit {
  unsigned moving, fixed;  // moving primitive (slice-major), static face
};

struct PairSink {
  std::mutex mutex;
  std::vector<PairHit> pairs;
};

/// rtcCollide callback: appends the pairs to the PairSink passed as user data (thread-safe).
/// Embree calls it from its TBB threads, so the pairs arrive in an order that changes from run
/// to run: sortPairs must put them in order before anything depends on it.
void collectPairs(void* user, RTCCollision* collisions, unsigned n);
/// Sorts broad-phase pairs by (moving primitive, static face) and drops repeats, so that the
/// solves that follow, and the first contact they report, do not depend on the order in which
/// Embree's threads called collectPairs.
void sortPairs(std::vector<PairHit>& pairs);

/// A strict total order on contacts: earlier time first; at equal times certain before
/// uncertain, crossing before touching, then by span time, type, features, and the remaining
/// fields by their bits (so that every two different contacts are ordered, and equal times are
/// decided by the contacts, not by the order in which pairs were solved). Used to pick the first
/// contact and to order contact events.
bool contactBefore(const Contact& x, const Contact& y);

/// A new Embree device; throws Error(InvalidArgument) when Embree cannot create one.
RTCDevice newDevice();
/// One Embree device for the queries that build their own scenes (creating one costs tens of
/// milliseconds); Embree devices are thread-safe. Never released: it lives as long as the process.
RTCDevice sharedDevice();
/// A user geometry of `count` primitives with the given bounds callback, committed into `scene`.
void addUserGeometry(RTCDevice device, RTCScene scene, unsigned count, RTCBoundsFunction fn, void* user);

}  // namespace steady::detail

namespace steady {
struct StaticScene::Impl : detail::SceneData {};
}  // namespace steady
