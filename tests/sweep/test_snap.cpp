// The merging of vertices a rounding apart in the envelope's output stage (sweep/src/snap.hpp),
// against a brute-force oracle: every pair of vertices compared, classes by union-find.
#include "snap.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

namespace {

using steady::sweep::detail::kSnap;
using steady::sweep::detail::snapVertices;
using V3 = Eigen::Vector3d;
using Tri = std::array<int, 3>;

int root(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x];
  return x;
}

// The classes of the vertices within delta of each other (L-infinity), by all pairs.
std::vector<int> oracleClasses(const std::vector<V3>& V, double delta) {
  std::vector<int> parent(V.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t i = 0; i < V.size(); ++i)
    for (std::size_t j = i + 1; j < V.size(); ++j)
      if ((V[i] - V[j]).cwiseAbs().maxCoeff() <= delta)
        parent[root(parent, static_cast<int>(j))] = root(parent, static_cast<int>(i));
  std::vector<int> out(V.size());
  for (std::size_t i = 0; i < V.size(); ++i) out[i] = root(parent, static_cast<int>(i));
  return out;
}

// Seeded property: clusters of points placed at up to 0.999 delta from a centre along each axis
// (so that their cells differ, often on every axis), near points just beyond delta, and
// scattered points. The merged count, the surviving triangles and the merged positions agree
// with the oracle's classes.
TEST(Snap, MergesExactlyThePairsWithinTheToleranceAcrossCells) {
  std::mt19937_64 rng(20261201);
  std::uniform_real_distribution<double> unit(-1, 1), side(0.0, 1.0);
  int merged_total = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<V3> V;
    // (the box is [-1, 1]^3 or so: its diagonal is about 3.46, and delta kSnap times it)
    V.push_back(V3(-1, -1, -1));
    V.push_back(V3(1, 1, 1));
    const double delta = kSnap * (V[1] - V[0]).norm();
    for (int c = 0; c < 60; ++c) {
      const V3 centre(unit(rng), unit(rng), unit(rng));
      V.push_back(centre);
      const int extra = static_cast<int>(side(rng) * 4);
      for (int k = 0; k < extra; ++k) {
        V3 d;
        for (int a = 0; a < 3; ++a) d[a] = (side(rng) < 0.5 ? -1 : 1) * delta * (k % 2 ? 0.999 : side(rng));
        V.push_back(centre + d);
      }
      // just beyond delta on one axis: never merged with the centre directly
      V3 far = centre;
      far[static_cast<int>(side(rng) * 3)] += 1.01 * delta * (side(rng) < 0.5 ? -1 : 1);
      V.push_back(far);
    }
    // (make sure the box stays [-1, 1]^3: every point lies within it up to 2 delta)
    for (V3& x : V) x = x.cwiseMax(V3::Constant(-1)).cwiseMin(V3::Constant(1));
    std::vector<Tri> T;
    for (int i = 0; i + 2 < static_cast<int>(V.size()); ++i) T.push_back({{i, i + 1, i + 2}});
    const std::vector<int> cls = oracleClasses(V, delta);
    std::size_t expect_merged = 0;
    for (std::size_t i = 0; i < V.size(); ++i) expect_merged += cls[i] != static_cast<int>(i);
    std::vector<V3> out_v = V;
    std::vector<Tri> out_t = T;
    const std::size_t merged = snapVertices(out_v, out_t);
    ASSERT_EQ(merged, expect_merged) << "trial " << trial;
    merged_total += static_cast<int>(merged);
    if (merged == 0) continue;
    // The triangles that survive are those whose corners lie in three classes, in order, and
    // each corner sits at a position of its class.
    std::vector<Tri> expect;
    for (const Tri& t : T)
      if (cls[t[0]] != cls[t[1]] && cls[t[1]] != cls[t[2]] && cls[t[2]] != cls[t[0]]) expect.push_back(t);
    ASSERT_EQ(out_t.size(), expect.size()) << "trial " << trial;
    for (std::size_t f = 0; f < expect.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        const V3& got = out_v[static_cast<std::size_t>(out_t[f][k])];
        bool in_class = false;
        for (std::size_t i = 0; i < V.size() && !in_class; ++i) in_class = cls[i] == cls[expect[f][k]] && V[i] == got;
        ASSERT_TRUE(in_class) << "trial " << trial << ", triangle " << f << ", corner " << k;
      }
    // Two corners of different classes never share a position.
    for (const Tri& t : out_t) EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[2] != t[0]);
  }
  EXPECT_GT(merged_total, 1000);  // (the clusters do merge)
}

TEST(Snap, NothingWithinTheToleranceLeavesTheMeshAlone) {
  std::vector<V3> V = {V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), V3(0, 0, 1)};
  std::vector<Tri> T = {{{0, 2, 1}}, {{0, 1, 3}}, {{1, 2, 3}}, {{0, 3, 2}}};
  const auto V0 = V;
  const auto T0 = T;
  EXPECT_EQ(snapVertices(V, T), 0u);
  EXPECT_EQ(V, V0);
  EXPECT_EQ(T, T0);
}

}  // namespace
