#pragma once
// The step of the sweep's output stage that merges vertices left a rounding apart (defined in
// trim.cpp), declared here for its tests. Internal to steady::sweep.
#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <vector>

namespace steady::sweep::detail {

// Vertices closer than this times the scene's box diagonal are merged after rounding (1e-13:
// a thousand times the rounding of coordinates, far below any tessellation tolerance).
constexpr double kSnap = 1e-13;

// Merges the vertices of V within delta = kSnap times the diagonal of V's box of each other
// (L-infinity distance, transitively: the classes of the pairs within delta), each class into
// the position of one of its vertices (which one depends on the vertex numbers only), drops the
// triangles of T that collapse and the vertices no triangle uses (renumbering the rest in their
// order of first use). Returns the number of vertices merged away (0: V and T are left as they
// are).
std::size_t snapVertices(std::vector<Eigen::Vector3d>& V, std::vector<std::array<int, 3>>& T);

}  // namespace steady::sweep::detail
