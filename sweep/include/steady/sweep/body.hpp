#pragma once
/// @file
/// The body of a sweep: a closed, oriented, 2-manifold triangle mesh in body coordinates,
/// validated once, with the adjacency the grazing and candidate steps need.

#include <steady/core/motion.hpp>

#include <Eigen/Core>

#include <array>
#include <vector>

namespace steady::sweep {

/// Options of the body validation.
struct BodyOptions {
  /// A face is degenerate (zero area) when twice its area, `|(b - a) x (c - a)|`, is at most
  /// this tolerance times the square of its longest edge. The ratio is about the face's
  /// smallest angle (in radians) and does not depend on units; the default 1e-12 rejects faces
  /// that are flat up to rounding (repeated or collinear vertices), not merely thin ones.
  double degenerate_tolerance = 1e-12;
  /// A body is flat (encloses no volume) when `|signed volume|` is at most this tolerance
  /// times the cube of its bounding-box diagonal (a closed surface folded onto itself).
  double volume_tolerance = 1e-12;
};

/// A closed, consistently and outward oriented, 2-manifold triangle mesh (body coordinates).
///
/// Faces are counter-clockwise seen from outside (right-hand rule: the normal
/// `(b - a) x (c - a)` points out). Several closed shells are accepted (a shell oriented inward
/// is a cavity) as long as the total signed volume is positive. Vertices used by no face are
/// kept (indices stay those of the input) and play no role in the sweep.
class Body {
 public:
  /// An undirected edge `(vertices[0] < vertices[1])` and its two faces: `faces[0]` traverses
  /// it from vertices[0] to vertices[1] (so it lies on the left of that direction seen from
  /// outside), `faces[1]` from vertices[1] to vertices[0].
  struct Edge {
    std::array<int, 2> vertices{{-1, -1}};
    std::array<int, 2> faces{{-1, -1}};
  };

  /// Validates and stores the mesh (vertices: #V points; faces: #F triples of vertex indices).
  ///
  /// Checks, in this order; each failure throws steady::Error whose message gives the number
  /// of offending elements, the first one, and what to do:
  /// - DegenerateInput: no vertex or no face;
  /// - NonFinite: a vertex with a NaN or infinite coordinate;
  /// - InvalidArgument: a face index outside [0, #V);
  /// - DegenerateInput: a degenerate face (see BodyOptions::degenerate_tolerance; this includes
  ///   faces that repeat a vertex);
  /// - DegenerateInput: an open mesh (an edge used by one face only: a boundary edge);
  /// - DegenerateInput: a non-manifold edge (shared by more than two faces);
  /// - DegenerateInput: inconsistent orientation (an edge traversed twice in the same direction);
  /// - DegenerateInput: a non-manifold vertex (its faces form more than one fan);
  /// - InvalidArgument: inward orientation (negative signed volume: flip the faces);
  /// - DegenerateInput: a flat body (see BodyOptions::volume_tolerance).
  /// Also throws Error(InvalidArgument) for bad options (non-finite or negative tolerances).
  Body(std::vector<Eigen::Vector3d> vertices, std::vector<std::array<int, 3>> faces,
       const BodyOptions& options = {});

  /// The vertices (body coordinates), as given.
  const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
  /// The faces, as given (counter-clockwise seen from outside).
  const std::vector<std::array<int, 3>>& faces() const { return faces_; }
  /// Every undirected edge once (see Edge), sorted by (vertices[0], vertices[1]).
  const std::vector<Edge>& edges() const { return edges_; }
  /// For face f, `faceEdges()[f][k]` is the index of its edge from corner k to corner k+1 (mod 3).
  const std::vector<std::array<int, 3>>& faceEdges() const { return face_edges_; }
  /// Unit outward face normals (body coordinates).
  const std::vector<Eigen::Vector3d>& faceNormals() const { return normals_; }
  /// Enclosed volume (positive: validation rejects inward bodies), by the divergence theorem.
  double signedVolume() const { return volume_; }
  /// Total surface area.
  double area() const { return area_; }
  /// Bounding box of the vertices (body coordinates).
  const Box<3>& box() const { return box_; }

 private:
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<Edge> edges_;
  std::vector<std::array<int, 3>> face_edges_;
  std::vector<Eigen::Vector3d> normals_;
  double volume_ = 0.0;
  double area_ = 0.0;
  Box<3> box_;
};

}  // namespace steady::sweep
