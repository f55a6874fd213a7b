// The spans a re-sweep refines (detail::spansNear, trim.cpp): per span, whether a doubtful
// point lies in the box of one of the span's triangles grown by the reach. Known answers on
// three spans of small triangles set along x, a long thin triangle whose box is much larger
// than the triangle, points on the grown box's faces and just outside, spans without
// triangles, and a seeded comparison with a brute-force oracle written from the definition.
#include "doubt.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace {

using Vec = Eigen::Vector3d;
using Tri = std::array<int, 3>;
using steady::sweep::detail::spansNear;

// Span i holds one unit right triangle in the plane z = 0 with its corner at (3 i, 0, 0).
struct ThreeSpans {
  std::vector<Vec> V;
  std::vector<Tri> T;
  std::vector<std::size_t> end;
  ThreeSpans() {
    for (int i = 0; i < 3; ++i) {
      const int b = static_cast<int>(V.size());
      V.emplace_back(3.0 * i, 0, 0);
      V.emplace_back(3.0 * i + 1, 0, 0);
      V.emplace_back(3.0 * i, 1, 0);
      T.push_back({b, b + 1, b + 2});
      end.push_back(T.size());
    }
  }
};

std::vector<char> bits(std::initializer_list<int> l) { return std::vector<char>(l.begin(), l.end()); }

TEST(SpansNear, PicksTheSpansWhoseGrownBoxesHoldAPoint) {
  const ThreeSpans s;
  EXPECT_EQ(spansNear({Vec(3.5, 0.5, 0.2)}, s.V, s.T, s.end, 0.25), bits({0, 1, 0}));
  EXPECT_EQ(spansNear({Vec(3.5, 0.5, 0.3)}, s.V, s.T, s.end, 0.25), bits({0, 0, 0}));
  // Between spans 0 and 1 (box x ranges [0, 1] and [3, 4]): within 1.5 of both.
  EXPECT_EQ(spansNear({Vec(2, 0.5, 0)}, s.V, s.T, s.end, 1.5), bits({1, 1, 0}));
  EXPECT_EQ(spansNear({Vec(2, 0.5, 0)}, s.V, s.T, s.end, 0.9), bits({0, 0, 0}));
  // Two points, each near one span.
  EXPECT_EQ(spansNear({Vec(-0.1, 0, 0), Vec(7.1, 1, 0)}, s.V, s.T, s.end, 0.2), bits({1, 0, 1}));
  // No points: no span.
  EXPECT_EQ(spansNear({}, s.V, s.T, s.end, 10), bits({0, 0, 0}));
}

TEST(SpansNear, TheGrownBoxIsClosed) {
  const ThreeSpans s;
  // On the face x = 4 + 0.5 of span 1's grown box, and just beyond it.
  EXPECT_EQ(spansNear({Vec(4.5, 1.5, -0.5)}, s.V, s.T, s.end, 0.5), bits({0, 1, 0}));
  EXPECT_EQ(spansNear({Vec(4.5 + 1e-12, 0.5, 0)}, s.V, s.T, s.end, 0.5), bits({0, 0, 0}));
}

// A box test: a point far from a long diagonal triangle but inside its box picks its span.
TEST(SpansNear, ALongTrianglePicksItsSpanByItsBox) {
  const std::vector<Vec> V = {Vec(0, 0, 0), Vec(10, 10, 0), Vec(10, 10.01, 0)};
  const std::vector<Tri> T = {{0, 1, 2}};
  EXPECT_EQ(spansNear({Vec(9, 1, 0)}, V, T, {1}, 0.01), bits({1}));
  EXPECT_EQ(spansNear({Vec(9, 1, 0.02)}, V, T, {1}, 0.01), bits({0}));
}

// Spans that hold no triangle (equal ends) are never picked, and the ranges do not leak into
// each other.
TEST(SpansNear, EmptySpansAreNeverPicked) {
  const ThreeSpans s;
  const std::vector<std::size_t> end = {1, 1, 2, 3, 3};
  EXPECT_EQ(spansNear({Vec(0.2, 0.2, 0), Vec(3.2, 0.2, 0), Vec(6.2, 0.2, 0)}, s.V, s.T, end, 0.1),
            bits({1, 0, 1, 1, 0}));
}

// Seeded: random triangles in random spans against a brute-force reading of the definition.
TEST(SpansNear, AgreesWithBruteForceOnRandomScenes) {
  std::mt19937_64 rng(20261130);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> count(0, 6);
  int picked = 0, total = 0;
  for (int scene = 0; scene < 200; ++scene) {
    std::vector<Vec> V;
    std::vector<Tri> T;
    std::vector<std::size_t> end;
    const int spans = 1 + scene % 5;
    for (int i = 0; i < spans; ++i) {
      const int n = count(rng);
      for (int k = 0; k < n; ++k) {
        const int b = static_cast<int>(V.size());
        const Vec c(u(rng), u(rng), u(rng));
        for (int j = 0; j < 3; ++j) V.push_back(c + 0.4 * Vec(u(rng), u(rng), u(rng)));
        T.push_back({b, b + 1, b + 2});
      }
      end.push_back(T.size());
    }
    std::vector<Vec> points(static_cast<std::size_t>(count(rng)));
    for (Vec& p : points) p = Vec(u(rng), u(rng), u(rng));
    const double reach = 0.2 * (1 + u(rng));
    std::vector<char> expected(end.size(), 0);
    std::size_t begin = 0;
    for (std::size_t i = 0; i < end.size(); ++i) {
      for (std::size_t k = begin; k < end[i]; ++k)
        for (const Vec& p : points) {
          bool in = true;
          for (int d = 0; d < 3; ++d) {
            double lo = V[T[k][0]][d], hi = lo;
            for (int j = 1; j < 3; ++j) lo = std::min(lo, V[T[k][j]][d]), hi = std::max(hi, V[T[k][j]][d]);
            in = in && p[d] >= lo - reach && p[d] <= hi + reach;
          }
          if (in) expected[i] = 1;
        }
      begin = end[i];
    }
    ASSERT_EQ(spansNear(points, V, T, end, reach), expected) << "scene " << scene;
    for (const char e : expected) picked += e, ++total;
  }
  // (the scenes pick some spans and leave others)
  EXPECT_GT(picked, total / 10);
  EXPECT_LT(picked, total * 9 / 10);
}

}  // namespace
