#pragma once
/// @file
/// Contact prediction between a triangle mesh moving along a Motion (SAM spans) and a static
/// triangle mesh: the first contact, every contact event, or whether they ever touch.
///
/// Method. The static mesh goes into an Embree BVH once (StaticScene). For each query, every
/// moving triangle gets, per span and per time slice of the span, a conservative box of its
/// swept volume (each vertex stays within its path length `|v| r phi1(r |M|)` of its position at
/// the slice's middle, see span_roots.hpp; boxes rounded outward to float), and Embree's
/// rtcCollide pairs these boxes with the static triangles' boxes. Each candidate pair is then
/// solved exactly on its slice: moving vertices against the static triangle's plane
/// (vertex/face), static vertices against the moving triangle's plane (face/vertex, on the
/// inverse span), and edges against edges (coplanarity), each root checked for the features
/// actually meeting. Candidate slices are processed in time order, so the first contact stops
/// the search as soon as no earlier slice remains.
///
/// Guarantee. A contact is reported at the lower end `lo` of its root bracket, never later than
/// the true time by more than RootOptions::time_tolerance (1e-12 in span time), unless the
/// features meet only within `contact_tolerance` (then it may be reported or not). Both meshes
/// are treated as surfaces: contact means the surfaces touch.

#include <steady/collide/span_roots.hpp>
#include <steady/core/motion.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

namespace steady {

/// Options of the mesh contact queries.
struct CollideOptions {
  RootOptions roots;  ///< root isolation (time tolerance 1e-12 in span time by default)
  /// Time slices per span for the broad phase (each moving triangle gets this many swept boxes
  /// per span). More slices give tighter boxes for large motions and fewer candidate pairs, at
  /// the cost of a bigger moving BVH. Default 8 (1 to 128).
  int slices = 8;
  /// Distance, relative to the larger bounding-box diagonal of the two meshes, within which two
  /// features count as meeting at a root (a vertex on the plane of a face must lie within it of
  /// the triangle; two coplanar edges within it of each other). Default 1e-9.
  double contact_tolerance = 1e-9;
};

/// The feature pair of a contact.
enum class ContactType {
  VertexFace,  ///< a moving vertex meets a static triangle
  FaceVertex,  ///< a static vertex meets a moving triangle
  EdgeEdge,    ///< a moving edge meets a static edge
};

/// Stable name ("vertex-face", "face-vertex", "edge-edge").
const char* to_string(ContactType type) noexcept;

/// One contact event between the moving and the static mesh.
struct Contact {
  double t = 0.0;           ///< motion time (key time scale), never later than the true contact
  std::size_t span = 0;     ///< index of the motion span
  double span_time = 0.0;   ///< the span's own parameter s in [0, 1]
  ContactType type = ContactType::VertexFace;
  /// Moving feature: the vertex index (VertexFace), the face index (FaceVertex), or the two
  /// vertex indices of the edge (EdgeEdge; the second entry is -1 otherwise).
  std::array<int, 2> moving{{-1, -1}};
  /// Static feature, with the same conventions (face for VertexFace, vertex for FaceVertex).
  std::array<int, 2> fixed{{-1, -1}};
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   ///< world contact point at time t
  /// Unit world normal at the contact: the static face's (VertexFace), the moving face's at time
  /// t (FaceVertex), or the edges' common normal (EdgeEdge, up to sign).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  /// +1 or -1 when the features cross, 0 for a touch (see ContactRoot::crossing).
  int crossing = 0;
  bool certain = true;  ///< false only when a root solve hit its work limit
};

/// Counters of one query (for reports and benchmarks).
struct CollideStats {
  std::size_t candidate_pairs = 0;  ///< broad-phase pairs (moving slice box, static triangle)
  std::size_t pairs_solved = 0;     ///< pairs whose features were solved
  std::size_t feature_solves = 0;   ///< point/plane and edge/edge root solves
  double broad_seconds = 0.0;       ///< building the moving BVH and rtcCollide
  double narrow_seconds = 0.0;      ///< the exact solves
};

/// A static triangle mesh in an Embree BVH, built once and queried by many motions. Queries
/// are const and may run concurrently.
class StaticScene {
 public:
  /// Builds the BVH. Throws Error(DegenerateInput) for an empty mesh or a zero-area triangle,
  /// Error(NonFinite) for a non-finite vertex, Error(InvalidArgument) for a face index out of
  /// range; messages name the first offending element.
  StaticScene(std::vector<Eigen::Vector3d> vertices, std::vector<std::array<int, 3>> faces);
  ~StaticScene();
  StaticScene(const StaticScene&) = delete;
  StaticScene& operator=(const StaticScene&) = delete;
  StaticScene(StaticScene&&) noexcept;
  StaticScene& operator=(StaticScene&&) noexcept;

  /// The earliest contact of the mesh (vertices in body coordinates, posed by the motion) with
  /// the scene over the whole motion, or none. Throws like the constructor for a bad mesh, and
  /// Error(InvalidArgument) for bad options.
  std::optional<Contact> firstContact(const std::vector<Eigen::Vector3d>& vertices,
                                      const std::vector<std::array<int, 3>>& faces,
                                      const Motion3& motion, const CollideOptions& options = {},
                                      CollideStats* stats = nullptr) const;
  /// Every contact event over the motion, in time order (features that cross, touch, or keep
  /// touching; duplicates of one event found through adjacent triangles are merged).
  std::vector<Contact> contacts(const std::vector<Eigen::Vector3d>& vertices,
                                const std::vector<std::array<int, 3>>& faces, const Motion3& motion,
                                const CollideOptions& options = {}, CollideStats* stats = nullptr) const;
  /// Whether the meshes touch at any time of the motion (stops at the first contact found).
  bool touches(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::array<int, 3>>& faces,
               const Motion3& motion, const CollideOptions& options = {}) const;

  /// Number of static triangles.
  std::size_t faceCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace steady
