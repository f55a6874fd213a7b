#pragma once
// A bounding-volume hierarchy of triangle boxes, for box and segment queries: the inside test's
// broad phase over the body faces (inside.cpp) and the label rays over the arrangement
// (trim.cpp). Internal to steady::sweep.
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

namespace steady::sweep::detail {

// A bounding-volume hierarchy of the boxes of triangles: median splits of the box centres along
// the longest axis, up to 4 triangles per leaf. The nodes' boxes are stored in float, rounded
// outward, and the triangles' own boxes are computed from their vertices when a leaf is reached
// (a large arrangement has millions of faces), or stored in the tree's order when it is built
// with keep_boxes. Box queries round their box to the nearest
// floats once and test the nodes in float: rounding to nearest is monotone and a node's box is
// rounded outward from its faces' double coordinates, so a node whose faces meet the query in
// double passes (lo_f <= hi implies down(lo_f) <= nearest(lo_f) <= nearest(hi)). The faces'
// own boxes are tested in double, so the queries report exactly the faces whose boxes meet the
// query's. Its queries only read it, so they may run concurrently.
class FaceTree {
 public:
  using Vec = Eigen::Vector3d;
  using Faces = std::vector<std::array<int, 3>>;

  // The tree keeps references to `vertices` and `faces`: they must outlive it, unchanged.
  // `threads` as SweepOptions::threads (1: on the calling thread alone; 0: every hardware
  // thread). The tree is the same for any number of threads: each node's place in the node
  // array follows from the sizes of the ranges alone (pre-order), and subtrees over disjoint
  // ranges are built concurrently. With `keep_boxes` the faces' boxes are also stored, in the
  // tree's order (48 bytes a face), so that a leaf's faces are tested from one run of memory
  // rather than through the face and vertex arrays: the same boxes, so the same answers. (The
  // inside test's tree of body faces, queried millions of times: the exact inside test 1.1 to
  // 1.2x faster near the swept boundary, BM_SweptContains on the elephant and bunny00 screws.
  // The arrangement's trees, with millions of faces and few queries each, do without.) Such a
  // tree also gets a four-wide copy of its nodes for overlappingUntil (see Wide).
  void build(const std::vector<Vec>& vertices, const Faces& faces, int threads = 1, bool keep_boxes = false) {
    V_ = &vertices;
    F_ = &faces;
    boxes_.clear();
    const std::size_t nf = faces.size();
    order_.resize(nf);
    // The faces with their box centres (doubled, in float), partitioned in place while
    // building; order_ is read from them at the end. (Partitioning indices into a separate
    // array of centres spent most of the build waiting for those loads.)
    std::vector<Item> items(nf);
    auto prepare = [&](std::size_t begin, std::size_t end) {
      for (std::size_t f = begin; f < end; ++f) {
        const Box b = faceBox(static_cast<int>(f));
        items[f] = {(b.lo + b.hi).cast<float>(), static_cast<int>(f)};
      }
    };
    nodes_.clear();
    wide_.clear();
    if (nf == 0) return;
    nodes_.resize(nodeCount(static_cast<int>(nf)));
    if (threads == 1 || nf < kParallelBuild) {
      prepare(0, nf);
      split(0, 0, static_cast<int>(nf), items, false);
    } else {
      tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf),
                          [&](const tbb::blocked_range<std::size_t>& r) { prepare(r.begin(), r.end()); });
        split(0, 0, static_cast<int>(nf), items, true);
      });
    }
    if (keep_boxes) {
      boxes_.resize(nf);
      for (std::size_t i = 0; i < nf; ++i) boxes_[i] = faceBox(order_[i]);
      buildWide();
    }
  }

  // Calls visit(f) for every face whose box meets the box [lo, hi].
  template <class Visit>
  void overlapping(const Vec& lo, const Vec& hi, Visit&& visit) const {
    const Vec3f flo = lo.cast<float>(), fhi = hi.cast<float>();
    forEach([&](const Node& n) { return meets(n.lo, n.hi, flo, fhi); },
            [&](int i) {
              if (placeMeets(i, lo, hi)) visit(order_[i]);
            });
  }

  // The number of faces, and the face at place k (0 <= k < size()) of the tree's order.
  std::size_t size() const { return order_.size(); }
  int faceAt(std::size_t k) const { return order_[k]; }

  // As overlapping(), for the faces after place k of the tree's order only: called from each
  // face's place with its own box, it reports every pair of faces whose boxes meet once, and
  // prunes the subtrees wholly before k.
  template <class Visit>
  void overlappingAfter(std::size_t k, const Vec& lo, const Vec& hi, Visit&& visit) const {
    const Vec3f flo = lo.cast<float>(), fhi = hi.cast<float>();
    forEach(
        [&](const Node& n) {
          return static_cast<std::size_t>(n.first + n.count) > k + 1 && meets(n.lo, n.hi, flo, fhi);
        },
        [&](int i) {
          if (static_cast<std::size_t>(i) > k && placeMeets(i, lo, hi)) visit(order_[i]);
        });
  }

  // Calls keep_going(f) for the faces whose boxes meet the box [lo, hi] until it returns false.
  // (The faces come in the tree's order, so the same ones as from overlapping(), in the same
  // order, whichever walk is taken.)
  template <class Visit>
  void overlappingUntil(const Vec& lo, const Vec& hi, Visit&& keep_going) const {
    bool stop = false;
    const Vec3f flo = lo.cast<float>(), fhi = hi.cast<float>();
    auto leaf = [&](int i) {
      if (!stop && placeMeets(i, lo, hi)) stop = !keep_going(order_[i]);
    };
#if defined(__SSE2__)
    if (!wide_.empty()) {
      forEachWide(flo, fhi, stop, leaf);
      return;
    }
#endif
    forEach([&](const Node& n) { return !stop && meets(n.lo, n.hi, flo, fhi); }, leaf);
  }

  // Calls visit(f) for every face whose box, inflated by `pad`, meets the segment [p, q].
  template <class Visit>
  void alongSegment(const Vec& p, const Vec& q, double pad, Visit&& visit) const {
    const Vec d = q - p;
    // Slabs in the parameter t of p + t d, by multiplying with 1 / d (within an ulp of the
    // quotients, far inside the 1e-12 slack); an axis along which the segment does not move
    // only tests p's coordinate.
    bool moves[3];
    Vec inv;
    for (int k = 0; k < 3; ++k) {
      moves[k] = d[k] != 0;
      inv[k] = moves[k] ? 1.0 / d[k] : 0.0;
    }
    auto hits = [&](const Box& b) {
      double t0 = 0.0, t1 = 1.0;
      for (int k = 0; k < 3; ++k) {
        const double l = b.lo[k] - pad, h = b.hi[k] + pad;
        if (!moves[k]) {
          if (p[k] < l || p[k] > h) return false;
          continue;
        }
        double s = (l - p[k]) * inv[k], e = (h - p[k]) * inv[k];
        if (s > e) std::swap(s, e);
        t0 = std::max(t0, s - 1e-12);
        t1 = std::min(t1, e + 1e-12);
        if (t0 > t1) return false;
      }
      return true;
    };
    forEach([&](const Node& n) { return hits(Box{n.lo.cast<double>(), n.hi.cast<double>()}); },
            [&](int i) {
              if (hits(placeBox(i))) visit(order_[i]);
            });
  }

 private:
  using Vec3f = Eigen::Vector3f;
  struct Box {
    Vec lo, hi;
  };
  struct Item {
    Vec3f centre;
    int face;
  };
  struct Node {
    Vec3f lo, hi;
    int left = -1, right = -1;  // children (inner node) or -1 (leaf)
    int first = 0, count = 0;   // its faces: order_[first, first + count)
  };

  // The float at or below (above) each coordinate.
  static Vec3f down(const Vec& x) {
    Vec3f r = x.cast<float>();
    for (int k = 0; k < 3; ++k)
      if (static_cast<double>(r[k]) > x[k]) r[k] = std::nextafter(r[k], -std::numeric_limits<float>::infinity());
    return r;
  }
  static Vec3f up(const Vec& x) {
    Vec3f r = x.cast<float>();
    for (int k = 0; k < 3; ++k)
      if (static_cast<double>(r[k]) < x[k]) r[k] = std::nextafter(r[k], std::numeric_limits<float>::infinity());
    return r;
  }

  // Whether the boxes [alo, ahi] and [blo, bhi] meet (closed boxes; float or double).
  template <class V3>
  static bool meets(const V3& alo, const V3& ahi, const V3& blo, const V3& bhi) {
    return !(alo[0] > bhi[0] || alo[1] > bhi[1] || alo[2] > bhi[2] || blo[0] > ahi[0] || blo[1] > ahi[1] ||
             blo[2] > ahi[2]);
  }
  // The box of the face at place i of the tree's order (stored, or from its vertices), and
  // whether it meets [lo, hi] (in double).
  Box placeBox(int i) const {
    return boxes_.empty() ? faceBox(order_[static_cast<std::size_t>(i)]) : boxes_[static_cast<std::size_t>(i)];
  }
  bool placeMeets(int i, const Vec& lo, const Vec& hi) const {
    const Box b = placeBox(i);
    return meets(b.lo, b.hi, lo, hi);
  }

  Box faceBox(int f) const {
    const std::array<int, 3>& t = (*F_)[static_cast<std::size_t>(f)];
    const Vec &a = (*V_)[t[0]], &b = (*V_)[t[1]], &c = (*V_)[t[2]];
    return {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
  }

  // Calls visit(i) for every place i (in order_) of the leaves reached through nodes that pass
  // test(node).
  // (Children are tested before they are pushed, both at once: the left child lies next to its
  // parent in memory. The leaves are still reached left to right.)
  template <class NodeTest, class Visit>
  void forEach(NodeTest&& test, Visit&& visit) const {
    if (nodes_.empty() || !test(nodes_[0])) return;
    std::array<int, 128> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (n.left < 0) {
        for (int i = n.first; i < n.first + n.count; ++i) visit(i);
        continue;
      }
      const bool right = test(nodes_[n.right]), left = test(nodes_[n.left]);
      if (right) stack[top++] = n.right;
      if (left) stack[top++] = n.left;
    }
  }

  // The four-wide copy of the hierarchy (built with keep_boxes, for the inside test's many
  // queries): each node holds the boxes of the grandchildren of an inner node of the binary
  // tree (or of a child that is a leaf), so one walk step tests four boxes at once in SIMD
  // registers. A grandchild's box meets a query only if its parent's does (a parent's float box
  // is the exact union of its children's), so the walk reaches the same leaves as the binary
  // one, and it reaches them in the same order (slots left to right, depth first), so the inside
  // test's answers are the same. An inside query near the swept boundary tests about 580 binary
  // nodes on the elephant screw, 70% of them in the searches that stop at the ninth face in reach;
  // with this walk BM_SweptContains/<mesh>/screw/boundary took 9.7-11.0 ms against 10.8-11.2
  // (elephant) and 15.0-15.9 against 16.3-16.7 ms (bunny00), three alternating pairs of runs.
  struct Wide {
    float lo[3][4], hi[3][4];  // per axis, the four slots' boxes (an empty slot: lo +inf, hi -inf)
    int slot[4];               // a wide node (>= 0), or ~n for the leaf n of the binary tree
  };
  static constexpr int kEmptySlot = std::numeric_limits<int>::min();

  // (build() calls it with the binary tree built, never empty, and wide_ cleared)
  void buildWide() {
    if (nodes_[0].left < 0) {  // (a single leaf)
      wide_.push_back(emptyWide());
      setSlot(wide_[0], 0, 0);
      return;
    }
    wideOf(0);
  }
  static Wide emptyWide() {
    Wide w;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 4; ++j) w.lo[k][j] = std::numeric_limits<float>::infinity(), w.hi[k][j] = -std::numeric_limits<float>::infinity();
    for (int j = 0; j < 4; ++j) w.slot[j] = kEmptySlot;
    return w;
  }
  // Slot j of w holds the binary node n (~n when it is a leaf; the caller sets an inner one).
  void setSlot(Wide& w, int j, int n) const {
    for (int k = 0; k < 3; ++k) w.lo[k][j] = nodes_[n].lo[k], w.hi[k][j] = nodes_[n].hi[k];
    w.slot[j] = ~n;
  }
  // The wide node of the inner binary node n (appended with its subtrees, pre-order).
  int wideOf(int n) {
    const int id = static_cast<int>(wide_.size());
    wide_.push_back(emptyWide());
    int j = 0;
    std::array<int, 4> inner{{-1, -1, -1, -1}};
    for (const int c : {nodes_[n].left, nodes_[n].right}) {
      if (nodes_[c].left < 0) {
        setSlot(wide_[id], j++, c);
        continue;
      }
      for (const int g : {nodes_[c].left, nodes_[c].right}) {
        setSlot(wide_[id], j, g);
        if (nodes_[g].left >= 0) inner[j] = g;
        ++j;
      }
    }
    for (int k = 0; k < 4; ++k)
      if (inner[k] >= 0) {
        const int w = wideOf(inner[k]);
        wide_[id].slot[k] = w;
      }
    return id;
  }

#if defined(__SSE2__)
  // Calls leaf(i) for every place i of the leaves whose boxes meet [flo, fhi] (tested as meets()
  // does, NaN included: a slot is passed over only when one of the comparisons is true), left
  // to right, while `stop` is false.
  template <class Leaf>
  void forEachWide(const Vec3f& flo, const Vec3f& fhi, const bool& stop, Leaf&& leaf) const {
    const __m128 qlo[3] = {_mm_set1_ps(flo[0]), _mm_set1_ps(flo[1]), _mm_set1_ps(flo[2])};
    const __m128 qhi[3] = {_mm_set1_ps(fhi[0]), _mm_set1_ps(fhi[1]), _mm_set1_ps(fhi[2])};
    std::array<int, 128> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0 && !stop) {
      const int at = stack[--top];
      if (at < 0) {  // (a leaf of the binary tree)
        const Node& n = nodes_[static_cast<std::size_t>(~at)];
        for (int i = n.first; i < n.first + n.count; ++i) leaf(i);
        continue;
      }
      const Wide& w = wide_[static_cast<std::size_t>(at)];
      __m128 apart = _mm_setzero_ps();
      for (int k = 0; k < 3; ++k) {
        apart = _mm_or_ps(apart, _mm_cmpgt_ps(_mm_loadu_ps(w.lo[k]), qhi[k]));
        apart = _mm_or_ps(apart, _mm_cmpgt_ps(qlo[k], _mm_loadu_ps(w.hi[k])));
      }
      const int meet = ~_mm_movemask_ps(apart) & 0xF;
      for (int j = 3; j >= 0; --j)
        if ((meet >> j & 1) && w.slot[j] != kEmptySlot) stack[top++] = w.slot[j];
    }
  }
#endif

  // Ranges of at least this many faces build their two halves concurrently (when allowed).
  static constexpr std::size_t kParallelBuild = 1 << 15;

  // The numbers of nodes of the subtrees over m and m + 1 faces (m >= 1; a leaf holds up to 4,
  // a larger range splits into n / 2 and n - n / 2): the halves of both lie in {m/2, m/2 + 1},
  // so one recursion of depth log m gives both.
  static std::array<std::size_t, 2> nodeCounts(std::size_t m) {
    if (m + 1 <= 4) return {{1, 1}};
    const std::size_t h = m / 2;
    const std::array<std::size_t, 2> q = nodeCounts(h);
    std::array<std::size_t, 2> r{};
    for (std::size_t i = 0; i < 2; ++i) {
      const std::size_t n = m + i;
      r[i] = n <= 4 ? 1 : 1 + q[n / 2 - h] + q[n - n / 2 - h];
    }
    return r;
  }
  static std::size_t nodeCount(int n) { return nodeCounts(static_cast<std::size_t>(n))[0]; }

  // Builds the subtree of items[first, last) at node id (its left subtree follows it, then its
  // right one); node boxes come from the faces at the leaves and from the children above them.
  // The leaves write their faces to order_.
  void split(std::size_t id, int first, int last, std::vector<Item>& items, bool parallel) {
    Node& node = nodes_[id];
    node.first = first;
    node.count = last - first;
    if (last - first <= 4) {
      Vec lo = Vec::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (int i = first; i < last; ++i) {
        order_[i] = items[i].face;
        const Box b = faceBox(order_[i]);
        lo = lo.cwiseMin(b.lo);
        hi = hi.cwiseMax(b.hi);
      }
      node.lo = down(lo);
      node.hi = up(hi);
      return;
    }
    Vec3f clo = Vec3f::Constant(std::numeric_limits<float>::infinity()), chi = -clo;
    for (int i = first; i < last; ++i) {
      clo = clo.cwiseMin(items[i].centre);
      chi = chi.cwiseMax(items[i].centre);
    }
    int axis = 0;
    (chi - clo).maxCoeff(&axis);
    const int mid = first + (last - first) / 2;
    std::nth_element(items.begin() + first, items.begin() + mid, items.begin() + last,
                     [axis](const Item& a, const Item& b) { return a.centre[axis] < b.centre[axis]; });
    const std::size_t l = id + 1, r = id + 1 + nodeCount(mid - first);
    if (parallel && static_cast<std::size_t>(last - first) >= kParallelBuild) {
      tbb::parallel_invoke([&] { split(l, first, mid, items, true); }, [&] { split(r, mid, last, items, true); });
    } else {
      split(l, first, mid, items, parallel);
      split(r, mid, last, items, parallel);
    }
    node.left = static_cast<int>(l);
    node.right = static_cast<int>(r);
    node.lo = nodes_[l].lo.cwiseMin(nodes_[r].lo);
    node.hi = nodes_[l].hi.cwiseMax(nodes_[r].hi);
  }

  const std::vector<Vec>* V_ = nullptr;
  const Faces* F_ = nullptr;
  std::vector<Node> nodes_;
  std::vector<int> order_;
  std::vector<Box> boxes_;  // per place, when built with keep_boxes
  std::vector<Wide> wide_;  // when built with keep_boxes (see Wide)
};

}  // namespace steady::sweep::detail
