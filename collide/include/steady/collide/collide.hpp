#pragma once
/// @file
/// Contact prediction between a triangle mesh moving along a Motion (SAM spans) and a static
/// triangle mesh, or a second moving mesh: the first contact, every contact event, or whether
/// they ever touch.
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
/// the search as soon as no earlier slice remains. A slice whose boxes are mostly path (mean
/// path diameter above two triangle sizes) is halved before any Embree query, a slice with more
/// than four pairs per moving triangle after it; halves reuse their parent's faces or pairs,
/// since a sub-interval's true sweep lies inside the parent's boxes.
///
/// Guarantee. A contact is reported at the lower end `lo` of its root bracket, never later than
/// the true time by more than RootOptions::time_tolerance (1e-12 in span time), unless the
/// features meet only within `contact_tolerance` (then it may be reported or not). Both meshes
/// are treated as surfaces: contact means the surfaces touch.
///
/// Determinism. The answers are bit-identical from run to run and whatever the number of threads
/// Embree runs on: the candidate pairs Embree reports (from several threads, in an order that
/// changes) are sorted by (moving feature, static feature) before they are solved; among
/// contacts found at the same time, certain ones come first, then crossings, then the feature
/// indices and the other fields decide (a strict total order, no tolerance); and an edge/edge
/// contact's normal and crossing sign do not depend on which triangles found it.

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

/// The feature pair of a contact. "a" is the query mesh (the one moving along the motion
/// passed to the query, or the first of two moving meshes), "b" the scene mesh (or the second).
enum class ContactType {
  VertexFace,  ///< a vertex of a meets a triangle of b
  FaceVertex,  ///< a triangle of a meets a vertex of b
  EdgeEdge,    ///< an edge of a meets an edge of b
};

/// Stable name ("vertex-face", "face-vertex", "edge-edge").
const char* to_string(ContactType type) noexcept;

/// One contact event between two meshes.
struct Contact {
  double t = 0.0;           ///< motion time (key time scale), never later than the true contact
  /// The true contact lies in [t, t_latest]: the root's bracket, 1e-12 of a span wide for a
  /// clean crossing (RootOptions::time_tolerance), wider where rounding blurs the contact
  /// function (features nearly parallel: see RootOptions) or for a touch.
  double t_latest = 0.0;
  std::size_t span = 0;     ///< index of the span of a's motion
  double span_time = 0.0;   ///< that span's own parameter s in [0, 1]
  ContactType type = ContactType::VertexFace;
  /// Feature of mesh a: the vertex index (VertexFace), the face index (FaceVertex), or the two
  /// vertex indices of the edge, smaller first (EdgeEdge; the second entry is -1 otherwise).
  std::array<int, 2> a{{-1, -1}};
  /// Feature of mesh b, with the same conventions (face for VertexFace, vertex for FaceVertex).
  std::array<int, 2> b{{-1, -1}};
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   ///< world contact point at time t
  /// Unit world normal at the contact: b's face normal (VertexFace), a's face normal at time t
  /// (FaceVertex), or the edges' common normal (EdgeEdge): a's edge cross b's edge, each edge
  /// running from the first to the second vertex of `a` and `b` (smaller index first).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  /// +1 or -1 when the features cross, 0 for a touch (see ContactRoot::crossing; for EdgeEdge,
  /// the sign of normal . (b's edge - a's edge) goes from -crossing to +crossing).
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

/// Options of the clearance queries (minimum distance over a motion).
struct ClearanceOptions {
  /// The search stops once upper - lower <= max(absolute_gap * D, relative_gap * upper), D the
  /// larger bounding-box diagonal of the two meshes. Defaults: 1e-2 relative, 1e-9 absolute.
  /// The work grows like (path length of the motion) / gap where the distance stays near its
  /// minimum for long (a body gliding at constant height needs about path / gap evaluations),
  /// and like its square root near an isolated minimum.
  double relative_gap = 1e-2;
  double absolute_gap = 1e-9;
  /// Cap on exact distance evaluations (poses); when reached, the bracket returned is simply
  /// wider than asked (it is always valid). Default 20000.
  std::size_t max_evaluations = 20000;
};

/// The minimum distance between two meshes over a motion, bracketed: the true minimum over all
/// times lies in [lower, upper], and upper is the exact distance at time t (so it is attained).
/// Meshes that touch or cross somewhere have lower = 0.
struct Clearance {
  double lower = 0.0;
  double upper = 0.0;
  double t = 0.0;                                      ///< a time where the distance is upper
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();   ///< closest point of the moving mesh a at t (world)
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();   ///< closest point of mesh b at t (world)
  std::size_t evaluations = 0;                         ///< exact distance evaluations used
};

/// A moving mesh prepared once for many contact queries against static scenes: the mesh is
/// checked and a box hierarchy over its faces is built in body coordinates (median splits, one
/// face per leaf). A query with a prepared mesh poses only the parts of the hierarchy that come
/// near the scene, instead of every vertex and face of the mesh, so its cost follows the
/// neighbourhood of the contact rather than the mesh size.
///
/// Method of those queries (StaticScene::firstContact(const PreparedMesh&, ...) and siblings).
/// The static scene keeps a box hierarchy of its own besides the Embree BVH. The search runs
/// through each span's time in order, halving intervals. Over span time [a, b] (middle m,
/// r = (b - a) / 2) a body point at y at time m moves, along axis k, by at most
/// r |v_k(y)| + r (phi1(r |M|) - 1) |v(y)| (v = M y + u the span's velocity field, phi1 as in
/// span_roots.hpp; v(x(s)) = L^(s-m) v(y) and |L^t - 1| <= e^(|t| |M|) - 1); for a node of the
/// hierarchy, posed at m, |v_k| and |v| are bounded from its centre plus |M| times its radius.
/// A node's swept box is its posed box grown by these travels, by the contact distance, and by
/// a rounding margin of 1e-13 of the magnitudes involved. Pairs of (moving node, static node)
/// whose boxes are apart are dropped for the interval; the larger box of a pair is split; a
/// node whose travel exceeds 0.3 of its radius, or on which both its children would wait, waits
/// for the interval to be halved (with its static partners: a sub-interval's sweep lies inside
/// the parent's bound). A triangle gathers the
/// static faces that its swept box meets and that no separating axis parts from it (its middle
/// triangle grown by the travel box, against the static triangle, over the 11 axes of two
/// triangles), and is then halved in time alone, earliest piece first, while its travel exceeds
/// a tenth of its radius, before the exact solves of the other queries run on the surviving
/// pairs (thresholds in src/prepared.cpp; they change the work, not the answer).
/// Intervals that start after the earliest contact found so far are never visited, so a
/// first-contact query looks at the motion only up to the contact. The guarantee is the one of
/// this header; CollideOptions::slices is checked but not used.
/// Immutable after construction; queries with one prepared mesh may run concurrently.
class PreparedMesh {
 public:
  /// Checks the mesh (vertices in body coordinates) and builds its hierarchy. Throws
  /// Error(DegenerateInput) for an empty mesh or a zero-area triangle, Error(NonFinite) for a
  /// non-finite vertex, Error(InvalidArgument) for a face index out of range.
  PreparedMesh(std::vector<Eigen::Vector3d> vertices, std::vector<std::array<int, 3>> faces);
  ~PreparedMesh();
  PreparedMesh(const PreparedMesh&) = delete;
  PreparedMesh& operator=(const PreparedMesh&) = delete;
  PreparedMesh(PreparedMesh&&) noexcept;
  PreparedMesh& operator=(PreparedMesh&&) noexcept;

  /// The vertices (body coordinates).
  const std::vector<Eigen::Vector3d>& vertices() const;
  /// The faces.
  const std::vector<std::array<int, 3>>& faces() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  friend class StaticScene;
};

/// A static triangle mesh in an Embree BVH, built once and queried by many motions. Queries
/// are const and may run concurrently.
class StaticScene {
 public:
  /// Builds the BVH, and a box hierarchy of its own for the prepared-mesh queries. Throws
  /// Error(DegenerateInput) for an empty mesh or a zero-area triangle, Error(NonFinite) for a
  /// non-finite vertex, Error(InvalidArgument) for a face index out of range; messages name
  /// the first offending element.
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

  /// The same three queries for a prepared mesh (see PreparedMesh): the same answers and
  /// guarantee, with a search that follows the motion through time and the two hierarchies in
  /// depth, so that a query costs about what the neighbourhood of the contact costs. Each
  /// thread keeps the working memory of these queries for its next one (it grows to what the
  /// largest query on that thread needed). Error(InvalidArgument) for bad options.
  std::optional<Contact> firstContact(const PreparedMesh& mesh, const Motion3& motion, const CollideOptions& options = {},
                                      CollideStats* stats = nullptr) const;
  /// Every contact event of a prepared mesh over the motion, in time order (see contacts above).
  std::vector<Contact> contacts(const PreparedMesh& mesh, const Motion3& motion, const CollideOptions& options = {},
                                CollideStats* stats = nullptr) const;
  /// Whether a prepared mesh touches the scene at any time of the motion.
  bool touches(const PreparedMesh& mesh, const Motion3& motion, const CollideOptions& options = {}) const;

  /// The minimum distance between the mesh (posed by the motion) and the scene over the whole
  /// motion, as a bracket (see Clearance): exact distances at chosen times, and between them the
  /// bound that no point moves farther than its path length. Throws like firstContact, and
  /// Error(InvalidArgument) for bad options.
  Clearance clearance(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::array<int, 3>>& faces,
                      const Motion3& motion, const ClearanceOptions& options = {}) const;

  /// Number of static triangles.
  std::size_t faceCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A mesh (vertices in body coordinates) moving along a motion, for two-body queries.
struct MovingMesh {
  const std::vector<Eigen::Vector3d>& vertices;    ///< body coordinates
  const std::vector<std::array<int, 3>>& faces;    ///< vertex indices
  const Motion3& motion;                           ///< body-to-world poses over time
};

/// The earliest contact of two meshes that both move, over the time range their motions share,
/// or none. Between consecutive key times of either motion, each mesh follows one SAM span; the
/// relative motion is not a SAM, and the contact functions of the composed motion are solved
/// with the same guarantee (bounds from both spans' logs). `span`/`span_time` of the result refer
/// to mesh a's motion. Throws like StaticScene for bad meshes, Error(InvalidArgument) when the
/// motions share no time or for bad options.
std::optional<Contact> firstContact(const MovingMesh& a, const MovingMesh& b, const CollideOptions& options = {},
                                    CollideStats* stats = nullptr);
/// Every contact event of two moving meshes, in time order (see firstContact(a, b)).
std::vector<Contact> contacts(const MovingMesh& a, const MovingMesh& b, const CollideOptions& options = {},
                              CollideStats* stats = nullptr);
/// The minimum distance between two moving meshes over the time range their motions share, as
/// a bracket (see Clearance and StaticScene::clearance).
Clearance clearance(const MovingMesh& a, const MovingMesh& b, const ClearanceOptions& options = {});

}  // namespace steady
