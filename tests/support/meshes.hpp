#pragma once
// Small test meshes generated in code, shared by the collide and sweep tests.
#include <Eigen/Core>

#include <array>
#include <cmath>
#include <vector>

namespace steady_test {

using V = Eigen::Vector3d;
using Faces = std::vector<std::array<int, 3>>;

struct Mesh {
  std::vector<V> v;
  Faces f;
};

// An axis-aligned box [lo, hi], outward triangles; vertex i has x from bit 0, y bit 1, z bit 2.
inline Mesh box(const V& lo, const V& hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.v.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  m.f = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
         {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}


// A regular octahedron of radius r about c.
inline Mesh octahedron(const V& c, double r) {
  Mesh m;
  m.v = {c + V(r, 0, 0), c + V(-r, 0, 0), c + V(0, r, 0), c + V(0, -r, 0), c + V(0, 0, r), c + V(0, 0, -r)};
  m.f = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return m;
}


// A grid of 2 n^2 triangles over [-h, h]^2 in the plane z = 0, normals up.
inline Mesh grid(int n, double h) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.v.emplace_back(-h + 2 * h * i / n, -h + 2 * h * j / n, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.f.push_back({a, b, d});
      m.f.push_back({a, d, c});
    }
  return m;
}


// A UV sphere of radius r about c (rings x segments quads, fans at the poles), outward triangles.
inline Mesh uvSphere(int rings, int segments, double r, const V& c = V::Zero()) {
  Mesh m;
  m.v.push_back(c + V(0, 0, r));
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / segments;
      m.v.push_back(c + r * V(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  m.v.push_back(c + V(0, 0, -r));
  const int south = static_cast<int>(m.v.size()) - 1;
  auto ring = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) m.f.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      m.f.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.f.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  for (int j = 0; j < segments; ++j) m.f.push_back({south, ring(rings - 1, j + 1), ring(rings - 1, j)});
  return m;
}


}  // namespace steady_test
