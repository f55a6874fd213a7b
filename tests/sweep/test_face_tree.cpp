// The box hierarchy shared by the inside test, the labels and the checks (sweep/src/face_tree.hpp,
// internal): its box queries against brute force, and the same tree whether it is built on one
// thread or several (the parallel build places every node by the sizes of the ranges alone).
#include "face_tree.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace {

using steady::sweep::detail::FaceTree;
using Vec = Eigen::Vector3d;

struct Soup {
  std::vector<Vec> V;
  FaceTree::Faces F;
};

// n small random triangles in the unit cube, some of them needles and some repeated.
Soup randomSoup(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), d(-0.01, 0.01);
  Soup s;
  for (std::size_t f = 0; f < n; ++f) {
    const Vec c(u(rng), u(rng), u(rng));
    const int base = static_cast<int>(s.V.size());
    s.V.push_back(c);
    s.V.push_back(c + Vec(d(rng), d(rng), d(rng)));
    s.V.push_back(f % 7 == 0 ? Vec(c + 1e-9 * Vec(1, 1, 1)) : Vec(c + Vec(d(rng), d(rng), d(rng))));
    s.F.push_back({{base, base + 1, base + 2}});
    if (f % 101 == 0) s.F.push_back({{base, base + 1, base + 2}});
  }
  return s;
}

// The box of face f of s.
std::pair<Vec, Vec> faceBox(const Soup& s, std::size_t f) {
  const Vec& a = s.V[s.F[f][0]];
  const Vec& b = s.V[s.F[f][1]];
  const Vec& c = s.V[s.F[f][2]];
  return {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
}

// Whether the closed boxes [alo, ahi] and [blo, bhi] meet (in double).
bool boxesMeet(const Vec& alo, const Vec& ahi, const Vec& blo, const Vec& bhi) {
  return !((alo.array() > bhi.array()).any() || (blo.array() > ahi.array()).any());
}

std::vector<int> boxQuery(const FaceTree& tree, const Vec& lo, const Vec& hi) {
  std::vector<int> out;
  tree.overlapping(lo, hi, [&](int f) { out.push_back(f); });
  std::sort(out.begin(), out.end());
  return out;
}

// Sizes across the serial/parallel threshold and leaf sizes 1 to 4 at the bottom.
TEST(FaceTree, BoxQueriesMatchBruteForceOnAnyNumberOfThreads) {
  for (const std::size_t n : {1u, 5u, 9u, 1000u, 70001u}) {
    const Soup s = randomSoup(n, 7 + n);
    FaceTree one, two, all;
    one.build(s.V, s.F, 1);
    two.build(s.V, s.F, 2);
    all.build(s.V, s.F, 0);
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> u(-0.05, 1.05), w(0.0, 0.08);
    for (int q = 0; q < 200; ++q) {
      const Vec lo(u(rng), u(rng), u(rng));
      const Vec hi = lo + Vec(w(rng), w(rng), w(rng));
      std::vector<int> expect;
      for (std::size_t f = 0; f < s.F.size(); ++f) {
        const auto [flo, fhi] = faceBox(s, f);
        if (boxesMeet(flo, fhi, lo, hi)) expect.push_back(static_cast<int>(f));
      }
      ASSERT_EQ(boxQuery(one, lo, hi), expect) << n << " faces, query " << q;
      ASSERT_EQ(boxQuery(two, lo, hi), expect) << n << " faces, query " << q << ", 2 threads";
      ASSERT_EQ(boxQuery(all, lo, hi), expect) << n << " faces, query " << q << ", all threads";
    }
    // The same tree: the faces come out of a query that meets everything in the same order.
    std::vector<int> a, b;
    one.overlapping(Vec::Constant(-1), Vec::Constant(2), [&](int f) { a.push_back(f); });
    two.overlapping(Vec::Constant(-1), Vec::Constant(2), [&](int f) { b.push_back(f); });
    EXPECT_EQ(a, b) << n << " faces";
    EXPECT_EQ(a.size(), s.F.size());
  }
}

// Each pair of faces whose boxes meet, met once: from every place k of the tree's order, the
// faces after k whose boxes meet the box of the face at k. Also the boxes that touch a face's
// box only at its faces' exact coordinates (doubles that no float equals), which the float node
// tests must not lose.
TEST(FaceTree, PairsFromEachPlaceMatchBruteForceOnce) {
  for (const std::size_t n : {1u, 2u, 7u, 600u, 40000u}) {
    const Soup s = randomSoup(n, 31 + n);
    FaceTree tree;
    tree.build(s.V, s.F, 2);
    ASSERT_EQ(tree.size(), s.F.size());
    auto box = [&](int f) { return faceBox(s, static_cast<std::size_t>(f)); };
    std::vector<std::pair<int, int>> found;
    std::vector<char> seen(s.F.size(), 0);
    for (std::size_t k = 0; k < tree.size(); ++k) {
      const int f = tree.faceAt(k);
      seen[static_cast<std::size_t>(f)] = 1;
      const auto [lo, hi] = box(f);
      tree.overlappingAfter(k, lo, hi, [&](int g) { found.emplace_back(std::min(f, g), std::max(f, g)); });
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(s.F.size())) << "every face has one place";
    std::sort(found.begin(), found.end());
    std::vector<std::pair<int, int>> expect;
    if (n <= 600) {  // (brute force over all pairs)
      for (int f = 0; f < static_cast<int>(s.F.size()); ++f)
        for (int g = f + 1; g < static_cast<int>(s.F.size()); ++g)
          if (boxesMeet(box(f).first, box(f).second, box(g).first, box(g).second)) expect.emplace_back(f, g);
      EXPECT_EQ(found, expect) << n << " faces";
    } else {  // (the pairs again through plain box queries)
      for (int f = 0; f < static_cast<int>(s.F.size()); ++f) {
        const auto [lo, hi] = box(f);
        for (const int g : boxQuery(tree, lo, hi))
          if (g > f) expect.emplace_back(f, g);
      }
      EXPECT_EQ(found, expect) << n << " faces";
    }
    // A query box that only touches face f (its box shifted to end where f's begins) finds f.
    for (int f = 0; f < static_cast<int>(std::min<std::size_t>(s.F.size(), 200)); ++f) {
      const auto [lo, hi] = box(f);
      for (int k = 0; k < 3; ++k) {
        Vec qlo = lo, qhi = hi;
        qlo[k] = lo[k] - 0.3;
        qhi[k] = lo[k];
        const std::vector<int> got = boxQuery(tree, qlo, qhi);
        EXPECT_TRUE(std::binary_search(got.begin(), got.end(), f)) << "face " << f << " touched along axis " << k;
      }
    }
  }
}

// A tree built with keep_boxes walks four boxes at a time (FaceTree::Wide) in overlappingUntil:
// the faces must be those of the binary walk (overlapping), in the same order, and stopping
// after the k-th must give the first k. Also a query box with a NaN corner, which meets
// everything in both walks (no comparison with NaN is true), and one that meets nothing.
TEST(FaceTree, FourWideWalkGivesTheBinaryWalksFacesInOrder) {
  for (const std::size_t n : {1u, 3u, 5u, 9u, 17u, 1000u, 70001u}) {
    const Soup s = randomSoup(n, 501 + n);
    FaceTree plain, wide;
    plain.build(s.V, s.F, 2);
    wide.build(s.V, s.F, 2, true);
    std::mt19937_64 rng(5 + n);
    std::uniform_real_distribution<double> u(-0.05, 1.05), w(0.0, 0.3);
    auto until = [&](const FaceTree& tree, const Vec& lo, const Vec& hi, std::size_t k) {
      std::vector<int> out;
      tree.overlappingUntil(lo, hi, [&](int f) {
        out.push_back(f);
        return out.size() < k;
      });
      return out;
    };
    auto all = [&](const FaceTree& tree, const Vec& lo, const Vec& hi) {
      std::vector<int> out;
      tree.overlapping(lo, hi, [&](int f) { out.push_back(f); });
      return out;
    };
    for (int q = 0; q < 300; ++q) {
      const Vec lo(u(rng), u(rng), u(rng));
      const Vec hi = lo + Vec(w(rng), w(rng), w(rng));
      const std::vector<int> expect = all(plain, lo, hi);
      ASSERT_EQ(all(wide, lo, hi), expect) << n << " faces, query " << q;
      ASSERT_EQ(until(wide, lo, hi, s.F.size() + 1), expect) << n << " faces, query " << q;
      const std::size_t k = 1 + static_cast<std::size_t>(q) % 9;
      const std::vector<int> first(expect.begin(), expect.begin() + static_cast<std::ptrdiff_t>(std::min(k, expect.size())));
      ASSERT_EQ(until(wide, lo, hi, k), first) << n << " faces, query " << q << ", stop after " << k;
      ASSERT_EQ(until(plain, lo, hi, k), first) << n << " faces, query " << q << ", binary, stop after " << k;
    }
    const Vec nan = Vec::Constant(std::numeric_limits<double>::quiet_NaN());
    EXPECT_EQ(until(wide, nan, nan, s.F.size() + 1), all(plain, nan, nan)) << n << " faces, NaN query";
    EXPECT_EQ(all(plain, nan, nan).size(), s.F.size()) << n << " faces, NaN query";
    EXPECT_TRUE(until(wide, Vec::Constant(3), Vec::Constant(4), s.F.size() + 1).empty()) << n << " faces";
  }
}

}  // namespace
