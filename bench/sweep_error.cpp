// Error measures of the sweep benchmarks (see sweep_error.hpp).
#include "sweep_error.hpp"

#include <steady/core/error.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>

namespace steady::bench {

namespace {

using V = Eigen::Vector3d;

constexpr int kLeafSize = 4;

// Squared distance from p to the axis-aligned box [lo, hi] (0 inside).
double boxDistance2(const V& p, const V& lo, const V& hi) {
  const V d = (lo - p).cwiseMax(p - hi).cwiseMax(V::Zero());
  return d.squaredNorm();
}

// Whether the ray p + s d, s >= 0, meets the box [lo, hi] (slab test; inv = 1 / d).
bool rayHitsBox(const V& p, const V& inv, const V& lo, const V& hi) {
  double s0 = 0, s1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    double near = (lo[a] - p[a]) * inv[a], far = (hi[a] - p[a]) * inv[a];
    if (near > far) std::swap(near, far);
    s0 = std::max(s0, near);
    s1 = std::min(s1, far);
    if (s0 > s1) return false;
  }
  return true;
}

// Directions of the inside test: not parallel to coordinate planes or to each other, so that
// axis-aligned meshes (voxel output) do not make every ray graze an edge.
const V kDirections[] = {
    V(0.5773502691896258, 0.6123724356957945, 0.5400617248673217),
    V(-0.3826834323650898, 0.7071067811865475, 0.5948227867513413),
    V(0.2672612419124244, -0.5345224838248488, 0.8017837257372732),
    V(-0.7071067811865476, -0.4082482904638630, -0.5773502691896258),
    V(0.8164965809277260, 0.1825741858350554, -0.5477225575051661),
    V(-0.1313064328597225, -0.9191450300180579, 0.3713906763541037),
    V(0.6396021490668313, -0.4264014327112209, -0.6396021490668313),
};

}  // namespace

MeshQuery::MeshQuery(std::vector<Eigen::Vector3d> vertices, std::vector<std::array<int, 3>> triangles)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)) {
  if (triangles_.empty()) throw Error(ErrorCode::DegenerateInput, "MeshQuery: the mesh has no triangle.");
  const int nv = static_cast<int>(vertices_.size());
  for (const auto& t : triangles_)
    for (int c : t)
      if (c < 0 || c >= nv) throw Error(ErrorCode::DegenerateInput, "MeshQuery: a triangle index is outside [0, #V).");
  order_.resize(triangles_.size());
  for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<int>(i);
  nodes_.reserve(2 * triangles_.size() / kLeafSize + 2);
  build(0, static_cast<int>(order_.size()), 0);
}

// Median split of order_[first, first + count) along the longest axis of the centroids' box.
int MeshQuery::build(int first, int count, int depth) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  V lo = V::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  V clo = lo, chi = hi;
  for (int i = first; i < first + count; ++i) {
    const auto& t = triangles_[order_[i]];
    V c = V::Zero();
    for (int k : t) {
      lo = lo.cwiseMin(vertices_[k]);
      hi = hi.cwiseMax(vertices_[k]);
      c += vertices_[k];
    }
    c /= 3.0;
    clo = clo.cwiseMin(c);
    chi = chi.cwiseMax(c);
  }
  nodes_[id].lo = lo;
  nodes_[id].hi = hi;
  if (count <= kLeafSize || depth > 60) {
    nodes_[id].first = first;
    nodes_[id].count = count;
    return id;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const int half = count / 2;
  auto centroid = [&](int t) {
    const auto& f = triangles_[t];
    return vertices_[f[0]][axis] + vertices_[f[1]][axis] + vertices_[f[2]][axis];
  };
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](int a, int b) { return centroid(a) < centroid(b); });
  const int left = build(first, half, depth + 1);
  const int right = build(first + half, count - half, depth + 1);
  nodes_[id].left = left;
  nodes_[id].right = right;
  return id;
}

// Squared distance from p to triangle t: the closest point is found by the Voronoi region of
// p (a corner, an edge, or the interior), from the barycentric sub-determinants.
double MeshQuery::triangleDistance2(int t, const Eigen::Vector3d& p) const {
  const V& a = vertices_[triangles_[t][0]];
  const V& b = vertices_[triangles_[t][1]];
  const V& c = vertices_[triangles_[t][2]];
  const V ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();  // corner a
  const V bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();  // corner b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {  // edge ab
    const double s = d1 / (d1 - d3);
    return (p - (a + s * ab)).squaredNorm();
  }
  const V cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();  // corner c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {  // edge ac
    const double s = d2 / (d2 - d6);
    return (p - (a + s * ac)).squaredNorm();
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {  // edge bc
    const double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return (p - (b + s * (c - b))).squaredNorm();
  }
  const double denom = va + vb + vc;
  if (!(denom > 0)) {  // zero-area triangle: the nearest of its three edges
    auto seg = [&](const V& x, const V& y) {
      const V e = y - x;
      const double l2 = e.squaredNorm();
      const double s = l2 > 0 ? std::clamp((p - x).dot(e) / l2, 0.0, 1.0) : 0.0;
      return (p - (x + s * e)).squaredNorm();
    };
    return std::min({seg(a, b), seg(b, c), seg(c, a)});
  }
  const double v = vb / denom, w = vc / denom;  // interior
  return (p - (a + v * ab + w * ac)).squaredNorm();
}

double MeshQuery::distance(const Eigen::Vector3d& p) const {
  double best = std::numeric_limits<double>::infinity();
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (boxDistance2(p, n.lo, n.hi) >= best) continue;
    if (n.left < 0) {
      for (int i = n.first; i < n.first + n.count; ++i) best = std::min(best, triangleDistance2(order_[i], p));
      continue;
    }
    // Visit the nearer child first (pushed last).
    const double dl = boxDistance2(p, nodes_[n.left].lo, nodes_[n.left].hi);
    const double dr = boxDistance2(p, nodes_[n.right].lo, nodes_[n.right].hi);
    if (dl < dr) {
      stack[top++] = n.right;
      stack[top++] = n.left;
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  return std::sqrt(best);
}

bool MeshQuery::inside(const Eigen::Vector3d& p) const {
  constexpr double kEdge = 1e-9;  // barycentric margin of an ambiguous crossing
  const double scale = (nodes_[0].hi - nodes_[0].lo).norm();
  for (const V& d : kDirections) {
    const V inv = d.cwiseInverse();
    bool ambiguous = false;
    int crossings = 0;
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0 && !ambiguous) {
      const Node& n = nodes_[stack[--top]];
      if (!rayHitsBox(p, inv, n.lo, n.hi)) continue;
      if (n.left >= 0) {
        stack[top++] = n.left;
        stack[top++] = n.right;
        continue;
      }
      for (int i = n.first; i < n.first + n.count && !ambiguous; ++i) {
        // Möller-Trumbore: p + s d = a + u (b - a) + v (c - a).
        const auto& f = triangles_[order_[i]];
        const V& a = vertices_[f[0]];
        const V e1 = vertices_[f[1]] - a, e2 = vertices_[f[2]] - a;
        const V pv = d.cross(e2);
        const double det = e1.dot(pv);
        const V s = p - a;
        if (std::abs(det) <= 1e-14 * e1.norm() * e2.norm()) {
          // The ray is parallel to the triangle's plane: ambiguous only if it lies in it.
          const V nrm = e1.cross(e2);
          const double nn = nrm.norm();
          if (nn == 0 || std::abs(nrm.dot(s)) <= 1e-12 * scale * nn) ambiguous = true;
          continue;
        }
        const double inv_det = 1.0 / det;
        const double u = s.dot(pv) * inv_det;
        const V q = s.cross(e1);
        const double v = d.dot(q) * inv_det;
        const double w = 1.0 - u - v;
        if (u < -kEdge || v < -kEdge || w < -kEdge) continue;
        const double dist = e2.dot(q) * inv_det;
        if (dist < -1e-12 * scale) continue;
        if (u <= kEdge || v <= kEdge || w <= kEdge || dist <= 1e-12 * scale) {
          ambiguous = true;  // through an edge, a vertex, or starting on the surface
          continue;
        }
        ++crossings;
      }
    }
    if (!ambiguous) return crossings % 2 == 1;
    ++retries_;
  }
  return false;  // every direction ambiguous: p is on the surface up to rounding
}

Containment containmentError(const MeshQuery& mesh, const std::vector<Eigen::Vector3d>& body_vertices,
                             const std::function<Affine3(double)>& pose, int times, std::size_t max_vertices,
                             std::uint64_t seed, double tolerance) {
  if (times < 2) throw Error(ErrorCode::InvalidArgument, "containmentError: times must be at least 2.");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<int> pick(body_vertices.size());
  for (std::size_t i = 0; i < pick.size(); ++i) pick[i] = static_cast<int>(i);
  const std::size_t per_time = std::min(max_vertices, body_vertices.size());
  const std::size_t retries_before = mesh.inside_retries();
  Containment out;
  for (int k = 0; k < times; ++k) {
    const double t = k == 0 ? 0.0 : k == 1 ? 1.0 : uniform(rng);
    const Affine3 P = pose(t);
    if (per_time < pick.size()) {  // partial Fisher-Yates: a fresh random subset
      for (std::size_t i = 0; i < per_time; ++i) {
        std::uniform_int_distribution<std::size_t> j(i, pick.size() - 1);
        std::swap(pick[i], pick[j(rng)]);
      }
    }
    for (std::size_t i = 0; i < per_time; ++i) {
      const V x = P.applyPoint(body_vertices[pick[i]]);
      ++out.points;
      const double d = mesh.distance(x);
      // Only a point farther than both thresholds can change the result: skip its ray test.
      if (d <= out.max_outside && d <= tolerance) continue;
      if (mesh.inside(x)) continue;
      if (d > tolerance) ++out.outside;
      if (d > out.max_outside) {
        out.max_outside = d;
        out.max_time = t;
      }
    }
  }
  out.ray_retries = mesh.inside_retries() - retries_before;
  return out;
}

double meshVolume(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::array<int, 3>>& triangles) {
  double six_v = 0;
  for (const auto& t : triangles) six_v += vertices[t[0]].dot(vertices[t[1]].cross(vertices[t[2]]));
  return six_v / 6.0;
}

}  // namespace steady::bench
