// Vertices that the certificate could not place within ε of the true boundary, moved onto it
// where that is safe (detail::settleVertices, trim.cpp). The region is a half-space or a box
// given by its exact inside test, the surface a cube whose top is a fan about a vertex dented
// 1.2 ε into the region. Known answers: the vertex lands on the boundary within the bisection's
// bracket; a move that would make its faces cross another face is refused, or taken short of
// the boundary where that clears the face; a move that turns a face over is refused for the
// next direction, and one into the region that the surface encloses only goes up to ε; a vertex
// that cannot move keeps its coordinates exactly.
#include "settle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

using Vec = Eigen::Vector3d;
using Tri = std::array<int, 3>;
using steady::sweep::detail::kSettleBracket;
using steady::sweep::detail::settleVertices;

constexpr double kEps = 0.01;

// The cube [-1, 1]³, outward, with its top (z = 1) a fan of four faces about vertex 8 at
// (0, 0, top).
struct DentedCube {
  std::vector<Vec> V;
  std::vector<Tri> T;
  explicit DentedCube(double top) {
    for (const double z : {-1.0, 1.0}) {
      V.emplace_back(-1, -1, z);
      V.emplace_back(1, -1, z);
      V.emplace_back(1, 1, z);
      V.emplace_back(-1, 1, z);
    }
    V.emplace_back(0, 0, top);
    T = {{{0, 2, 1}}, {{0, 3, 2}}, {{0, 1, 5}}, {{0, 5, 4}}, {{1, 2, 6}}, {{1, 6, 5}}, {{2, 3, 7}},
         {{2, 7, 6}}, {{3, 0, 4}}, {{3, 4, 7}}, {{8, 4, 5}}, {{8, 5, 6}}, {{8, 6, 7}}, {{8, 7, 4}}};
  }
  // A small tetrahedron (a shell of its own) whose bottom face, at height z, lies over the fan's
  // vertex: 0.1 across, apex 0.1 above.
  void addTetrahedronAbove(double z) {
    const int b = static_cast<int>(V.size());
    V.emplace_back(-0.05, -0.05, z);
    V.emplace_back(0.05, -0.05, z);
    V.emplace_back(0.0, 0.05, z);
    V.emplace_back(0.0, 0.0, z + 0.1);
    T.push_back({{b, b + 2, b + 1}});
    T.push_back({{b, b + 1, b + 3}});
    T.push_back({{b + 1, b + 2, b + 3}});
    T.push_back({{b + 2, b, b + 3}});
  }
};

bool insideBox(const Vec& p) { return p.cwiseAbs().maxCoeff() <= 1.0; }

TEST(SettleVertices, MovesADentedVertexOntoTheBoundary) {
  DentedCube c(1 - 1.2 * kEps);
  const std::vector<Vec> before = c.V;
  const Vec x = c.V[8];
  const std::size_t moved = settleVertices(c.V, c.T, {{8, x + Vec(0, 0, 1.25 * kEps)}}, insideBox, kEps);
  EXPECT_EQ(moved, 1u);
  // (the crossing found by bisection lies within half the bracket of z = 1)
  EXPECT_LE(std::abs(c.V[8].z() - 1), 0.5 * kSettleBracket * kEps);
  EXPECT_EQ(c.V[8].x(), 0.0);
  EXPECT_EQ(c.V[8].y(), 0.0);
  for (int v = 0; v < 8; ++v) EXPECT_EQ(c.V[static_cast<std::size_t>(v)], before[static_cast<std::size_t>(v)]);
}

TEST(SettleVertices, RefusesEveryMoveThatMakesItsFacesCrossAnotherFace) {
  DentedCube c(1 - 1.2 * kEps);
  // Every allowed target (the crossing, and 0.5 or 0.85 ε short of it) lies above the
  // tetrahedron's bottom at 1 - ε, every direction that reaches the boundary within 1.25 ε goes
  // up through it.
  c.addTetrahedronAbove(1 - kEps);
  const std::vector<Vec> before = c.V;
  const std::size_t moved = settleVertices(c.V, c.T, {{8, c.V[8] + Vec(0, 0, 1.25 * kEps)}}, insideBox, kEps);
  EXPECT_EQ(moved, 0u);
  EXPECT_EQ(c.V, before);  // (exactly where it was)
}

TEST(SettleVertices, StopsShortOfTheBoundaryWhereThatClearsTheFace) {
  DentedCube c(1 - 1.2 * kEps);
  // The tetrahedron's bottom at 1 - 0.7 ε: the crossing and 0.5 ε short of it would put the
  // vertex above it, 0.85 ε short below it.
  c.addTetrahedronAbove(1 - 0.7 * kEps);
  const std::size_t moved = settleVertices(c.V, c.T, {{8, c.V[8] + Vec(0, 0, 1.25 * kEps)}}, insideBox, kEps);
  EXPECT_EQ(moved, 1u);
  EXPECT_NEAR(c.V[8].z(), 1 - 0.85 * kEps, 0.5 * kSettleBracket * kEps);
  EXPECT_EQ(c.V[8].x(), 0.0);
  EXPECT_EQ(c.V[8].y(), 0.0);
}

TEST(SettleVertices, RefusesAMoveThatTurnsAFaceOver) {
  // The region z <= 3; the probe across it lies beyond the cube's side x = 1, so the crossing
  // on the way to it (x about 1.36, z = 3) would turn face (8, 5, 6) over: the tent over the
  // cube would then cross nothing, so only the turn refuses it. The next directions tried are
  // the normals of the fan's faces, nearly straight up: the vertex lands near (0, 0, 3).
  DentedCube c(1 - 1.2 * kEps);
  auto below = [](const Vec& p) { return p.z() <= 3.0; };
  const Vec y = c.V[8] + Vec(1.5, 0, 2.2);
  const std::size_t moved = settleVertices(c.V, c.T, {{8, y}}, below, kEps);
  EXPECT_EQ(moved, 1u);
  EXPECT_LE(std::abs(c.V[8].z() - 3), 0.5 * kSettleBracket * kEps);
  EXPECT_LT(c.V[8].head<2>().cwiseAbs().maxCoeff(), 0.1) << c.V[8].transpose();
}

TEST(SettleVertices, MovesTheSurfaceIntoTheRegionItEnclosesByEpsAtMost) {
  // The region lies above a plane below the dented vertex (which is inside it), so the boundary
  // lies into the cube. 2 ε below: the crossing and the points 0.5 and 0.85 ε short of it are
  // all more than ε away, so the vertex stays, although no move turns or crosses a face.
  {
    DentedCube c(1 - 1.2 * kEps);
    auto above = [](const Vec& p) { return p.z() >= 1 - 3.2 * kEps; };
    const std::vector<Vec> before = c.V;
    EXPECT_EQ(settleVertices(c.V, c.T, {{8, c.V[8] - Vec(0, 0, 2.5 * kEps)}}, above, kEps), 0u);
    EXPECT_EQ(c.V, before);
  }
  // 0.8 ε below: the crossing is taken.
  {
    DentedCube c(1 - 1.2 * kEps);
    auto above = [](const Vec& p) { return p.z() >= 1 - 2 * kEps; };
    EXPECT_EQ(settleVertices(c.V, c.T, {{8, c.V[8] - Vec(0, 0, 1.25 * kEps)}}, above, kEps), 1u);
    EXPECT_NEAR(c.V[8].z(), 1 - 2 * kEps, 0.5 * kSettleBracket * kEps);
  }
}

TEST(SettleVertices, LeavesAVertexWhoseProbeIsOnItsOwnSide) {
  // The probe must get the other answer than the vertex; one on the same side moves nothing.
  DentedCube c(1 - 1.2 * kEps);
  const std::vector<Vec> before = c.V;
  EXPECT_EQ(settleVertices(c.V, c.T, {{8, c.V[8] + Vec(0, 0, 0.5 * kEps)}}, insideBox, kEps), 0u);
  EXPECT_EQ(c.V, before);
}

}  // namespace
