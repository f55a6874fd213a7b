#pragma once
/// @file
/// The error measures of bench_sweep.cpp, the same for steady's envelope and the OpenVDB peer:
/// how far posed copies of the body stick out of a swept-volume mesh (benchmark code).
///
/// Containment error. A swept volume must contain the body at every time. The body's vertices
/// are posed at seeded random times (plus both ends) and each posed vertex's distance outside
/// the output mesh is measured exactly: the unsigned distance to the nearest triangle (an AABB
/// tree over the triangles, exact point/triangle distance in double) and inside/outside by ray
/// parity. The largest such distance is the containment error; 0 means every tested vertex is
/// inside or on the mesh. It measures missing volume (stroboscopic gaps between samples, lost
/// thin features, tessellation that cuts corners), not excess volume (that shows in the volume
/// difference to a fine reference, computed by the benchmark).

#include <steady/core/affine.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace steady::bench {

/// A closed triangle mesh prepared for point queries (an AABB tree over its triangles, built
/// once). The mesh need not be manifold; the inside test assumes it is closed (every ray from
/// an inside point crosses it an odd number of times).
class MeshQuery {
 public:
  /// @param[in] vertices #V points; @param[in] triangles #T triples of indices into vertices.
  /// @throws Error(DegenerateInput) for no triangle or an index out of range.
  MeshQuery(std::vector<Eigen::Vector3d> vertices, std::vector<std::array<int, 3>> triangles);

  /// Distance from p to the nearest point of the mesh (exact up to rounding).
  double distance(const Eigen::Vector3d& p) const;

  /// True when p is inside: the parity of the crossings of a ray from p. A ray that passes
  /// within 1e-9 (barycentric) of an edge or a vertex, or grazes a triangle's plane, is
  /// ambiguous and replaced by the next of a fixed list of directions; `inside_retries()`
  /// counts these replacements.
  bool inside(const Eigen::Vector3d& p) const;

  /// Rays re-cast so far because of an ambiguous crossing.
  std::size_t inside_retries() const { return retries_; }

 private:
  struct Node {
    Eigen::Vector3d lo, hi;
    int left = -1, right = -1;  ///< children (inner node), or -1
    int first = 0, count = 0;   ///< leaf: order_[first, first + count)
  };
  int build(int first, int count, int depth);
  double triangleDistance2(int t, const Eigen::Vector3d& p) const;

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<int> order_;  ///< triangle indices, grouped by leaf
  std::vector<Node> nodes_;
  mutable std::size_t retries_ = 0;
};

/// Result of containmentError().
struct Containment {
  double max_outside = 0;     ///< largest distance outside the mesh of a tested posed vertex
  double max_time = 0;        ///< the time at which it was found
  std::size_t points = 0;     ///< posed vertices tested
  std::size_t outside = 0;    ///< of them, outside by more than `tolerance`
  std::size_t ray_retries = 0;  ///< ambiguous rays re-cast (MeshQuery::inside_retries)
};

/// The containment error of a swept-volume mesh.
///
/// @param[in] mesh the swept volume's boundary (world coordinates)
/// @param[in] body_vertices the body's vertices (body coordinates)
/// @param[in] pose the motion: vertex p is at `pose(t).applyPoint(p)`, t in [0, 1]
/// @param[in] times number of times: 0, 1 and `times - 2` uniform random times (>= 2)
/// @param[in] max_vertices at most this many vertices per time: all of them when the body has
///   no more, else a random subset drawn afresh at each time
/// @param[in] seed seed of the times and subsets (std::mt19937_64), so runs are comparable
/// @param[in] tolerance the threshold of `Containment::outside` (world units)
Containment containmentError(const MeshQuery& mesh, const std::vector<Eigen::Vector3d>& body_vertices,
                             const std::function<Affine3(double)>& pose, int times, std::size_t max_vertices,
                             std::uint64_t seed, double tolerance);

/// Signed volume of a triangle mesh (divergence theorem); positive for a closed outward mesh.
double meshVolume(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::array<int, 3>>& triangles);

}  // namespace steady::bench
