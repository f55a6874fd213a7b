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

/// The static scene's data (StaticScene::Impl adds nothing: it only names it for the header).
struct SceneData {
  std::vector<Vec> V;
  Faces F;
  std::vector<Vec> normal;  // unit face normals
  std::vector<double> offset;  // normal . x = offset on the face's plane
  double diag = 0;
  double mean_extent = 0;  // mean over faces of the largest side of the face's box
  Vec lo, hi;  // bounding box
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

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

struct PairHit {
  unsigned moving, fixed;  // moving primitive (slice-major), static face
};

struct PairSink {
  std::mutex mutex;
  std::vector<PairHit> pairs;
};

/// rtcCollide callback: appends the pairs to the PairSink passed as user data (thread-safe).
void collectPairs(void* user, RTCCollision* collisions, unsigned n);

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
