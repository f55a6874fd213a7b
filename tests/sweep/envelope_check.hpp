#pragma once
// Independent geometric oracles of the swept-volume tests (envelope and inside test): more test
// meshes (torus, extruded polygons), a generalized winding number, point/mesh distances, the
// signed distance of a point to a posed body, and a certified bracket of its minimum over the
// motion (Lipschitz branch and bound). Nothing here calls steady::sweep; only the poses come
// from steady::core.
#include "sweep/sweep_test.hpp"

#include <steady/core/motion.hpp>
#include <steady/sweep/body.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <queue>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace steady_sweep_test {

// A validated body from a test mesh, and the one-span motion from B to C.
inline steady::sweep::Body makeBody(const Mesh& m) { return steady::sweep::Body(m.v, m.f); }
inline steady::Motion3 single(const steady::Affine3& B, const steady::Affine3& C) {
  return steady::Motion3::polySam(std::vector<steady::Affine3>{B, C});
}

// ---- meshes ------------------------------------------------------------------------------------

// A torus about the z axis through c: major radius R, minor radius r, nu x nv quads split in two.
// Outward: d/du x d/dv points away from the tube's core circle.
inline Mesh torus(double R, double r, int nu, int nv, const V& c = V::Zero()) {
  Mesh m;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
      m.v.push_back(c + V((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)));
    }
  auto id = [&](int i, int j) { return ((i + nu) % nu) * nv + (j + nv) % nv; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int a = id(i, j), b = id(i + 1, j), cc = id(i, j + 1), d = id(i + 1, j + 1);
      m.f.push_back({a, b, d});
      m.f.push_back({a, d, cc});
    }
  return m;
}

// The prism over a counter-clockwise simple polygon (x, y) from z0 to z1. The caps are fans
// from polygon vertex `fan`, which must see every other vertex (a convex polygon: any vertex;
// an L: its reflex vertex).
inline Mesh prism(const std::vector<std::array<double, 2>>& poly, double z0, double z1, int fan) {
  Mesh m;
  const int n = static_cast<int>(poly.size());
  for (const auto& p : poly) m.v.emplace_back(p[0], p[1], z0);
  for (const auto& p : poly) m.v.emplace_back(p[0], p[1], z1);
  for (int k = 1; k + 1 < n; ++k) {
    const int a = fan, b = (fan + k) % n, c = (fan + k + 1) % n;
    m.f.push_back({n + a, n + b, n + c});  // top: counter-clockwise seen from +z
    m.f.push_back({a, c, b});              // bottom: reversed
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.f.push_back({i, j, n + j});
    m.f.push_back({i, n + j, n + i});
  }
  return m;
}

// An L-shaped prism (non-convex): the square [0, 2]^2 minus [1, 2]^2, extruded over [0, h].
inline Mesh lShape(double h = 0.6) {
  return prism({{{0, 0}}, {{2, 0}}, {{2, 1}}, {{1, 1}}, {{1, 2}}, {{0, 2}}}, 0.0, h, 3);
}

// The prism over a polygon star-shaped about the z axis (corners (x, y) counter-clockwise),
// from z = 0 to z1, its caps fanned from their centres (0, 0, 0) and (0, 0, z1).
inline Mesh starPrismOf(const std::vector<std::array<double, 2>>& corners, double z1) {
  const int n = static_cast<int>(corners.size());
  Mesh m;
  for (const double z : {0.0, z1})
    for (const auto& p : corners) m.v.emplace_back(p[0], p[1], z);
  const int bottom_centre = 2 * n, top_centre = 2 * n + 1;
  m.v.emplace_back(0, 0, 0.0);
  m.v.emplace_back(0, 0, z1);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.f.push_back({top_centre, n + i, n + j});  // counter-clockwise seen from +z
    m.f.push_back({bottom_centre, j, i});
    m.f.push_back({i, j, n + j});
    m.f.push_back({i, n + j, n + i});
  }
  return m;
}

inline Mesh transformed(Mesh m, const steady::Affine3& A) {
  for (auto& p : m.v) p = A.applyPoint(p);
  return m;
}

// ---- mesh measures -----------------------------------------------------------------------------

// Generalized winding number of a closed triangle mesh about p: the sum of the signed solid
// angles of the triangles (Van Oosterom and Strackee's formula) over 4 pi. An integer (the
// number of times the surface wraps around p) away from the surface.
inline double windingNumber(const std::vector<V>& v, const Faces& f, const V& p) {
  double total = 0;
  for (const auto& t : f) {
    const V a = v[t[0]] - p, b = v[t[1]] - p, c = v[t[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    total += 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
  }
  return total / (4 * M_PI);
}

inline double meshDistance(const std::vector<V>& v, const Faces& f, const V& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : f) best = std::min(best, pointTriangleDistance(p, v[t[0]], v[t[1]], v[t[2]]));
  return best;
}

// Signed distance of p to the solid bounded by a closed mesh: negative inside (winding >= 1/2).
inline double signedDistance(const std::vector<V>& v, const Faces& f, const V& p) {
  const double d = meshDistance(v, f, p);
  return windingNumber(v, f, p) >= 0.5 ? -d : d;
}

// Enclosed volume and area by the divergence theorem.
inline double meshVolume(const std::vector<V>& v, const Faces& f) {
  double s = 0;
  for (const auto& t : f) s += v[t[0]].dot(v[t[1]].cross(v[t[2]]));
  return s / 6;
}
inline double meshArea(const std::vector<V>& v, const Faces& f) {
  double s = 0;
  for (const auto& t : f) s += 0.5 * (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).norm();
  return s;
}

inline V boxLo(const std::vector<V>& v) {
  V lo = v.front();
  for (const V& p : v) lo = lo.cwiseMin(p);
  return lo;
}
inline V boxHi(const std::vector<V>& v) {
  V hi = v.front();
  for (const V& p : v) hi = hi.cwiseMax(p);
  return hi;
}

// The directed-edge count of a closed, oriented, 2-manifold mesh: every directed edge (a, b)
// exactly once and its reverse (b, a) exactly once. Returns "" or a description of the first
// faults (with their counts).
inline std::string directedEdgeFaults(const Faces& f, std::size_t nv) {
  std::map<std::pair<int, int>, int> count;
  std::size_t bad_index = 0, repeated = 0;
  for (const auto& t : f)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a < 0 || b < 0 || static_cast<std::size_t>(a) >= nv || static_cast<std::size_t>(b) >= nv) ++bad_index;
      if (a == b) ++repeated;
      ++count[{a, b}];
    }
  std::size_t twice = 0, unmatched = 0;
  std::string first;
  for (const auto& [e, c] : count) {
    if (c != 1) {
      ++twice;
      if (first.empty()) first = "edge " + std::to_string(e.first) + "->" + std::to_string(e.second) + " used " + std::to_string(c) + " times";
    }
    const auto r = count.find({e.second, e.first});
    if (r == count.end() || r->second != 1) {
      ++unmatched;
      if (first.empty()) first = "edge " + std::to_string(e.first) + "->" + std::to_string(e.second) + " has " +
                                 std::to_string(r == count.end() ? 0 : r->second) + " reverse edges";
    }
  }
  if (bad_index + repeated + twice + unmatched == 0) return "";
  return std::to_string(bad_index) + " bad indices, " + std::to_string(repeated) + " repeated-vertex edges, " +
         std::to_string(twice) + " directed edges used more than once, " + std::to_string(unmatched) +
         " without exactly one reverse; first: " + first;
}

// Depth of x in the Minkowski sum of the box [lo, hi] and the segment [0, d]:
// max over tau in [0, 1] of min over the six box constraints on x - tau d (positive inside; at
// most the distance to the boundary, and when negative, the distance to the sum is at least
// its magnitude). The min of affine functions of tau is concave and piecewise affine, so the
// max is at tau = 0, 1 or where two of them cross.
inline double minkowskiDepth(const V& x, const V& lo, const V& hi, const V& d) {
  std::array<double, 6> a{}, b{};  // f_j(tau) = a_j + b_j tau
  for (int i = 0; i < 3; ++i) {
    a[2 * i] = x[i] - lo[i];
    b[2 * i] = -d[i];
    a[2 * i + 1] = hi[i] - x[i];
    b[2 * i + 1] = d[i];
  }
  auto f = [&](double t) {
    double m = std::numeric_limits<double>::infinity();
    for (int j = 0; j < 6; ++j) m = std::min(m, a[j] + b[j] * t);
    return m;
  };
  double best = std::max(f(0.0), f(1.0));
  for (int j = 0; j < 6; ++j)
    for (int k = j + 1; k < 6; ++k)
      if (b[j] != b[k]) {
        const double t = (a[k] - a[j]) / (b[j] - b[k]);
        if (t > 0 && t < 1) best = std::max(best, f(t));
      }
  return best;
}

// Connected components of a triangle mesh through shared (undirected) edges, largest (most
// triangles) first.
inline std::vector<Faces> edgeComponents(const Faces& f) {
  std::vector<int> parent(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) parent[i] = static_cast<int>(i);
  auto root = [&](int x) {
    while (parent[static_cast<std::size_t>(x)] != x) x = parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    return x;
  };
  std::map<std::pair<int, int>, int> first;
  for (std::size_t i = 0; i < f.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int a = std::min(f[i][k], f[i][(k + 1) % 3]), b = std::max(f[i][k], f[i][(k + 1) % 3]);
      const auto [it, added] = first.emplace(std::make_pair(a, b), static_cast<int>(i));
      if (!added) parent[static_cast<std::size_t>(root(it->second))] = root(static_cast<int>(i));
    }
  std::map<int, Faces> comps;
  for (std::size_t i = 0; i < f.size(); ++i) comps[root(static_cast<int>(i))].push_back(f[i]);
  std::vector<Faces> out;
  for (auto& [r, tris] : comps) out.push_back(std::move(tris));
  std::sort(out.begin(), out.end(), [](const Faces& a, const Faces& b) { return a.size() > b.size(); });
  return out;
}

// The connected components (edgeComponents): for each, its triangle count, signed volume and
// area, largest first ("n tri, V, A; ...").
inline std::string componentSummary(const std::vector<V>& v, const Faces& f, std::size_t max_listed = 6) {
  std::vector<std::tuple<std::size_t, double, double>> rows;
  for (const Faces& tris : edgeComponents(f)) rows.emplace_back(tris.size(), meshVolume(v, tris), meshArea(v, tris));
  std::string out = std::to_string(rows.size()) + " components:";
  char buf[128];
  for (std::size_t i = 0; i < rows.size() && i < max_listed; ++i) {
    std::snprintf(buf, sizeof buf, " [%zu tri, V %.3g, A %.3g]", std::get<0>(rows[i]), std::get<1>(rows[i]), std::get<2>(rows[i]));
    out += buf;
  }
  if (rows.size() > max_listed) out += " ...";
  return out;
}

// ---- the moving body ---------------------------------------------------------------------------

// A body mesh moving along a polySAM, evaluated by the oracles below.
//
// Speeds. On span i a body point at W (span time 0) is at A^tau W and moves with velocity
// v(A^tau W) = L^tau v(W), v(x) = M x + u (per unit span time), so over |tau - c| <= r its speed
// is at most e^{|M| r} |v(X(c))|, and |v| is convex, so over the body it is at most
// e^{|M|_F r} max over the vertices of |v(X_k(c))| (the body lies in the hull of its vertices).
struct MovingBody {
  Mesh mesh;
  steady::Motion3 motion;
  std::vector<double> lognorm;  // per span: |M|_F, at least the spectral norm

  MovingBody(Mesh m, steady::Motion3 mo) : mesh(std::move(m)), motion(std::move(mo)) {
    for (std::size_t i = 0; i < motion.spanCount(); ++i) lognorm.push_back(motion.span(i).log().M.norm() * (1 + 1e-12));
  }

  std::vector<V> posed(std::size_t span, double tau) const {
    const steady::Affine3 P = motion.span(span).pose(tau);
    std::vector<V> w;
    w.reserve(mesh.v.size());
    for (const V& p : mesh.v) w.push_back(P.applyPoint(p));
    return w;
  }
  double signedDistance(std::size_t span, double tau, const V& x) const {
    return steady_sweep_test::signedDistance(posed(span, tau), mesh.f, x);
  }
  // The signed distance at (span, tau) and the largest vertex speed there.
  double signedDistance(std::size_t span, double tau, const V& x, double& vmax) const {
    const std::vector<V> w = posed(span, tau);
    const auto& sp = motion.span(span);
    vmax = 0;
    for (const V& p : w) vmax = std::max(vmax, sp.velocity(p).norm());
    vmax *= 1 + 1e-9;
    return steady_sweep_test::signedDistance(w, mesh.f, x);
  }
};

// A certified bracket [lo, hi] of min over the motion (all spans, span times in [0, 1]) of the
// signed distance of x to the posed body (negative inside): hi is attained at (span, tau).
// Branch and bound: the distance of x to a surface whose points move at speed <= S changes at
// rate <= S (through zero when x crosses it), so on [c - r, c + r] the signed distance is at least
// sd(c) - e^{|M| r} vmax(c) r (see MovingBody). Refines the interval of smallest lower bound until
// stop(lo, hi) says the answer is decided or `budget` evaluations are spent.
struct MinBracket {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  std::size_t span = 0;
  double tau = 0;
  int evaluations = 0;
};

template <class Stop>
MinBracket minSignedDistance(const MovingBody& mb, const V& x, Stop&& stop, int budget = 4000, int initial = 16,
                             double tau_max_of_last = 1.0, std::size_t last_span = static_cast<std::size_t>(-1)) {
  struct Item {
    double lower, c, r;
    std::size_t span;
    bool operator<(const Item& o) const { return lower > o.lower; }  // smallest lower bound first
  };
  MinBracket b;
  std::priority_queue<Item> queue;
  const std::size_t spans =
      last_span == static_cast<std::size_t>(-1) ? mb.motion.spanCount() : std::min(mb.motion.spanCount(), last_span + 1);
  auto push = [&](std::size_t s, double c, double r) {
    double vmax = 0;
    const double v = mb.signedDistance(s, c, x, vmax);
    ++b.evaluations;
    if (v < b.hi) {
      b.hi = v;
      b.span = s;
      b.tau = c;
    }
    queue.push({v - std::exp(mb.lognorm[s] * r) * vmax * r, c, r, s});
  };
  for (std::size_t s = 0; s < spans; ++s) {
    const double end = s + 1 == spans ? tau_max_of_last : 1.0;
    for (int k = 0; k < initial; ++k) push(s, end * (k + 0.5) / initial, 0.5 * end / initial);
  }
  for (;;) {
    b.lo = queue.empty() ? b.hi : std::min(queue.top().lower, b.hi);
    if (stop(b.lo, b.hi) || queue.empty() || b.evaluations >= budget) return b;
    const Item it = queue.top();
    queue.pop();
    if (it.lower >= b.hi) continue;  // cannot hold a smaller value than the best one
    const double h = 0.5 * it.r;
    push(it.span, it.c - h, h);
    push(it.span, it.c + h, h);
  }
}

}  // namespace steady_sweep_test

namespace steady_sweep_test {

// ---- random motions ----------------------------------------------------------------------------

enum class MotionKind { Screw, Translation, Affine, ShearScale, PolySam };

inline const char* motionName(MotionKind k) {
  switch (k) {
    case MotionKind::Screw: return "screw";
    case MotionKind::Translation: return "translation";
    case MotionKind::Affine: return "affine";
    case MotionKind::ShearScale: return "shear+scale";
    case MotionKind::PolySam: return "polysam";
  }
  return "?";
}

// A rigid pose: rotation about a random axis, then a translation of up to `reach`.
inline steady::Affine3 randomRigidPose(std::mt19937_64& rng, double reach = 1.0) {
  return steady::Affine3::translation(V(uniform(rng, -reach, reach), uniform(rng, -reach, reach), uniform(rng, -reach, reach))) *
         steady::Affine3::rotation(randomUnit(rng), uniform(rng, -3, 3));
}

// A random relative motion A of the given kind (sizes about those of a unit body).
inline steady::Affine3 randomRelative(MotionKind kind, std::mt19937_64& rng) {
  using steady::Affine3;
  switch (kind) {
    case MotionKind::Screw: {
      const V axis = randomUnit(rng), through(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      return Affine3::translation(through + uniform(rng, -1.5, 1.5) * axis) * Affine3::rotation(axis, uniform(rng, 0.8, 2.8)) *
             Affine3::translation(-through);
    }
    case MotionKind::Translation:
      return Affine3::translation(uniform(rng, 0.5, 2.5) * randomUnit(rng));
    case MotionKind::ShearScale: {
      const V s = randomUnit(rng), d = s.unitOrthogonal();
      return Affine3::translation(randomUnit(rng)) * Affine3::shear(s, d, uniform(rng, 0.5, 1.2)) *
             Affine3::scaling(V(uniform(rng, 0.5, 1.8), uniform(rng, 0.5, 1.8), uniform(rng, 0.5, 1.8))) *
             Affine3::rotation(randomUnit(rng), uniform(rng, -1, 1));
    }
    case MotionKind::Affine:
    case MotionKind::PolySam:
    default: {
      for (;;) {
        Eigen::Matrix3d X;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) X(i, j) = uniform(rng, -0.7, 0.7);
        // exp(X) by scaling and squaring of a Taylor series (X is small): det > 0, a real log.
        Eigen::Matrix3d E = Eigen::Matrix3d::Identity(), term = Eigen::Matrix3d::Identity();
        const Eigen::Matrix3d Y = X / 16;
        for (int k = 1; k < 20; ++k) {
          term = term * Y / k;
          E += term;
        }
        for (int k = 0; k < 4; ++k) E = E * E;
        // Condition number from the eigenvalues of E^T E (at most 400: singular values within 20).
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(E.transpose() * E, Eigen::EigenvaluesOnly);
        if (!(es.eigenvalues()(0) > 0) || es.eigenvalues()(2) / es.eigenvalues()(0) > 400) continue;
        return Affine3(E, V(uniform(rng, -1.5, 1.5), uniform(rng, -1.5, 1.5), uniform(rng, -1.5, 1.5)));
      }
    }
  }
}

// A random motion: one span of `kind`, or (PolySam) 2 or 3 spans of mixed kinds.
inline steady::Motion3 randomMotion(MotionKind kind, std::mt19937_64& rng) {
  const steady::Affine3 B = randomRigidPose(rng, 0.5);
  std::vector<steady::Affine3> poses{B};
  // Draws until a SAM exists (a shear composed with a rotation can have no real log).
  auto next = [&](MotionKind k) {
    for (;;) {
      const steady::Affine3 C = randomRelative(k, rng) * poses.back();
      if (steady::samExists(poses.back(), C)) return C;
    }
  };
  if (kind != MotionKind::PolySam) {
    poses.push_back(next(kind));
  } else {
    const int spans = 2 + static_cast<int>(rng() % 2);
    const MotionKind kinds[] = {MotionKind::Screw, MotionKind::Translation, MotionKind::Affine, MotionKind::ShearScale};
    for (int i = 0; i < spans; ++i) poses.push_back(next(kinds[rng() % 4]));
  }
  return steady::Motion3::polySam(poses);
}

}  // namespace steady_sweep_test
