// The sampled-union swept volume on OpenVDB (see vdb_baseline.hpp).
#include "vdb_baseline.hpp"

#include <steady/core/error.hpp>

#include <Eigen/Geometry>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <string>

namespace steady::bench {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void initializeOnce() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

}  // namespace

VdbSweep vdbSampledSweep(const std::vector<Eigen::Vector3d>& vertices,
                         const std::vector<std::array<int, 3>>& faces,
                         const std::function<Affine3(double)>& pose, const VdbSweepOptions& options) {
  if (options.samples < 2)
    throw Error(ErrorCode::InvalidArgument, "vdbSampledSweep: samples is " + std::to_string(options.samples) +
                                                "; give at least 2 (both ends of the motion).");
  if (!std::isfinite(options.voxel_size) || options.voxel_size <= 0)
    throw Error(ErrorCode::InvalidArgument, "vdbSampledSweep: voxel_size must be finite and positive (world units).");
  if (!(options.half_width >= 2.0) || !std::isfinite(options.half_width))
    throw Error(ErrorCode::InvalidArgument,
                "vdbSampledSweep: half_width must be at least 2 voxels, so that the union's surface "
                "lies inside the band of the copy that forms it.");
  if (!(options.adaptivity >= 0.0 && options.adaptivity <= 1.0))
    throw Error(ErrorCode::InvalidArgument, "vdbSampledSweep: adaptivity must lie in [0, 1].");
  if (vertices.empty() || faces.empty())
    throw Error(ErrorCode::DegenerateInput, "vdbSampledSweep: the mesh has no vertex or no face.");
  const int nv = static_cast<int>(vertices.size());
  std::vector<openvdb::Vec3I> tris;
  tris.reserve(faces.size());
  for (const auto& f : faces) {
    for (int c : f)
      if (c < 0 || c >= nv)
        throw Error(ErrorCode::DegenerateInput, "vdbSampledSweep: a face index is outside [0, #V).");
    tris.emplace_back(static_cast<openvdb::Index32>(f[0]), static_cast<openvdb::Index32>(f[1]),
                      static_cast<openvdb::Index32>(f[2]));
  }
  initializeOnce();

  VdbSweep out;
  const auto t_all = Clock::now();
  // One transform for every copy: voxel (i, j, k) is centred at world (i, j, k) * voxel_size,
  // so the copies' voxels coincide and csgUnion works voxel by voxel.
  const openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(options.voxel_size);
  const auto half_width = static_cast<float>(options.half_width);

  openvdb::FloatGrid::Ptr acc;
  std::vector<openvdb::Vec3s> posed(vertices.size());
  for (int k = 0; k < options.samples; ++k) {
    const double t = static_cast<double>(k) / (options.samples - 1);
    auto t0 = Clock::now();
    const Affine3 P = pose(t);
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      const Eigen::Vector3d w = P.applyPoint(vertices[i]);
      posed[i] = openvdb::Vec3s(static_cast<float>(w.x()), static_cast<float>(w.y()), static_cast<float>(w.z()));
    }
    // meshToLevelSet takes world-space points and rasterises them through `xform`.
    openvdb::FloatGrid::Ptr copy = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, posed, tris, half_width);
    out.timings.level_sets += since(t0);
    t0 = Clock::now();
    if (!acc) {
      acc = copy;
    } else {
      openvdb::tools::csgUnion(*acc, *copy);  // acc = min(acc, copy); copy is emptied
    }
    out.timings.unite += since(t0);
  }

  const auto t_mesh = Clock::now();
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*acc, points, triangles, quads, 0.0, options.adaptivity);
  out.vertices.reserve(points.size());
  for (const auto& p : points) out.vertices.emplace_back(p.x(), p.y(), p.z());
  out.triangles.reserve(triangles.size() + 2 * quads.size());
  auto idx = [](openvdb::Index32 i) { return static_cast<int>(i); };
  for (const auto& t : triangles) out.triangles.push_back({idx(t[0]), idx(t[1]), idx(t[2])});
  for (const auto& q : quads) {
    out.triangles.push_back({idx(q[0]), idx(q[1]), idx(q[2])});
    out.triangles.push_back({idx(q[0]), idx(q[2]), idx(q[3])});
  }
  // Signed volume by the divergence theorem; volumeToMesh's winding is reversed to outward
  // (counter-clockwise seen from outside) when it comes out negative.
  double six_v = 0;
  for (const auto& t : out.triangles)
    six_v += out.vertices[t[0]].dot(out.vertices[t[1]].cross(out.vertices[t[2]]));
  if (six_v < 0) {
    for (auto& t : out.triangles) std::swap(t[1], t[2]);
    six_v = -six_v;
  }
  out.volume = six_v / 6.0;
  out.active_voxels = static_cast<std::size_t>(acc->activeVoxelCount());
  out.grid_bytes = static_cast<std::size_t>(acc->memUsage());
  out.timings.mesh = since(t_mesh);
  out.timings.total = since(t_all);
  return out;
}

int samplesForStep(const std::vector<Eigen::Vector3d>& vertices, const std::function<Affine3(double)>& pose,
                   double step, int probe) {
  if (!std::isfinite(step) || step <= 0)
    throw Error(ErrorCode::InvalidArgument, "samplesForStep: step must be finite and positive (world units).");
  if (probe < 1) throw Error(ErrorCode::InvalidArgument, "samplesForStep: probe must be at least 1.");
  std::vector<double> length(vertices.size(), 0.0);
  Affine3 prev = pose(0.0);
  for (int k = 1; k <= probe; ++k) {
    const Affine3 cur = pose(static_cast<double>(k) / probe);
    for (std::size_t i = 0; i < vertices.size(); ++i)
      length[i] += (cur.applyPoint(vertices[i]) - prev.applyPoint(vertices[i])).norm();
    prev = cur;
  }
  const double longest = vertices.empty() ? 0.0 : *std::max_element(length.begin(), length.end());
  return std::max(2, static_cast<int>(std::ceil(longest / step)) + 1);
}

}  // namespace steady::bench
