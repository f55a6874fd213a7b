#pragma once
/// @file
/// The sampled-union swept volume on OpenVDB: the peer that bench_sweep.cpp measures steady's
/// exact envelopes against (benchmark code, not part of the library).
///
/// Method. The body is posed at N times `t_k = k / (N - 1)`, k = 0..N-1; each posed mesh is
/// rasterised into a narrow-band signed-distance level set (`tools::meshToLevelSet`, negative
/// inside) on one shared grid transform; the level sets are united one after the other into an
/// accumulator (`tools::csgUnion`, the voxel-wise minimum), and the zero isosurface of the
/// union is extracted (`tools::volumeToMesh`, quads split into two triangles).
///
/// What it misses, by construction: the motion between two samples (a point moving at speed v
/// can be outside every sampled copy by up to about `v / (2 (N - 1))`), and features thinner
/// than about a voxel, which the level set cannot hold. Choose N so that no body point moves
/// more than about a voxel between samples (samplesForStep() below) to balance the two.
///
/// Narrow band and union. Each level set holds exact distances only within `half_width`
/// voxels of its own surface; beyond, it holds ±(half_width · voxel) (the background, with the
/// inside sign from the flood fill). The minimum of two such fields has the sign of the true
/// minimum everywhere, and its value is the true minimum wherever that minimum lies inside the
/// band of the copy attaining it. volumeToMesh reads the 8 corners of every cell the zero set
/// crosses; those corners lie within `√3` voxels of the union's surface, so a half width above
/// √3 (default 3, at least 2 is required) makes the extracted surface that of the exact
/// minimum of the sampled distance fields, however far the copies move between samples.

#include <steady/core/affine.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <functional>
#include <vector>

namespace steady::bench {

/// Options of vdbSampledSweep().
struct VdbSweepOptions {
  /// N >= 2: poses at t_k = k / (N - 1), both ends included.
  int samples = 100;
  /// Edge length of a voxel, in world units (the units of the posed vertices), > 0.
  double voxel_size = 0.01;
  /// Half width of each narrow band, in voxels; >= 2 (see the file comment). Default 3
  /// (OpenVDB's LEVEL_SET_HALF_WIDTH).
  double half_width = 3.0;
  /// volumeToMesh's adaptivity in [0, 1]: 0 keeps one polygon per crossed voxel face (the
  /// finest mesh); larger merges flat regions into fewer polygons.
  double adaptivity = 0.0;
};

/// Wall-clock seconds of each stage.
struct VdbSweepTimings {
  double level_sets = 0;  ///< posing the vertices and meshToLevelSet, all N samples
  double unite = 0;       ///< csgUnion into the accumulator, all N samples
  double mesh = 0;        ///< volumeToMesh, quad splitting, orientation and volume
  double total = 0;
};

/// The sampled-union sweep.
struct VdbSweep {
  std::vector<Eigen::Vector3d> vertices;      ///< world coordinates
  std::vector<std::array<int, 3>> triangles;  ///< counter-clockwise seen from outside
  double volume = 0;                          ///< enclosed volume of the output mesh
  std::size_t active_voxels = 0;              ///< active voxels of the united level set
  std::size_t grid_bytes = 0;                 ///< memory of the united level set (memUsage)
  VdbSweepTimings timings;
};

/// The swept volume of a closed mesh as the union of its level sets at N sampled poses.
///
/// @param[in] vertices #V body vertices (body coordinates)
/// @param[in] faces #F triangles, indices into `vertices`; the mesh must be closed (the level
///   set's inside is found by flood fill) but may be non-manifold or self-intersecting
/// @param[in] pose the pose at time t in [0, 1]: body point p is at `pose(t).applyPoint(p)`
/// @param[in] options N, voxel size (world units), band half width, adaptivity
/// @return the meshed zero isosurface of the union, oriented outward (world coordinates),
///   its volume, the grid's size and the time of each stage
/// @throws Error(InvalidArgument) for N < 2, a voxel size that is not finite and positive, a
///   half width below 2 or an adaptivity outside [0, 1]; Error(DegenerateInput) for an empty
///   mesh or a face index out of range. Runs on OpenVDB's TBB threads.
VdbSweep vdbSampledSweep(const std::vector<Eigen::Vector3d>& vertices,
                         const std::vector<std::array<int, 3>>& faces,
                         const std::function<Affine3(double)>& pose, const VdbSweepOptions& options);

/// The number of samples N that keeps every body vertex within `step` (world units) of its
/// previous sample: N - 1 = ceil(L / step), L the largest path length of a vertex over
/// t in [0, 1], measured on `probe` equal time steps (a lower bound of the true length that
/// converges from below). With `step` equal to the voxel size, the time-sampling gap is about
/// the voxel resolution. Returns at least 2.
int samplesForStep(const std::vector<Eigen::Vector3d>& vertices, const std::function<Affine3(double)>& pose,
                   double step, int probe = 256);

}  // namespace steady::bench
