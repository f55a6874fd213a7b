// Body validation: every error case with its code and message, valid meshes, adjacency, and the
// exact volume and area of a box.
#include <steady/sweep/body.hpp>

#include "sweep/sweep_test.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <set>

namespace {

using steady::ErrorCode;
using steady::sweep::Body;
using namespace steady_sweep_test;

Body make(const Mesh& m) { return Body(m.v, m.f); }

TEST(Body, EmptyMesh) {
  EXPECT_TRUE(throwsError([] { Body b({}, {}); }, ErrorCode::DegenerateInput, "empty \\(0 vertices, 0 faces\\)"));
  const Mesh c = box(V(0, 0, 0), V(1, 1, 1));
  EXPECT_TRUE(throwsError([&] { Body b(c.v, {}); }, ErrorCode::DegenerateInput, "empty \\(8 vertices, 0 faces\\)"));
}

TEST(Body, NonFiniteVertex) {
  Mesh c = box(V(0, 0, 0), V(1, 1, 1));
  c.v[3].y() = std::numeric_limits<double>::quiet_NaN();
  c.v[6].z() = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throwsError([&] { make(c); }, ErrorCode::NonFinite,
                          "2 vertices are not finite, the first is vertex 3 \\(1, nan, 0\\).*NaN/Inf"));
}

TEST(Body, FaceIndexOutOfRange) {
  Mesh c = box(V(0, 0, 0), V(1, 1, 1));
  c.f[2] = {4, 8, 6};
  c.f[7] = {-1, 6, 7};
  EXPECT_TRUE(throwsError([&] { make(c); }, ErrorCode::InvalidArgument,
                          "2 faces refer to vertices outside \\[0, 8\\), the first is face 2 \\(4, 8, 6\\); fix"));
}

TEST(Body, DegenerateFace) {
  Mesh c = box(V(0, 0, 0), V(1, 1, 1));
  c.f[5] = {1, 1, 4};  // repeated vertex
  EXPECT_TRUE(throwsError([&] { make(c); }, ErrorCode::DegenerateInput,
                          "1 face is degenerate \\(twice the area at most 1e-12 times the squared longest edge\\), "
                          "the first is face 5 \\(1, 1, 4\\); remove"));
  // Collinear vertices: a vertex moved onto the line of two others (up to rounding).
  Mesh d = box(V(0, 0, 0), V(1, 1, 1));
  d.v[2] = V(0.5, 0, 0);  // on the edge 0-1
  EXPECT_TRUE(throwsError([&] { make(d); }, ErrorCode::DegenerateInput, "the first is face 0 \\(0, 2, 1\\)"));
  steady::sweep::BodyOptions o;
  o.degenerate_tolerance = -1;
  EXPECT_TRUE(throwsError([&] { Body b(d.v, d.f, o); }, ErrorCode::InvalidArgument, "degenerate_tolerance"));
}

TEST(Body, OpenMesh) {
  Mesh c = box(V(0, 0, 0), V(1, 1, 1));
  c.f.erase(c.f.begin() + 1);  // face (1, 2, 3) of the bottom
  EXPECT_TRUE(throwsError([&] { make(c); }, ErrorCode::DegenerateInput,
                          "open: 3 boundary edges are used by one face only, the first is edge \\(1, 2\\) of face 0; close"));
}

TEST(Body, NonManifoldEdge) {
  // Two tetrahedra sharing the edge (0, 1): four faces on it.
  Mesh m;
  m.v = {V(0, 0, 0), V(1, 0, 0), V(0.5, 1, 0.2), V(0.5, 0.3, 1), V(0.5, -1, 0.2), V(0.5, -0.3, -1)};
  auto tet = [&](int a, int b, int c, int d) {
    const Faces t = {{a, b, c}, {a, d, b}, {a, c, d}, {b, d, c}};
    for (auto f : t) {
      const V n = (m.v[f[1]] - m.v[f[0]]).cross(m.v[f[2]] - m.v[f[0]]);
      const V cen = (m.v[a] + m.v[b] + m.v[c] + m.v[d]) / 4;
      if (n.dot(m.v[f[0]] - cen) < 0) std::swap(f[1], f[2]);
      m.f.push_back(f);
    }
  };
  tet(0, 1, 2, 3);
  tet(0, 1, 4, 5);
  EXPECT_TRUE(throwsError([&] { make(m); }, ErrorCode::DegenerateInput,
                          "not manifold: 1 edge is shared by more than two faces, the first is edge \\(0, 1\\) with 4 faces"));
}

TEST(Body, NonManifoldVertex) {
  // Two cubes touching at one corner: (1,1,1) of the first is (1,1,1) of the second, one vertex.
  Mesh a = box(V(0, 0, 0), V(1, 1, 1));
  const Mesh b = box(V(1, 1, 1), V(2, 2, 2));
  std::vector<int> map(8);
  for (int i = 0; i < 8; ++i) {
    if (i == 0) {
      map[i] = 7;  // b's corner 0 is a's corner 7
      continue;
    }
    map[i] = static_cast<int>(a.v.size());
    a.v.push_back(b.v[i]);
  }
  for (auto f : b.f) a.f.push_back({map[f[0]], map[f[1]], map[f[2]]});
  EXPECT_TRUE(throwsError([&] { make(a); }, ErrorCode::DegenerateInput,
                          "not manifold at 1 vertex .*more than one fan.*the first is vertex 7 with 2 fans; give each fan"));
}

TEST(Body, InconsistentOrientation) {
  Mesh c = box(V(0, 0, 0), V(1, 1, 1));
  std::swap(c.f[4][1], c.f[4][2]);  // face (0, 1, 4) -> (0, 4, 1)
  EXPECT_TRUE(throwsError([&] { make(c); }, ErrorCode::DegenerateInput,
                          "not consistently oriented: 3 edges are traversed twice in the same direction, "
                          "the first is edge 1 -> 0 in faces 0 and 4; reorient"));
}

TEST(Body, InwardOrientation) {
  const Mesh c = flipped(box(V(0, 0, 0), V(1, 1, 1)));
  EXPECT_TRUE(throwsError([&] { make(c); }, ErrorCode::InvalidArgument,
                          "oriented inward \\(signed volume -1 < 0\\); flip the faces"));
  const Mesh s = flipped(uvSphere(8, 12, 1.0));
  EXPECT_TRUE(throwsError([&] { make(s); }, ErrorCode::InvalidArgument, "flip the faces"));
}

TEST(Body, FlatClosedSurface) {
  Mesh m;
  m.v = {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)};
  m.f = {{0, 1, 2}, {0, 2, 1}};
  EXPECT_TRUE(throwsError([&] { make(m); }, ErrorCode::DegenerateInput, "encloses no volume"));
}

TEST(Body, ValidCube) {
  const Mesh c = box(V(-1, -1, -1), V(1, 1, 1));
  const Body b = make(c);
  EXPECT_EQ(b.edges().size(), 18u);
  EXPECT_DOUBLE_EQ(b.signedVolume(), 8.0);
  EXPECT_DOUBLE_EQ(b.area(), 24.0);
  EXPECT_DOUBLE_EQ(b.box().diagonal(), std::sqrt(12.0));
  // Each face normal is an axis direction pointing away from the centre.
  for (std::size_t f = 0; f < c.f.size(); ++f) {
    const V n = b.faceNormals()[f];
    EXPECT_NEAR(n.norm(), 1.0, 1e-15);
    EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0, 1e-15);
    EXPECT_GT(n.dot(c.v[c.f[f][0]]), 0.0);
  }
}

TEST(Body, ValidUvSphereAdjacency) {
  const Mesh s = uvSphere(10, 16, 2.0);
  const Body b = make(s);
  EXPECT_EQ(b.edges().size(), 3 * s.f.size() / 2);
  EXPECT_EQ(s.v.size() - b.edges().size() + s.f.size(), 2u);  // Euler characteristic
  EXPECT_GT(b.signedVolume(), 0.9 * 4.0 / 3.0 * M_PI * 8.0);
  EXPECT_LT(b.signedVolume(), 4.0 / 3.0 * M_PI * 8.0);
  // faces[0] runs v0 -> v1, faces[1] runs v1 -> v0, and faceEdges points back at the edge.
  for (std::size_t e = 0; e < b.edges().size(); ++e) {
    const auto& E = b.edges()[e];
    ASSERT_LT(E.vertices[0], E.vertices[1]);
    for (int side = 0; side < 2; ++side) {
      const auto& f = s.f[E.faces[side]];
      int k = 0;
      while (f[k] != E.vertices[side]) ++k;
      EXPECT_EQ(f[(k + 1) % 3], E.vertices[1 - side]) << "edge " << e << " side " << side;
      EXPECT_EQ(b.faceEdges()[E.faces[side]][k], static_cast<int>(e));
    }
  }
  for (std::size_t f = 0; f < s.f.size(); ++f) {
    const V cen = (s.v[s.f[f][0]] + s.v[s.f[f][1]] + s.v[s.f[f][2]]) / 3;
    EXPECT_GT(b.faceNormals()[f].dot(cen.normalized()), 0.9);
  }
}

TEST(Body, BoxVolumeAndAreaExact) {
  const Body b = make(box(V(1, -2, 0.5), V(3, 1, 4.5)));  // 2 x 3 x 4
  EXPECT_DOUBLE_EQ(b.signedVolume(), 24.0);
  EXPECT_DOUBLE_EQ(b.area(), 52.0);
}

TEST(Body, CavityIsAccepted) {
  // An outer cube with an inward-oriented inner cube (a cavity): positive total volume.
  Mesh m = box(V(-2, -2, -2), V(2, 2, 2));
  const Mesh in = flipped(box(V(-1, -1, -1), V(1, 1, 1)));
  for (const V& p : in.v) m.v.push_back(p);
  for (auto f : in.f) m.f.push_back({f[0] + 8, f[1] + 8, f[2] + 8});
  const Body b = make(m);
  EXPECT_DOUBLE_EQ(b.signedVolume(), 64.0 - 8.0);
}

}  // namespace
