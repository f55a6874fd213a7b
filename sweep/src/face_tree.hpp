#pragma once
// A bounding-volume hierarchy of triangle boxes, for box and segment queries: the inside test's
// broad phase over the body faces (inside.cpp) and the label rays over the arrangement
// (trim.cpp). Internal to steady::sweep.
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

namespace steady::sweep::detail {

// A bounding-volume hierarchy of the boxes of triangles: median splits of the triangle
// centroids along the longest axis, up to 4 triangles per leaf. Its queries only read it, so
// they may run concurrently.
class FaceTree {
 public:
  using Vec = Eigen::Vector3d;

  struct Node {
    Vec lo, hi;
    int left = -1, right = -1;  // children (inner node) or -1 (leaf)
    int first = 0, count = 0;   // leaf: order_[first, first + count)
  };

  void build(const std::vector<Vec>& vertices, const std::vector<std::array<int, 3>>& faces) {
    const std::size_t nf = faces.size();
    flo_.resize(nf);
    fhi_.resize(nf);
    std::vector<Vec> centroid(nf);
    order_.resize(nf);
    for (std::size_t f = 0; f < nf; ++f) {
      const Vec& a = vertices[faces[f][0]];
      const Vec& b = vertices[faces[f][1]];
      const Vec& c = vertices[faces[f][2]];
      flo_[f] = a.cwiseMin(b).cwiseMin(c);
      fhi_[f] = a.cwiseMax(b).cwiseMax(c);
      centroid[f] = (a + b + c) / 3.0;
      order_[f] = static_cast<int>(f);
    }
    nodes_.clear();
    nodes_.reserve(2 * nf);
    split(0, static_cast<int>(nf), centroid);
  }

  const Vec& faceLo(int f) const { return flo_[f]; }
  const Vec& faceHi(int f) const { return fhi_[f]; }
  const Node& root() const { return nodes_.front(); }

  // Calls visit(f) for every face whose box meets the box [lo, hi].
  template <class Visit>
  void overlapping(const Vec& lo, const Vec& hi, Visit&& visit) const {
    forEach([&](const Vec& nlo, const Vec& nhi) { return !((nlo.array() > hi.array()).any() || (lo.array() > nhi.array()).any()); },
            [&](int f) {
              if (!((flo_[f].array() > hi.array()).any() || (lo.array() > fhi_[f].array()).any())) visit(f);
            });
  }

  // Calls keep_going(f) for the faces whose boxes meet the box [lo, hi] until it returns false.
  template <class Visit>
  void overlappingUntil(const Vec& lo, const Vec& hi, Visit&& keep_going) const {
    bool stop = false;
    forEach([&](const Vec& nlo, const Vec& nhi) {
              return !stop && !((nlo.array() > hi.array()).any() || (lo.array() > nhi.array()).any());
            },
            [&](int f) {
              if (!stop && !((flo_[f].array() > hi.array()).any() || (lo.array() > fhi_[f].array()).any()))
                stop = !keep_going(f);
            });
  }

  // Calls visit(f) for every face whose box, inflated by `pad`, meets the segment [p, q].
  template <class Visit>
  void alongSegment(const Vec& p, const Vec& q, double pad, Visit&& visit) const {
    const Vec d = q - p;
    auto hits = [&](const Vec& lo, const Vec& hi) {
      double t0 = 0.0, t1 = 1.0;
      for (int k = 0; k < 3; ++k) {
        const double l = lo[k] - pad, h = hi[k] + pad;
        if (d[k] == 0) {
          if (p[k] < l || p[k] > h) return false;
          continue;
        }
        double a = (l - p[k]) / d[k], b = (h - p[k]) / d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a - 1e-12);
        t1 = std::min(t1, b + 1e-12);
        if (t0 > t1) return false;
      }
      return true;
    };
    forEach(hits, [&](int f) {
      if (hits(flo_[f], fhi_[f])) visit(f);
    });
  }

 private:
  template <class NodeTest, class Visit>
  void forEach(NodeTest&& test, Visit&& visit) const {
    if (nodes_.empty()) return;
    std::array<int, 128> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (!test(n.lo, n.hi)) continue;
      if (n.left < 0) {
        for (int i = n.first; i < n.first + n.count; ++i) visit(order_[i]);
      } else {
        stack[top++] = n.right;
        stack[top++] = n.left;
      }
    }
  }

  int split(int first, int last, const std::vector<Vec>& centroid) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Vec lo = Vec::Constant(std::numeric_limits<double>::infinity()), hi = -lo, clo = lo, chi = hi;
    for (int i = first; i < last; ++i) {
      lo = lo.cwiseMin(flo_[order_[i]]);
      hi = hi.cwiseMax(fhi_[order_[i]]);
      clo = clo.cwiseMin(centroid[order_[i]]);
      chi = chi.cwiseMax(centroid[order_[i]]);
    }
    nodes_[id].lo = lo;
    nodes_[id].hi = hi;
    if (last - first <= 4) {
      nodes_[id].first = first;
      nodes_[id].count = last - first;
      return id;
    }
    int axis = 0;
    (chi - clo).maxCoeff(&axis);
    const int mid = first + (last - first) / 2;
    std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + last,
                     [&](int a, int b) { return centroid[a][axis] < centroid[b][axis]; });
    const int l = split(first, mid, centroid);
    const int r = split(mid, last, centroid);
    nodes_[id].left = l;
    nodes_[id].right = r;
    return id;
  }

  std::vector<Node> nodes_;
  std::vector<int> order_;
  std::vector<Vec> flo_, fhi_;
};

}  // namespace steady::sweep::detail
