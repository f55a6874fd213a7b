// The step of the envelope's output that moves apart the copies of pinched vertices
// (sweep/src/pinches.hpp): small solids touching at a point, overlapping solids that cannot be
// moved apart, and a patch cut from a real envelope (knot1 along data/motions/keys.json) where
// two sheets touch along an edge and no single direction per pinch separates them, and one cut
// from another (armadillo along data/motions/screw.json) where a pinch put back voided the test
// its neighbour had passed.
#include "pinches.hpp"

#include <steady/sweep/envelope.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <string>

namespace {

using steady::sweep::inspectMesh;
using steady::sweep::detail::separatePinches;
using V3 = Eigen::Vector3d;
using Tri = std::array<int, 3>;

struct Patch {
  std::vector<V3> vertices;
  std::vector<Tri> triangles;
};

// An OFF file of triangles, read with full double precision (the fixtures write 17 digits).
Patch readOff(const std::string& path) {
  std::ifstream in(path);
  std::string magic;
  std::size_t nv = 0, nf = 0, ne = 0;
  in >> magic >> nv >> nf >> ne;
  Patch p;
  p.vertices.resize(nv);
  for (V3& v : p.vertices) in >> v.x() >> v.y() >> v.z();
  p.triangles.resize(nf);
  for (Tri& t : p.triangles) {
    int corners = 0;
    in >> corners >> t[0] >> t[1] >> t[2];
    EXPECT_EQ(corners, 3);
  }
  EXPECT_TRUE(in) << "could not read " << path;
  return p;
}

// The tetrahedron with apex `apex` over the triangle (a, b, c) (counter-clockwise seen from
// the apex's side), outward oriented, appended to p.
void addTetrahedron(Patch& p, const V3& apex, const V3& a, const V3& b, const V3& c) {
  const int o = static_cast<int>(p.vertices.size());
  p.vertices.insert(p.vertices.end(), {apex, a, b, c});
  p.triangles.insert(p.triangles.end(), {Tri{o + 1, o + 3, o + 2}, Tri{o, o + 1, o + 2}, Tri{o, o + 2, o + 3}, Tri{o, o + 3, o + 1}});
}

// How many vertices share their position with another.
std::size_t sharing(const std::vector<V3>& v) {
  std::map<std::array<double, 3>, int> count;
  for (const V3& x : v) ++count[{x.x(), x.y(), x.z()}];
  std::size_t n = 0;
  for (const auto& [x, c] : count) n += c > 1 ? c : 0;
  return n;
}

double largestMove(const std::vector<V3>& a, const std::vector<V3>& b) {
  double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, (a[i] - b[i]).norm());
  return m;
}

// Two tetrahedra touching at their apexes (one point, the second turned upside down): each copy
// steps into its own solid, and they no longer meet.
TEST(SeparatePinches, TetrahedraTouchingAtAPointAreMovedApart) {
  Patch p;
  const V3 o(0, 0, 0);
  addTetrahedron(p, o, V3(-1, -1, 1), V3(1, -1, 1), V3(0, 1, 1));
  addTetrahedron(p, o, V3(-1, -1, -1), V3(0, 1, -1), V3(1, -1, -1));
  ASSERT_GT(inspectMesh(p.vertices, p.triangles, true).self_intersections, 0);
  std::vector<V3> moved = p.vertices;
  const double eps = 0.01;
  EXPECT_EQ(separatePinches(moved, p.triangles, eps, 1), 0u);
  EXPECT_EQ(sharing(moved), 0u);
  EXPECT_EQ(inspectMesh(moved, p.triangles, true).self_intersections, 0);
  EXPECT_GT(largestMove(moved, p.vertices), 0.0);
  EXPECT_LE(largestMove(moved, p.vertices), 1e-3 * eps * (1 + 1e-12));
  EXPECT_GT(moved[0].z(), 0.0);  // into the upper solid
  EXPECT_LT(moved[4].z(), 0.0);
}

// Two tetrahedra whose interiors overlap near the shared apex: no step of at most 1e-3 ε takes
// them apart, so the copies are put back and reported.
TEST(SeparatePinches, OverlappingSolidsArePutBackAndCounted) {
  Patch p;
  const V3 o(0, 0, 0);
  addTetrahedron(p, o, V3(-1, -1, 1), V3(1, -1, 1), V3(0, 1, 1));
  addTetrahedron(p, o, V3(-1, 1, 1), V3(0, -1, 1.2), V3(1, 1, 1));
  std::vector<V3> moved = p.vertices;
  EXPECT_EQ(separatePinches(moved, p.triangles, 0.01, 1), 1u);  // (the second copy)
  EXPECT_EQ(moved, p.vertices);
}

// A patch cut from an envelope just before this step: every copy is moved apart (no shared
// position, no crossing), by at most 1e-3 ε (times 1 + `slack` for the rounding of the moved
// positions), vertices at no pinch stay, and two threads give the same positions as one.
void expectSeparated(const Patch& p, double eps, double slack) {
  std::vector<V3> one = p.vertices, two = p.vertices;
  EXPECT_EQ(separatePinches(one, p.triangles, eps, 1), 0u);
  EXPECT_EQ(sharing(one), 0u);
  EXPECT_EQ(inspectMesh(one, p.triangles, true).self_intersections, 0);
  EXPECT_LE(largestMove(one, p.vertices), 1e-3 * eps * (1 + slack));
  for (std::size_t i = 0; i < one.size(); ++i) {
    if (std::count(p.vertices.begin(), p.vertices.end(), p.vertices[i]) == 1) {
      EXPECT_EQ(one[i], p.vertices[i]) << "vertex " << i << " is at no pinch";
    }
  }
  separatePinches(two, p.triangles, eps, 2);
  EXPECT_EQ(one, two);
}

// 68 faces around two pinches of the envelope of knot1 (CGAL's sample, at its own size) along
// data/motions/keys.json at ε = 1e-3 of its diagonal, cut out just before this step: two
// groups of two copies 19 ε apart, joined by two edges (two sheets touching along a segment),
// with every face within a few degrees of one plane. Each group's directions fail whatever the
// step: moving both copies slides one sheet along the other, and moving one copy per group
// moved one sheet at one end and the other sheet at the other. One sheet moved at both ends
// (or other combinations per copy) separates them; before, the envelope kept 52 crossing
// pairs and failed its check.
TEST(SeparatePinches, SheetsTouchingAlongAnEdgeAreSeparated) {
  const Patch p = readOff(STEADY_TEST_FIXTURES "/pinched_edge.off");
  ASSERT_EQ(p.triangles.size(), 68u);
  ASSERT_EQ(sharing(p.vertices), 4u);
  ASSERT_GT(inspectMesh(p.vertices, p.triangles, true).self_intersections, 0);
  expectSeparated(p, 0.001462149762349945, 1e-12);
}

// 441 faces around two pinches of the envelope of CGAL's armadillo (at its own size) along
// data/motions/screw.json at ε = 1e-3 of its diagonal, cut out just before this step (the faces
// with a corner within 4 of the first pinch). Group A (the first pinch, two copies: a narrow
// spike and a sheet) is joined by an edge of the spike to group B. In the rounds, B moved while A
// tried its directions; A then failed every one and was put back, and B's moved copy, tested
// only against A's moved faces, left two faces of A's spike crossing each other (the envelope
// kept 30 crossing pairs and failed its check). The moved copies' faces are now tested again at
// the final positions: B starts over with A fixed, and the cluster of A and B is then retried.
TEST(SeparatePinches, NeighbourPutBackAfterAGroupMovedIsRechecked) {
  const Patch p = readOff(STEADY_TEST_FIXTURES "/folded_fan.off");
  ASSERT_EQ(p.triangles.size(), 441u);
  ASSERT_GT(sharing(p.vertices), 0u);
  // (coordinates near 75, whose ulp is 1.4e-14, round the moves of 2.3e-4 by up to 1e-10 of them)
  expectSeparated(p, 0.2288024820262228, 1e-9);
}

}  // namespace
