#pragma once
// Certified tests in doubles that two triangles meet in their shared corners at most, by a
// separating plane. Internal to steady::sweep (trim.cpp's crossing pairs and output check).
//
// The proof: a plane through a point O (evaluated as m . (X - O) for a normal m, any vector of
// doubles) with every corner of one triangle strictly on one side, but the corners it shares
// with the other triangle, which must be O itself, and every corner of the other strictly on the
// other side (O again excepted). Each triangle then lies in its closed half-space and touches the
// plane at O at most, so they meet at O at most; with no shared corner they are disjoint. Only
// the signs need care: a corner's double coordinates x lie within its pad p_x of the true point X
// (per coordinate; 0 for points that are exactly their doubles), so with w = x - o computed in
// doubles, the computed m . w is within
//   4 * 2^-52 * sum_i |m_i| |w_i|  +  (p_x + p_o) sum_i |m_i|
// of m . (X - O) (rounding of the difference, the three products and the sum: at most about
// 4 units of 2^-53 of sum |m_i| |w_i|, taken twice; then the pads), and a sign is taken as
// certain only beyond that, inflated by 1e-12 for the bound's own rounding, and never when the
// bound is so small that underflow could spoil it.
//
// Where they serve: coplanar triangles, for which the planes of the triangles themselves decide
// nothing. A cap face fanned around one point to n points on its sides gives n triangles whose
// boxes all meet; before these tests every such pair went to the exact predicates (an L-shaped
// prism along a shear: 7.4M pairs, 10 s of its 12 s sweep).
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

#include <algorithm>
#include <array>
#include <cmath>

namespace steady::sweep::detail {

// A corner: its doubles and its pad (see the file comment).
struct PadPoint {
  Eigen::Vector3d x;
  double pad = 0;
};

// +1 or -1: the certain sign of m . (X - O); 0: unsure.
inline int certainSide(const Eigen::Vector3d& m, const PadPoint& o, const PadPoint& x) {
  const Eigen::Vector3d w = x.x - o.x;
  const Eigen::Vector3d am = m.cwiseAbs();
  const double s = m.dot(w);
  const double bound = (4 * 0x1.0p-52 * am.dot(w.cwiseAbs()) + (x.pad + o.pad) * am.sum()) * (1 + 1e-12);
  if (!(bound > 1e-280)) return 0;
  return s > bound ? 1 : s < -bound ? -1 : 0;
}

// Whether the plane through o with normal m has a and b strictly on one side and c and d
// strictly on the other, certainly.
inline bool separates(const Eigen::Vector3d& m, const PadPoint& o, const PadPoint& a, const PadPoint& b, const PadPoint& c,
                      const PadPoint& d) {
  const int sa = certainSide(m, o, a);
  if (sa == 0 || certainSide(m, o, b) != sa) return false;
  return certainSide(m, o, c) == -sa && certainSide(m, o, d) == -sa;
}

// Triangles (v, a, b) and (v, c, d) sharing the corner v only: whether they certainly meet at v
// alone. Tries the planes through v that hold the normal of (v, a, b) and the bisector of one
// ray of each triangle (from v towards a or b, and towards c or d): for coplanar triangles whose
// wedges at v do not overlap, one of them separates. `plane`, when given, receives the normal of
// the separating plane (for tests).
inline bool meetAtSharedCornerOnly(const PadPoint& v, const PadPoint& a, const PadPoint& b, const PadPoint& c,
                                   const PadPoint& d, Eigen::Vector3d* plane = nullptr) {
  const Eigen::Vector3d n = (a.x - v.x).cross(b.x - v.x);
  const auto unit = [&](const PadPoint& p) {
    const Eigen::Vector3d r = p.x - v.x;
    const double len = r.norm();
    return len > 0 ? Eigen::Vector3d(r / len) : Eigen::Vector3d::Zero();
  };
  const std::array<Eigen::Vector3d, 2> mine{{unit(a), unit(b)}}, theirs{{unit(c), unit(d)}};
  for (const Eigen::Vector3d& p : mine)
    for (const Eigen::Vector3d& q : theirs) {
      const Eigen::Vector3d m = n.cross(p + q);
      if (separates(m, v, a, b, c, d)) {
        if (plane) *plane = m;
        return true;
      }
    }
  return false;
}

// Triangles s and t without a shared corner: whether they are certainly disjoint, by the
// separating axis test (the two normals, the nine cross products of an edge of each, and, for
// coplanar triangles, the six normals of their edges within their planes; two disjoint
// triangles are separated along one of them), with certified projections. `axis`,
// when given, receives the separating axis (for tests).
inline bool certainlyDisjoint(const std::array<PadPoint, 3>& s, const std::array<PadPoint, 3>& t,
                              Eigen::Vector3d* axis = nullptr) {
  // The six corners relative to o = s[0], computed once for every axis: w = x - o, |w|, and the
  // pads x.pad + o.pad.
  const PadPoint& o = s[0];
  std::array<Eigen::Vector3d, 6> w, aw;
  std::array<double, 6> pad;
  for (std::size_t k = 0; k < 6; ++k) {
    const PadPoint& x = k < 3 ? s[k] : t[k - 3];
    w[k] = x.x - o.x;
    aw[k] = w[k].cwiseAbs();
    pad[k] = x.pad + o.pad;
  }
  // Whether every corner of s is certainly below every corner of t along m, or above.
  const auto along = [&](const Eigen::Vector3d& m) {
    const Eigen::Vector3d am = m.cwiseAbs();
    if (!(am.maxCoeff() > 0)) return false;
    const double am_sum = am.sum();
    // the projections and their bounds, relative to o
    double s_lo = HUGE_VAL, s_hi = -HUGE_VAL, t_lo = HUGE_VAL, t_hi = -HUGE_VAL;
    for (std::size_t k = 0; k < 6; ++k) {
      const double p = m.dot(w[k]);
      const double bound = (4 * 0x1.0p-52 * am.dot(aw[k]) + pad[k] * am_sum) * (1 + 1e-12);
      // (no bound so small that underflow could spoil it; o itself excepted)
      if (!(bound > 1e-280) && k != 0) return false;
      double& lo = k < 3 ? s_lo : t_lo;
      double& hi = k < 3 ? s_hi : t_hi;
      lo = std::min(lo, p - bound);
      hi = std::max(hi, p + bound);
    }
    const bool apart = s_hi < t_lo || t_hi < s_lo;
    if (apart && axis) *axis = m;
    return apart;
  };
  std::array<Eigen::Vector3d, 3> es, et;
  for (int k = 0; k < 3; ++k) {
    es[static_cast<std::size_t>(k)] = s[static_cast<std::size_t>((k + 1) % 3)].x - s[static_cast<std::size_t>(k)].x;
    et[static_cast<std::size_t>(k)] = t[static_cast<std::size_t>((k + 1) % 3)].x - t[static_cast<std::size_t>(k)].x;
  }
  const Eigen::Vector3d ns = es[0].cross(es[1]), nt = et[0].cross(et[1]);
  if (along(ns) || along(nt)) return true;
  // The nine cross products of an edge of each, and the six normals of the edges within their
  // triangles' planes (for coplanar triangles every cross product is their normal or zero, and
  // one of these separates them). The answer is whether any of the 17 separates, so the order
  // only decides how soon: triangles whose normals lie within about 0.06 degrees of each other
  // (sin^2 < 1e-6) try the edge normals first. In the sweeps these are coplanar cap triangles,
  // and the cross products were then 9 wasted projections before the axis that separated.
  const auto crossed = [&] {
    for (const Eigen::Vector3d& e : es)
      for (const Eigen::Vector3d& f : et)
        if (along(e.cross(f))) return true;
    return false;
  };
  const auto inPlane = [&] {
    for (const Eigen::Vector3d& e : es)
      if (along(ns.cross(e))) return true;
    for (const Eigen::Vector3d& f : et)
      if (along(nt.cross(f))) return true;
    return false;
  };
  const bool coplanar = ns.cross(nt).squaredNorm() < 1e-6 * ns.squaredNorm() * nt.squaredNorm();
  return coplanar ? inPlane() || crossed() : crossed() || inPlane();
}

}  // namespace steady::sweep::detail
