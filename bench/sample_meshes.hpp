#pragma once
// CGAL's sample meshes (Debian libcgal-demo), extracted by bench/CMakeLists.txt into
// STEADY_CGAL_MESHES, as the mesh benchmarks use them: scaled to a bounding-box diagonal of 1
// about the box centre, so that tolerances and motions mean the same for every mesh.
#include <steady/io/mesh.hpp>

#include <Eigen/Core>

#include <string>

namespace steady_bench {

inline std::string meshPath(const std::string& name) {
  return std::string(STEADY_CGAL_MESHES) + "/" + name + ".off";
}

// Scales `m` about its bounding-box centre to a bounding-box diagonal of 1 (in place).
inline void toUnitDiagonal(steady::io::TriangleMesh& m) {
  Eigen::Vector3d lo = m.vertices.front(), hi = lo;
  for (const Eigen::Vector3d& p : m.vertices) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double s = 1.0 / (hi - lo).norm();
  const Eigen::Vector3d c = 0.5 * (lo + hi);
  for (Eigen::Vector3d& p : m.vertices) p = s * (p - c);
}

}  // namespace steady_bench
