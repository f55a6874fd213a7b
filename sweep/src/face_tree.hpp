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

namespace steady::sweep::detail {

// A bounding-volume hierarchy of the boxes of triangles: median splits of the box centres along
// the longest axis, up to 4 triangles per leaf. The nodes' boxes are stored in float, rounded
// outward, and the triangles' own boxes are computed from their vertices when a leaf is reached
// (a large arrangement has millions of faces), so every query may report a few more triangles
// than the exact boxes would, never fewer. Its queries only read it, so they may run
// concurrently.
class FaceTree {
 public:
  using Vec = Eigen::Vector3d;
  using Faces = std::vector<std::array<int, 3>>;

  // The tree keeps references to `vertices` and `faces`: they must outlive it, unchanged.
  void build(const std::vector<Vec>& vertices, const Faces& faces) {
    V_ = &vertices;
    F_ = &faces;
    const std::size_t nf = faces.size();
    order_.resize(nf);
    for (std::size_t f = 0; f < nf; ++f) order_[f] = static_cast<int>(f);
    // Box corners in float (outward) while building: centres and node boxes.
    std::vector<Vec3f> lo(nf), hi(nf);
    for (std::size_t f = 0; f < nf; ++f) {
      const Box b = faceBox(static_cast<int>(f));
      lo[f] = down(b.lo);
      hi[f] = up(b.hi);
    }
    nodes_.clear();
    nodes_.reserve(nf);  // at most nf nodes (leaves hold 2 to 4 faces); pages never touched stay free
    if (nf > 0) split(0, static_cast<int>(nf), lo, hi);
  }

  // Calls visit(f) for every face whose box meets the box [lo, hi].
  template <class Visit>
  void overlapping(const Vec& lo, const Vec& hi, Visit&& visit) const {
    auto meets = [&](const Box& b) { return !((b.lo.array() > hi.array()).any() || (lo.array() > b.hi.array()).any()); };
    forEach(meets, [&](int f) {
      if (meets(faceBox(f))) visit(f);
    });
  }

  // Calls keep_going(f) for the faces whose boxes meet the box [lo, hi] until it returns false.
  template <class Visit>
  void overlappingUntil(const Vec& lo, const Vec& hi, Visit&& keep_going) const {
    bool stop = false;
    auto meets = [&](const Box& b) { return !((b.lo.array() > hi.array()).any() || (lo.array() > b.hi.array()).any()); };
    forEach([&](const Box& b) { return !stop && meets(b); },
            [&](int f) {
              if (!stop && meets(faceBox(f))) stop = !keep_going(f);
            });
  }

  // Calls visit(f) for every face whose box, inflated by `pad`, meets the segment [p, q].
  template <class Visit>
  void alongSegment(const Vec& p, const Vec& q, double pad, Visit&& visit) const {
    const Vec d = q - p;
    auto hits = [&](const Box& b) {
      double t0 = 0.0, t1 = 1.0;
      for (int k = 0; k < 3; ++k) {
        const double l = b.lo[k] - pad, h = b.hi[k] + pad;
        if (d[k] == 0) {
          if (p[k] < l || p[k] > h) return false;
          continue;
        }
        double s = (l - p[k]) / d[k], e = (h - p[k]) / d[k];
        if (s > e) std::swap(s, e);
        t0 = std::max(t0, s - 1e-12);
        t1 = std::min(t1, e + 1e-12);
        if (t0 > t1) return false;
      }
      return true;
    };
    forEach(hits, [&](int f) {
      if (hits(faceBox(f))) visit(f);
    });
  }

 private:
  using Vec3f = Eigen::Vector3f;
  struct Box {
    Vec lo, hi;
  };
  struct Node {
    Vec3f lo, hi;
    int left = -1, right = -1;  // children (inner node) or -1 (leaf)
    int first = 0, count = 0;   // leaf: order_[first, first + count)
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

  Box faceBox(int f) const {
    const std::array<int, 3>& t = (*F_)[static_cast<std::size_t>(f)];
    const Vec &a = (*V_)[t[0]], &b = (*V_)[t[1]], &c = (*V_)[t[2]];
    return {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
  }

  template <class NodeTest, class Visit>
  void forEach(NodeTest&& test, Visit&& visit) const {
    if (nodes_.empty()) return;
    std::array<int, 128> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (!test(Box{n.lo.cast<double>(), n.hi.cast<double>()})) continue;
      if (n.left < 0) {
        for (int i = n.first; i < n.first + n.count; ++i) visit(order_[i]);
      } else {
        stack[top++] = n.right;
        stack[top++] = n.left;
      }
    }
  }

  int split(int first, int last, const std::vector<Vec3f>& flo, const std::vector<Vec3f>& fhi) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Vec3f lo = Vec3f::Constant(std::numeric_limits<float>::infinity()), hi = -lo;
    Vec3f clo = lo, chi = hi;  // bounds of the box centres (doubled)
    for (int i = first; i < last; ++i) {
      const int f = order_[i];
      lo = lo.cwiseMin(flo[f]);
      hi = hi.cwiseMax(fhi[f]);
      clo = clo.cwiseMin(flo[f] + fhi[f]);
      chi = chi.cwiseMax(flo[f] + fhi[f]);
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
    std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + last, [&](int a, int b) {
      return flo[a][axis] + fhi[a][axis] < flo[b][axis] + fhi[b][axis];
    });
    const int l = split(first, mid, flo, fhi);
    const int r = split(mid, last, flo, fhi);
    nodes_[id].left = l;
    nodes_[id].right = r;
    return id;
  }

  const std::vector<Vec>* V_ = nullptr;
  const Faces* F_ = nullptr;
  std::vector<Node> nodes_;
  std::vector<int> order_;
};

}  // namespace steady::sweep::detail
