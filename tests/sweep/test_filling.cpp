// The cutting step of the refinement of deep mouth fillings (detail::bisectFilling, trim.cpp):
// on a flat square and on the filling that made the step run away (campaign case 2819), the
// result is checked for what the step promises: a closed fan of faces over the same loop and
// area, points at least h/2 apart, and no edge left that the rule would still cut. And the shape
// by which the mouth rounds remember fillings (detail::FillingShape): the same for the same
// filling numbered anew in the same order, whose cut is then the same; different when a
// coordinate, the order of the numbers or the faces differ.
#include "filling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace {

using Vec = Eigen::Vector3d;
using Tri = std::array<int, 3>;
using steady::sweep::detail::bisectFilling;
using steady::sweep::detail::FillingShape;
using steady::sweep::detail::shapeOf;

double toLoop(const std::vector<Vec>& V, const std::vector<int>& loop, const Vec& x) {
  double d = HUGE_VAL;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Vec& a = V[static_cast<std::size_t>(loop[i])];
    const Vec ab = V[static_cast<std::size_t>(loop[(i + 1) % loop.size()])] - a;
    const double u = std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    d = std::min(d, (a + u * ab - x).norm());
  }
  return d;
}

double area(const std::vector<Vec>& P, const std::vector<Tri>& F) {
  double s = 0;
  for (const Tri& t : F) s += 0.5 * (P[t[1]] - P[t[0]]).cross(P[t[2]] - P[t[0]]).norm();
  return s;
}

// Checks the promises of bisectFilling on its output (faces over V followed by fresh).
void expectCut(const std::vector<Vec>& V, const std::vector<int>& loop, const std::vector<Tri>& before,
               const std::vector<Tri>& faces, const std::vector<Vec>& fresh, double h) {
  std::vector<Vec> P = V;
  P.insert(P.end(), fresh.begin(), fresh.end());
  // The same area (the new points are middles of edges of the flat faces).
  EXPECT_NEAR(area(P, faces), area(V, before), 1e-12 * area(V, before));
  // A fan over the loop: each loop edge used once, in the direction of the original faces;
  // every other edge used twice, once each way.
  std::map<std::pair<int, int>, int> uses;
  for (const Tri& t : faces)
    for (int k = 0; k < 3; ++k) ++uses[{t[k], t[(k + 1) % 3]}];
  std::map<std::pair<int, int>, int> loop_dir;
  for (const Tri& t : before)
    for (int k = 0; k < 3; ++k) loop_dir[{t[k], t[(k + 1) % 3]}] = 1;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const int a = loop[i], b = loop[(i + 1) % loop.size()];
    const std::pair<int, int> e = loop_dir.count({a, b}) ? std::make_pair(a, b) : std::make_pair(b, a);
    EXPECT_EQ(uses[e], 1) << "loop edge " << a << "-" << b;
    const std::pair<int, int> back(e.second, e.first);
    EXPECT_EQ(uses[back], 0) << "loop edge " << a << "-" << b;
    uses.erase(e);
  }
  for (const auto& [e, n] : uses) {
    if (n == 0) continue;
    EXPECT_EQ(n, 1) << "edge " << e.first << "-" << e.second;
    const auto back = uses.find({e.second, e.first});
    EXPECT_TRUE(back != uses.end() && back->second == 1) << "inner edge " << e.first << "-" << e.second << " has one face";
  }
  // Points at least h/2 apart: each new point from every point of the filling.
  std::vector<int> corners;
  for (const Tri& t : before) corners.insert(corners.end(), t.begin(), t.end());
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  std::vector<Vec> points;
  for (const int v : corners) points.push_back(V[static_cast<std::size_t>(v)]);
  for (const Vec& x : fresh) {
    for (const Vec& y : points) ASSERT_GE((x - y).norm(), 0.5 * h);
    points.push_back(x);
  }
  // Nothing left to cut: an inner edge longer than h has its middle within h/2 of the loop or
  // of a point.
  for (const auto& [e, n] : uses) {
    if (n == 0 || e.first > e.second) continue;
    const Vec& a = P[static_cast<std::size_t>(e.first)];
    const Vec& b = P[static_cast<std::size_t>(e.second)];
    if ((a - b).norm() <= h) continue;
    const Vec m = 0.5 * (a + b);
    double nearest = HUGE_VAL;
    for (const Vec& y : points) nearest = std::min(nearest, (m - y).norm());
    EXPECT_TRUE(toLoop(V, loop, m) <= 0.5 * h || nearest < 0.5 * h)
        << "edge " << e.first << "-" << e.second << " of length " << (a - b).norm() / h << " h left uncut";
  }
}

TEST(BisectFilling, CutsAFlatSquareDownToTheGivenLength) {
  const std::vector<Vec> V = {Vec(0, 0, 0), Vec(10, 0, 0), Vec(10, 10, 0), Vec(0, 10, 0)};
  const std::vector<int> loop = {0, 1, 2, 3};
  const std::vector<Tri> before = {{{0, 1, 2}}, {{0, 2, 3}}};
  std::vector<Tri> faces = before;
  std::vector<Vec> fresh;
  const double h = 1.0;
  ASSERT_TRUE(bisectFilling(V, loop, faces, fresh, h, 4096));
  // At most 16 / pi points per h² (discs of radius h/4 about points h/2 apart do not overlap),
  // and the loop's strip of h/2 stays free of cuts: well below that, well above none.
  EXPECT_GT(fresh.size(), 20u);
  EXPECT_LE(static_cast<double>(fresh.size()), 16 / M_PI * 100);
  expectCut(V, loop, before, faces, fresh, h);
  // Too few points allowed: refused.
  std::vector<Tri> small = before;
  EXPECT_FALSE(bisectFilling(V, loop, small, fresh, h, 10));
}

// The filling of a deep mouth of a bracket polySAM (campaign case 2819, ε = 0.0128): 11 loop
// points and 9 faces, a long strip whose faces have their longest edges on the loop. Cut at
// h = ε, it ran past 200,000 points before the rule on crowded middles (and failed at the cap
// of 4,096 that the sweep sets).
TEST(BisectFilling, FacesWithTheirLongestEdgesOnTheLoopStopBeingCut) {
  const std::vector<std::pair<int, Vec>> points = {
      {265, Vec(0.87445068961751726, -1.9215747171810407, 0.5974121012829654)},
      {273, Vec(0.91917572078600962, -1.9450561777869217, 0.6079992443910851)},
      {1300, Vec(0.67382253451090679, -2.0018748768867338, 0.57179380425859094)},
      {1302, Vec(0.46683410168065687, -2.0673451205505877, 0.55677697097910883)},
      {1304, Vec(0.25506412797902461, -2.1172208177995917, 0.55209055710420762)},
      {1312, Vec(0.16807100831385163, -2.1729206031349388, 0.56318327425800141)},
      {1313, Vec(0.21995567398454685, -2.171510386648384, 0.56388933289834231)},
      {2115, Vec(0.86409670019286555, -1.9070759785611417, 0.56183265229582346)},
      {2118, Vec(0.66312014841040967, -1.9877363399026786, 0.53617251269709698)},
      {2121, Vec(0.45575578359532809, -2.0535401971754417, 0.52113976194403988)},
      {2124, Vec(0.24636989156492106, -2.1031704103018822, 0.51645926779629237)}};
  std::map<int, int> index;
  std::vector<Vec> V;
  for (const auto& [id, x] : points) index[id] = static_cast<int>(V.size()), V.push_back(x);
  std::vector<int> loop;
  for (const int id : {1312, 1313, 2124, 2121, 2118, 2115, 273, 265, 1300, 1302, 1304}) loop.push_back(index.at(id));
  std::vector<Tri> before;
  for (const Tri& t : std::vector<Tri>{{{1312, 1304, 1302}}, {{1312, 1302, 273}}, {{273, 1302, 1300}},
                                       {{273, 1300, 265}}, {{1312, 273, 1313}}, {{1313, 273, 2121}},
                                       {{2121, 273, 2118}}, {{2118, 273, 2115}}, {{1313, 2121, 2124}}})
    before.push_back({{index.at(t[0]), index.at(t[1]), index.at(t[2])}});
  const double h = 0.012806248474865698;
  std::vector<Tri> faces = before;
  std::vector<Vec> fresh;
  ASSERT_TRUE(bisectFilling(V, loop, faces, fresh, h, 4096)) << "ran past 4,096 points";
  EXPECT_LE(static_cast<double>(fresh.size()), 16 / M_PI * area(V, before) / (h * h));
  expectCut(V, loop, before, faces, fresh, h);
}

// A filling and its cut, in the shape's numbers: the points of the shape, then the fresh ones.
struct LocalCut {
  std::vector<Vec> fresh;
  std::vector<Tri> faces;
};
LocalCut cutInShape(const std::vector<Vec>& V, const std::vector<int>& loop, const std::vector<Tri>& before,
                    const FillingShape& shape, double h) {
  std::vector<Tri> faces = before;
  LocalCut c;
  EXPECT_TRUE(bisectFilling(V, loop, faces, c.fresh, h, 4096));
  std::map<int, int> local;
  for (std::size_t k = 0; k < shape.global.size(); ++k) local[shape.global[k]] = static_cast<int>(k);
  const int base = static_cast<int>(V.size()), n = static_cast<int>(shape.global.size());
  for (const Tri& t : faces) {
    Tri u;
    for (int k = 0; k < 3; ++k) u[k] = t[k] < base ? local.at(t[k]) : n + (t[k] - base);
    c.faces.push_back(u);
  }
  return c;
}

// The square of CutsAFlatSquareDownToTheGivenLength (whose cut meets many equally long edges)
// numbered 0-3, and again among other points as 1, 3, 4 and 6: the same shape and hash, and
// the same cut, point for point and face for face.
TEST(FillingShape, IsTheSameForTheFillingNumberedAnewInTheSameOrder) {
  const std::vector<Vec> square = {Vec(0, 0, 0), Vec(10, 0, 0), Vec(10, 10, 0), Vec(0, 10, 0)};
  const std::vector<int> loop = {0, 1, 2, 3};
  const std::vector<Tri> before = {{{0, 1, 2}}, {{0, 2, 3}}};
  const std::vector<int> to = {1, 3, 4, 6};
  std::vector<Vec> V2(8, Vec(-5, 7, 1));
  for (int k = 0; k < 4; ++k) V2[static_cast<std::size_t>(to[k])] = square[static_cast<std::size_t>(k)];
  std::vector<int> loop2;
  for (const int v : loop) loop2.push_back(to[static_cast<std::size_t>(v)]);
  std::vector<Tri> before2;
  for (const Tri& t : before)
    before2.push_back({{to[static_cast<std::size_t>(t[0])], to[static_cast<std::size_t>(t[1])], to[static_cast<std::size_t>(t[2])]}});
  const FillingShape a = shapeOf(square, loop, before), b = shapeOf(V2, loop2, before2);
  EXPECT_TRUE(a == b);
  EXPECT_EQ(a.hash, b.hash);
  EXPECT_EQ(b.global, to);
  const LocalCut ca = cutInShape(square, loop, before, a, 1.0), cb = cutInShape(V2, loop2, before2, b, 1.0);
  ASSERT_GT(ca.fresh.size(), 20u);
  ASSERT_EQ(ca.fresh.size(), cb.fresh.size());
  for (std::size_t k = 0; k < ca.fresh.size(); ++k) EXPECT_TRUE(ca.fresh[k] == cb.fresh[k]) << "fresh point " << k;
  EXPECT_EQ(ca.faces, cb.faces);
}

TEST(FillingShape, TellsApartCoordinatesTheOrderOfTheNumbersAndTheFaces) {
  const std::vector<Vec> square = {Vec(0, 0, 0), Vec(10, 0, 0), Vec(10, 10, 0), Vec(0, 10, 0)};
  const std::vector<int> loop = {0, 1, 2, 3};
  const std::vector<Tri> before = {{{0, 1, 2}}, {{0, 2, 3}}};
  const FillingShape a = shapeOf(square, loop, before);
  // One coordinate one unit in the last place away.
  std::vector<Vec> moved = square;
  moved[2].y() = std::nextafter(10.0, 11.0);
  EXPECT_FALSE(a == shapeOf(moved, loop, before));
  // The same points and faces, numbered in another order (3, 2, 1, 0): the cut may break its
  // ties otherwise.
  const std::vector<Vec> reversed = {square[3], square[2], square[1], square[0]};
  const FillingShape r = shapeOf(reversed, {3, 2, 1, 0}, {{{3, 2, 1}}, {{3, 1, 0}}});
  EXPECT_EQ(r.points.size(), a.points.size());
  EXPECT_EQ(r.loop, a.loop);
  EXPECT_EQ(r.faces, a.faces);
  EXPECT_FALSE(a == r);
  // The faces in the other order, and the other diagonal.
  EXPECT_FALSE(a == shapeOf(square, loop, {{{0, 2, 3}}, {{0, 1, 2}}}));
  EXPECT_FALSE(a == shapeOf(square, loop, {{{0, 1, 3}}, {{1, 2, 3}}}));
}

}  // namespace
