#pragma once
// Cap slivers left by rounding: an envelope triangle (a, b, v) whose corner v lies on its side
// ab up to rounding. Internal to steady::sweep (trim.cpp, after the output check).
//
// Where they come from: a face of the exact arrangement is triangulated with the points where
// other faces cut it, and a point constructed a few units of 2^-53 off a side of the face gives
// a triangle whose height is that distance. Rounded to doubles, its corner falls on the side or
// past it, and the triangle overlaps its neighbour across the side: a self-intersecting pair.
// Planar motions of prisms, whose top and bottom faces slide in their planes, made such pairs:
// the bundled box turning a quarter about z while moving in x and y, at ε = 1e-3 of its
// diagonal, had 55 (stop 60).
//
// The cure moves no vertex: the side ab is flipped to the diagonal vw, w the far corner of the
// neighbour (b, a, w) across it. Since v lies on ab (within the height), the two new triangles
// (v, a, w) and (v, w, b) cover the neighbour's triangle and the sliver's area is gone; the
// surface moves by at most the sliver's height. A flip is made only where the two triangles
// alone hold each of their sides (manifold there), vw is not already an edge, and both new
// triangles face the way the neighbour did.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace steady::sweep::detail {

// Flips the cap slivers of the closed triangle mesh (V, T) (see the file comment): triangles
// whose corner lies within `height` of its opposite side and within 1e-9 of that side's length,
// strictly between the side's ends (by more than `height`). Returns the number of flips. A few
// passes, since a flip can leave another sliver against a new diagonal.
inline std::size_t flipCapSlivers(const std::vector<Eigen::Vector3d>& V, std::vector<std::array<int, 3>>& T,
                                  double height) {
  using Vec = Eigen::Vector3d;
  const auto key = [](int a, int b) {
    return static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32 | static_cast<std::uint32_t>(b);
  };
  // directed edge -> face, or -1 where several faces hold it
  std::unordered_map<std::uint64_t, int> face_of;
  face_of.reserve(T.size() * 3);
  const auto file = [&](std::size_t f) {
    for (int k = 0; k < 3; ++k) {
      const auto [it, added] = face_of.emplace(key(T[f][k], T[f][(k + 1) % 3]), static_cast<int>(f));
      if (!added) it->second = -1;
    }
  };
  const auto unfile = [&](std::size_t f) {
    for (int k = 0; k < 3; ++k) face_of.erase(key(T[f][k], T[f][(k + 1) % 3]));
  };
  for (std::size_t f = 0; f < T.size(); ++f) file(f);
  const auto normal = [&](int a, int b, int c) { return Vec((V[b] - V[a]).cross(V[c] - V[a])); };
  std::size_t flips = 0;
  for (int pass = 0; pass < 4; ++pass) {
    std::size_t flipped = 0;
    for (std::size_t f = 0; f < T.size(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const int a = T[f][k], b = T[f][(k + 1) % 3], v = T[f][(k + 2) % 3];
        const Vec e = V[b] - V[a];
        const double len2 = e.squaredNorm();
        if (!(len2 > 0)) continue;
        const double s = (V[v] - V[a]).dot(e) / len2, len = std::sqrt(len2);
        if (!(s * len > height && (1 - s) * len > height)) continue;  // not strictly between a and b
        const double h = (V[v] - V[a] - s * e).norm();
        if (!(h <= height && h <= 1e-9 * len)) continue;
        const auto it = face_of.find(key(b, a));
        if (it == face_of.end() || it->second < 0) continue;  // (not manifold here)
        const auto g = static_cast<std::size_t>(it->second);
        int w = -1;
        for (int j = 0; j < 3; ++j)
          if (T[g][j] != a && T[g][j] != b) w = T[g][j];
        if (w < 0 || w == v || face_of.count(key(v, w)) || face_of.count(key(w, v))) continue;
        bool owned = true;  // (each side of both held by its face alone: refiling keeps the map exact)
        for (const std::size_t x : {f, g})
          for (int j = 0; j < 3; ++j) owned = owned && face_of.at(key(T[x][j], T[x][(j + 1) % 3])) == static_cast<int>(x);
        if (!owned) continue;
        const Vec ng = normal(b, a, w);
        if (!(normal(v, a, w).dot(ng) > 0 && normal(v, w, b).dot(ng) > 0)) continue;
        unfile(f);
        unfile(g);
        T[f] = {{v, a, w}};
        T[g] = {{v, w, b}};
        file(f);
        file(g);
        ++flipped;
        break;  // (face f changed: its other sides are looked at on the next pass)
      }
    }
    flips += flipped;
    if (flipped == 0) break;
  }
  return flips;
}

}  // namespace steady::sweep::detail
