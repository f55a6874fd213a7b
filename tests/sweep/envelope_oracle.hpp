#pragma once
// The full check of one swept envelope against the independent oracles of envelope_check.hpp:
// topology, the reported measures, containment of the posed bodies, a sample of envelope
// vertices against the true boundary, and the inside test. Shared by the envelope tests
// (test_envelope.cpp) and the seeded stress campaign (stress_sweep.cpp), which runs the same
// checks on thousands of random cases and needs their figures, not only pass or fail.
#include <steady/sweep/envelope.hpp>
#include <steady/sweep/inside.hpp>

#include "sweep/envelope_check.hpp"
#include "sweep/sweep_test.hpp"

#include <steady/core/motion.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace steady_sweep_test {

// At most this many failure messages per check and case (the counts are always reported).
constexpr int kMaxMessages = 5;

struct CheckOptions {
  int containment_points = 240;  // posed body vertices (and as many face points / 4) tested
  int boundary_vertices = 120;   // envelope vertices tested against the true boundary
  int cross_points = 100;        // points compared with SweptVolume
  // Faces whose two sides are checked (checkFaceSides; a seeded sample when fewer than the
  // envelope's faces): every face by default.
  std::size_t face_sides = std::numeric_limits<std::size_t>::max();
  int expected_shells = 1;
  int expected_euler = 2;        // V - E + F of the envelope (2: a sphere; 0: a torus); 99: unchecked
};

// What checkEnvelope measured, for callers that report figures (distances in units of ε).
struct CheckStats {
  double worst_outside = 0;   // farthest posed body point outside the envelope
  double worst_boundary = 0;  // farthest sampled envelope vertex from the true boundary
  int containment_checked = 0, containment_failed = 0;
  int boundary_checked = 0, boundary_failed = 0, boundary_undecided = 0;
  int cross_checked = 0, cross_mismatched = 0;
  int sides_checked = 0, sides_failed = 0, sides_undecided = 0;  // checkFaceSides: points, failures
  double worst_side = 0;  // checkFaceSides' largest broken distance
};

// The certified bracket of min over the motion of the signed distance of x to the posed body,
// refined until it says whether x is within T of the true boundary (|min| <= T) or not (at
// most 6000 evaluations; an undecided bracket is left as it is).
inline MinBracket boundaryBracket(const MovingBody& mb, const V& x, double T) {
  return minSignedDistance(
      mb, x, [&](double blo, double bhi) { return (bhi <= T && blo >= -T) || blo > T || bhi < -T; }, 6000);
}

// Face interiors, which the vertex checks cannot see: a face can stand off the true boundary
// while its vertices lie on it, as a flat mouth filling across a concave stretch of boundary did
// in campaign cases 224 and 1249 before the filling probes (filling points 4 to more than 8 ε
// outside the swept volume S, every vertex within ε of the boundary). The points kSideOffset ε
// beneath and above each face's centroid, along its unit normal, are put to SweptVolume's
// inside test; where it disagrees with the face's own side (beneath inside, above outside) and
// the point lies farther than 3 ε from the envelope (nearer, a thin part of S or of the outside
// may end there), the face is a suspect, and the certified oracle decides two promises of the
// envelope (envelope.hpp):
// - the face's centroid lies within T = 1.01 ε of the true boundary, as every envelope vertex
//   must (boundaryBracket, as in checkEnvelope's vertex sample);
// - a point outside the envelope is not inside a posed body (it lies more than 3 ε from the
//   envelope, so the body posed there would stick out by more than ε).
// The inside test only picks the suspects, so a face whose side points it puts on the face's
// side is not examined further: this check is aimed at the envelope, and the random cross-check
// of checkEnvelope compares the inside test itself with the oracle. `faces` caps the number of
// faces (a seeded sample; every face when it is at least their number). `worst` is the largest
// broken distance in ε: of a centroid off the boundary, or of a posed body point outside the
// envelope; `off_faces` lists the faces whose centroid is off the boundary.
constexpr double kSideOffset = 4.0;
// Whether some face of the mesh lies within r of p (a box test first, then the distance).
inline bool withinDistance(const std::vector<V>& v, const Faces& f, const V& p, double r) {
  for (const auto& t : f) {
    const V lo = v[t[0]].cwiseMin(v[t[1]]).cwiseMin(v[t[2]]), hi = v[t[0]].cwiseMax(v[t[1]]).cwiseMax(v[t[2]]);
    if (((lo.array() - r) > p.array()).any() || ((hi.array() + r) < p.array()).any()) continue;
    if (pointTriangleDistance(p, v[t[0]], v[t[1]], v[t[2]]) <= r) return true;
  }
  return false;
}
struct SideCheck {
  int checked = 0, suspects = 0, failed = 0, undecided = 0;
  double worst = 0;
  std::vector<int> off_faces;  // the faces whose centroid the oracle finds off the true boundary
};
inline SideCheck checkFaceSides(const steady::sweep::Envelope& env, const MovingBody& mb,
                                const steady::sweep::SweptVolume& sv, std::size_t faces, std::mt19937_64& rng) {
  const std::vector<V>& ev = env.vertices;
  const Faces& ef = env.triangles;
  const double eps = env.tolerance;
  std::vector<std::size_t> order(ef.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  if (faces < order.size()) {
    std::shuffle(order.begin(), order.end(), rng);
    order.resize(faces);
  }
  const double T = eps * 1.01;
  SideCheck c;
  for (const std::size_t f : order) {
    const auto& t = ef[f];
    const V n = (ev[t[1]] - ev[t[0]]).cross(ev[t[2]] - ev[t[0]]);
    if (!(n.norm() > 0)) continue;
    const V centroid = (ev[t[0]] + ev[t[1]] + ev[t[2]]) / 3.0;
    bool suspect = false;
    for (const int side : {-1, 1}) {
      const V x = centroid + side * kSideOffset * eps * n.normalized();
      ++c.checked;
      if (sv.contains(x) == (side < 0) || withinDistance(ev, ef, x, 3 * eps)) continue;
      suspect = true;
      if (windingNumber(ev, ef, x) >= 0.5) continue;
      const MinBracket b = minSignedDistance(mb, x, [](double lo, double hi) { return hi < 0 || lo > 0; }, 20000);
      if (!(b.hi < 0 || b.lo > 0)) ++c.undecided;
      if (!(b.hi < 0)) continue;
      const double D = meshDistance(ev, ef, x) / eps;
      c.worst = std::max(c.worst, D);
      if (++c.failed <= kMaxMessages)
        ADD_FAILURE() << "the point " << kSideOffset << " eps " << (side < 0 ? "beneath" : "above") << " envelope face "
                      << f << ", at " << x.transpose() << ", lies inside the body posed at span " << b.span << " tau "
                      << b.tau << " and " << D << " eps outside the envelope";
    }
    if (!suspect) continue;
    ++c.suspects;
    const MinBracket b = boundaryBracket(mb, centroid, T);
    if (b.lo > T || b.hi < -T) {
      const double off = b.lo > T ? b.lo : -b.hi;
      c.worst = std::max(c.worst, off / eps);
      c.off_faces.push_back(static_cast<int>(f));
      if (++c.failed <= kMaxMessages)
        ADD_FAILURE() << "the centroid of envelope face " << f << ", at " << centroid.transpose() << ", is "
                      << (b.lo > T ? "farther than " : "deeper than ") << off / eps << " eps "
                      << (b.lo > T ? "from every posed body" : "inside the body posed at span " + std::to_string(b.span) +
                                                                   " tau " + std::to_string(b.tau))
                      << " (not on the true boundary)";
    } else if (!(b.hi <= T && b.lo >= -T)) {
      ++c.undecided;
    }
  }
  return c;
}

// Every check of one envelope; failures are reported with their numbers, and the figures in
// `stats` when given.
inline void checkEnvelope(const Mesh& mesh, const steady::Motion3& motion, const steady::sweep::Envelope& env,
                          double eps_expected, std::mt19937_64& rng, const std::string& name, const CheckOptions& co = {},
                          CheckStats* stats = nullptr) {
  SCOPED_TRACE(name);
  const steady::sweep::Body body = makeBody(mesh);
  const MovingBody mb(mesh, motion);
  const std::vector<V>& ev = env.vertices;
  const Faces& ef = env.triangles;
  ASSERT_FALSE(ef.empty()) << "empty envelope";
  const V lo = boxLo(ev), hi = boxHi(ev);
  const double scale = (hi - lo).norm();
  const double eps = env.tolerance;

  // The tolerance used: relative_tolerance times the body's box diagonal, or as given.
  EXPECT_NEAR(eps, eps_expected, 1e-12 * eps_expected);
  EXPECT_EQ(env.cycle_open_edges, 0u) << "the sweep cycle is not closed";

  // Topology, by the library's inspectMesh and by our own directed-edge count.
  const steady::sweep::MeshCheck mc = steady::sweep::inspectMesh(ev, ef, true);
  EXPECT_TRUE(mc.closed);
  EXPECT_TRUE(mc.manifold);
  EXPECT_TRUE(mc.oriented);
  EXPECT_EQ(mc.self_intersections, 0);
  EXPECT_EQ(mc.shells, co.expected_shells) << componentSummary(ev, ef);
  EXPECT_GT(mc.volume, 0);
  const std::string edges = directedEdgeFaults(ef, ev.size());
  EXPECT_EQ(edges, "") << "directed edges";
  std::vector<char> used(ev.size(), 0);
  for (const auto& t : ef)
    for (int k : t) used[static_cast<std::size_t>(k)] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "unused envelope vertices";
  if (co.expected_euler != 99 && edges.empty()) {
    const long euler = static_cast<long>(ev.size()) - static_cast<long>(3 * ef.size() / 2) + static_cast<long>(ef.size());
    EXPECT_EQ(euler, co.expected_euler) << "Euler characteristic V - E + F";
  }
  // Winding numbers cross the edges where patches meet; rays label one patch per connected
  // group and a check sample of 64, whose rays must agree (a disagreement rays the whole group).
  // (The number of rays is no measure of that: a polySAM of the UV sphere, campaign case 2754,
  // has 6 groups of patches, hence 69 rays, and no disagreement.)
  EXPECT_EQ(env.label_mismatches, 0u) << "labels propagated across edges disagreed with their check rays";
  EXPECT_LE(env.patches_by_ray, env.patches);
  // The reported measures against our own.
  const double vol = meshVolume(ev, ef), area = meshArea(ev, ef);
  EXPECT_NEAR(env.volume, vol, 1e-9 * std::abs(vol));
  EXPECT_NEAR(env.area, area, 1e-9 * area);
  EXPECT_NEAR(mc.volume, vol, 1e-9 * std::abs(vol));
  // The swept volume holds the body at every time: at least the largest posed volume (minus ε A).
  double posed_max = 0;
  for (std::size_t s = 0; s < motion.spanCount(); ++s)
    for (const double tau : {0.0, 0.5, 1.0}) posed_max = std::max(posed_max, meshVolume(mb.posed(s, tau), mesh.f));
  EXPECT_GE(vol, posed_max - eps * area) << "envelope volume below a posed body's volume";

  // Containment: posed body vertices (and face points) lie inside the envelope or within ε.
  int checked = 0, failed = 0;
  double worst = 0;
  const int face_points = co.containment_points / 4;
  for (int n = 0; n < co.containment_points + face_points; ++n) {
    const std::size_t s = rng() % motion.spanCount();
    const double tau = n % 7 == 0 ? (n % 2 ? 0.0 : 1.0) : uniform(rng, 0, 1);
    const std::vector<V> w = mb.posed(s, tau);
    V x;
    if (n < co.containment_points) {
      x = w[rng() % w.size()];
    } else {
      const auto& f = mesh.f[rng() % mesh.f.size()];
      double b0 = uniform(rng, 0, 1), b1 = uniform(rng, 0, 1);
      if (b0 + b1 > 1) b0 = 1 - b0, b1 = 1 - b1;
      x = w[f[0]] + b0 * (w[f[1]] - w[f[0]]) + b1 * (w[f[2]] - w[f[0]]);
    }
    ++checked;
    if (windingNumber(ev, ef, x) >= 0.5) continue;
    const double d = meshDistance(ev, ef, x);
    worst = std::max(worst, d / eps);
    if (d > eps * (1 + 1e-6) + 1e-12 * scale) {
      if (++failed <= kMaxMessages)
        ADD_FAILURE() << "posed body point " << x.transpose() << " (span " << s << ", tau " << tau
                      << ") is outside the envelope by " << d << " = " << d / eps << " eps";
    }
  }
  // The true boundary: every envelope vertex (a sample) has min over time of its signed distance
  // to the posed body within [-T, T], T = ε (+1% for the branch and bound's resolution): it is
  // within ε of some posed body, and never deeper than ε inside one (not interior).
  const double T = eps * 1.01 + 1e-9 * scale;
  int bchecked = 0, bfailed = 0, bundecided = 0;
  double bworst = 0;
  std::vector<std::size_t> order(ev.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  order.resize(std::min<std::size_t>(order.size(), static_cast<std::size_t>(co.boundary_vertices)));
  for (const std::size_t i : order) {
    const V& x = ev[i];
    const MinBracket b = boundaryBracket(mb, x, T);
    ++bchecked;
    if (b.lo > T || b.hi < -T) {
      const double off = b.lo > T ? b.lo : b.hi;
      bworst = std::max(bworst, std::abs(off) / eps);
      if (++bfailed <= kMaxMessages)
        ADD_FAILURE() << "envelope vertex " << i << " at " << x.transpose()
                      << (b.lo > T ? " is farther than " : " is deeper than ") << std::abs(off) << " = "
                      << std::abs(off) / eps << " eps " << (b.lo > T ? "from every posed body" : "inside the body posed at span ")
                      << (b.lo > T ? "" : std::to_string(b.span) + " tau " + std::to_string(b.tau)) << " (not on the boundary)";
    } else if (!(b.hi <= T && b.lo >= -T)) {
      ++bundecided;
    } else {
      bworst = std::max(bworst, std::max(std::abs(b.hi), 0.0) / eps);
    }
  }
  EXPECT_LE(bundecided, bchecked / 50) << "envelope vertices the oracle could not decide within its budget";

  // Cross-check with the inside test on points farther than 3 ε from the envelope.
  const steady::sweep::SweptVolume sv(body, motion);
  int cchecked = 0, cmismatch = 0;
  const V pad = 0.1 * (hi - lo);
  for (int n = 0; n < co.cross_points; ++n) {
    const V x(uniform(rng, lo.x() - pad.x(), hi.x() + pad.x()), uniform(rng, lo.y() - pad.y(), hi.y() + pad.y()),
              uniform(rng, lo.z() - pad.z(), hi.z() + pad.z()));
    if (meshDistance(ev, ef, x) <= 3 * eps) continue;
    ++cchecked;
    const bool in_env = windingNumber(ev, ef, x) >= 0.5;
    const bool in_sv = sv.contains(x);
    if (in_env == in_sv) continue;
    const MinBracket b = minSignedDistance(
        mb, x, [&](double blo, double bhi) { return bhi < -eps || blo > eps; }, 20000);
    const char* truth = b.hi < -eps ? "inside" : (b.lo > eps ? "outside" : "undecided");
    if (++cmismatch <= kMaxMessages)
      ADD_FAILURE() << "point " << x.transpose() << ": envelope says " << (in_env ? "inside" : "outside")
                    << ", SweptVolume says " << (in_sv ? "inside" : "outside") << ", the oracle says " << truth
                    << " (min signed distance in [" << b.lo << ", " << b.hi << "], eps " << eps << ")";
  }
  // Both sides of the faces: a face off the true boundary with its vertices on it.
  const SideCheck sides = checkFaceSides(env, mb, sv, co.face_sides, rng);
  EXPECT_LE(sides.undecided, sides.checked / 1000 + 10) << "face side points the oracle could not decide within its budget";
  if (stats) {
    *stats = CheckStats{worst, bworst, checked, failed, bchecked, bfailed, bundecided, cchecked, cmismatch};
    stats->sides_checked = sides.checked;
    stats->sides_failed = sides.failed;
    stats->sides_undecided = sides.undecided;
    stats->worst_side = sides.worst;
  }
  std::printf("[ info     ] %-26s %6zu tri  eps %.2e  V %.5f  A %.4f  %.2fs | outside-by <= %.3f eps (%d/%d fail) | "
              "boundary <= %.3f eps (%d/%d fail, %d undecided) | cross %d/%d mismatch | face sides %d/%d fail | buried "
              "patches %zu, mouths %zu\n",
              name.c_str(), ef.size(), eps, vol, area, env.timings.total, worst, failed, checked, bworst, bfailed, bchecked,
              bundecided, cmismatch, cchecked, sides.failed, sides.checked, env.buried_patches_removed,
              env.pocket_mouths_filled);
}

// The envelope vertices inside the box [lo, hi] under the certified oracle: each must be within
// T = 1.01 eps of the true boundary (within T of some posed body and never deeper than T inside
// one; the 1% is the oracle's resolution, as in checkEnvelope). Reports each failure (up to
// kMaxMessages) and returns the counts, and the largest distance from the true boundary among
// the decided vertices (in eps).
struct NearCheck {
  int checked = 0, failed = 0, undecided = 0;
  double worst = 0;
};
inline NearCheck checkVerticesInBox(const steady::sweep::Envelope& env, const MovingBody& mb, const V& lo, const V& hi) {
  const double eps = env.tolerance;
  const double T = eps * 1.01;
  NearCheck c;
  for (std::size_t i = 0; i < env.vertices.size(); ++i) {
    const V& x = env.vertices[i];
    if ((x.array() < lo.array()).any() || (x.array() > hi.array()).any()) continue;
    ++c.checked;
    const MinBracket b = boundaryBracket(mb, x, T);
    if (b.lo > T || b.hi < -T) {
      c.worst = std::max(c.worst, (b.lo > T ? b.lo : -b.hi) / eps);
      if (++c.failed <= kMaxMessages)
        ADD_FAILURE() << "envelope vertex " << i << " at " << x.transpose() << " is "
                      << (b.lo > T ? "farther than " + std::to_string(b.lo / eps) + " eps from every posed body"
                                   : std::to_string(-b.hi / eps) + " eps inside the body posed at tau " + std::to_string(b.tau));
    } else if (!(b.hi <= T && b.lo >= -T)) {
      ++c.undecided;
    } else {
      c.worst = std::max(c.worst, std::abs(b.hi) / eps);
    }
  }
  return c;
}

// Envelope vertices checked against the boundary of the swept volume S itself: each one the
// certified oracle finds inside S (the minimum over the motion of its signed distance to the
// posed body is negative) must have, within T = 1.01 eps, a point the oracle certifies outside
// S (minimum above 0). checkVerticesInBox cannot see such a vertex: being inside S, it is within
// T of some posed body's surface, and it may lie less than T deep in every posed body and yet
// farther than T from the boundary of their union. Probes, until one is outside: along the
// envelope's vertex normal (the area-weighted normals of its faces) and the 26 directions to
// the faces, edges and corners of a cube at radius T (1 - 1e-3); then just off each face at the
// vertex (x + a t +- b n, t the direction into the face, n its normal, a = T/2, T/4, T/8,
// b = T 2^-j for j = 3 .. 12), where a thin crack of outside space ending at the vertex opens;
// then 256 seeded random directions at T (1 - 1e-3) and T/2; last, just off each face again,
// with t also along 7 directions spread between the face's edges at the vertex, a also
// T (1 - 1e-3) - b, and b at half octaves (T 2^-j/2, j = 2 .. 24): the thin cracks beside
// the walls of campaign cases 604 and 4214 lie over part of a face's angle only, and within
// hundredths of eps of its plane, and the outside beside a thin fin of case 8054 lies 11 to
// 20 degrees off it. `deep` lists the vertices whose every probe the oracle
// certifies inside; `undecided` counts those with some probe it could not decide and none
// outside.
struct AcrossCheck {
  int checked = 0, inside = 0, undecided = 0;
  std::vector<int> deep;
  // Counts the verdict of acrossPoint for the point (vertex or face) `index`.
  void count(int verdict, int index) {
    ++checked;
    if (verdict == 2) return;
    ++inside;
    if (verdict == 0) ++undecided;
    if (verdict < 0) deep.push_back(index);
  }
};
// One point x of checkAcross, with the envelope's outward normal there (zero if none) and, per
// face at x, the direction from x to its centroid, its unit normal and its two edges from x:
// 2 when x itself is not certified inside S, 1 when a probe is certified outside S, 0 when
// none is and some probe is undecided, -1 when every probe is certified inside.
inline int acrossPoint(const MovingBody& mb, const V& x, const V& normal, const std::vector<std::array<V, 4>>& faces,
                       double T) {
  static const std::vector<V> dirs = [] {
    std::vector<V> d;
    for (int n = 1; n <= 3; ++n)
      for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
          for (int k = -1; k <= 1; ++k)
            if (std::abs(i) + std::abs(j) + std::abs(k) == n) d.push_back(V(i, j, k).normalized());
    return d;
  }();
  static const std::vector<V> random_dirs = [] {
    std::vector<V> d;
    std::mt19937_64 rng(0x5eed);
    std::normal_distribution<double> g;
    while (d.size() < 256) {
      const V u(g(rng), g(rng), g(rng));
      if (u.norm() > 1e-3) d.push_back(u.normalized());
    }
    return d;
  }();
  // -1 certified inside S, 1 certified outside, 0 undecided.
  auto side = [&](const V& q) {
    const MinBracket b = minSignedDistance(mb, q, [](double blo, double bhi) { return blo > 0 || bhi < 0; }, 6000);
    return b.lo > 0 ? 1 : b.hi < 0 ? -1 : 0;
  };
  if (side(x) >= 0) return 2;
  std::vector<V> probes;
  const double r = T * (1 - 1e-3);
  if (normal.norm() > 0) probes.push_back(x + r * normal.normalized());
  for (const V& d : dirs) probes.push_back(x + r * d);
  for (const auto& f : faces)
    for (int a = 1; a <= 3; ++a)
      for (int j = 3; j <= 12; ++j)
        for (const double sign : {1.0, -1.0})
          probes.push_back(x + std::ldexp(T, -a) * f[0] + sign * std::ldexp(T, -j) * f[1]);
  for (const V& d : random_dirs) probes.push_back(x + r * d), probes.push_back(x + 0.5 * T * d);
  for (const auto& f : faces)
    for (int k = 0; k < 8; ++k) {
      const V t = k == 0 ? f[0] : V(((8 - k) * f[2] + k * f[3]).normalized());
      for (int a = 0; a <= 3; ++a)
        for (int j = 2; j <= 24; ++j) {
          const double b = T * std::exp2(-0.5 * j);
          const double along = a == 0 ? r - b : std::ldexp(T, -a);
          for (const double sign : {1.0, -1.0}) probes.push_back(x + along * t + sign * b * f[1]);
        }
    }
  bool unsure = false;
  for (const V& q : probes) {
    const int s = side(q);
    if (s > 0) return 1;
    unsure = unsure || s == 0;
  }
  return unsure ? 0 : -1;
}

inline AcrossCheck checkAcross(const steady::sweep::Envelope& env, const MovingBody& mb, const std::vector<int>& which) {
  const double T = env.tolerance * 1.01;
  std::vector<V> normal(env.vertices.size(), V::Zero());
  // (per vertex and face at it: the direction to the centroid, the normal and the two edges)
  std::vector<std::vector<std::array<V, 4>>> faces(env.vertices.size());
  std::vector<char> wanted(env.vertices.size(), 0);
  for (const int i : which) wanted[static_cast<std::size_t>(i)] = 1;
  for (const auto& t : env.triangles) {
    const V n = (env.vertices[t[1]] - env.vertices[t[0]]).cross(env.vertices[t[2]] - env.vertices[t[0]]);
    const V centroid = (env.vertices[t[0]] + env.vertices[t[1]] + env.vertices[t[2]]) / 3.0;
    for (int k = 0; k < 3; ++k) {
      const int v = t[k];
      normal[v] += n;
      const V into = centroid - env.vertices[v];
      const V ea = env.vertices[t[(k + 1) % 3]] - env.vertices[v], eb = env.vertices[t[(k + 2) % 3]] - env.vertices[v];
      if (wanted[v] && n.norm() > 0 && into.norm() > 0)  // (then ea and eb are not zero either)
        faces[v].push_back({{into.normalized(), n.normalized(), ea.normalized(), eb.normalized()}});
    }
  }
  AcrossCheck c;
  for (const int i : which)
    c.count(acrossPoint(mb, env.vertices[static_cast<std::size_t>(i)], normal[i], faces[i], T), i);
  return c;
}

// checkAcross for the centroids of the faces `which` (indices into env.triangles), probed along
// the face's outward normal, the cube's and the random directions (`deep` lists faces).
inline AcrossCheck checkCentroidsAcross(const steady::sweep::Envelope& env, const MovingBody& mb,
                                        const std::vector<int>& which) {
  AcrossCheck c;
  for (const int f : which) {
    const auto& t = env.triangles[static_cast<std::size_t>(f)];
    const V &a = env.vertices[t[0]], &b = env.vertices[t[1]], &d = env.vertices[t[2]];
    c.count(acrossPoint(mb, (a + b + d) / 3.0, (b - a).cross(d - a), {}, env.tolerance * 1.01), f);
  }
  return c;
}

// checkAcross for the envelope vertices inside the box [lo, hi].
inline AcrossCheck checkAcrossInBox(const steady::sweep::Envelope& env, const MovingBody& mb, const V& lo, const V& hi) {
  std::vector<int> which;
  for (std::size_t i = 0; i < env.vertices.size(); ++i) {
    const V& x = env.vertices[i];
    if ((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all()) which.push_back(static_cast<int>(i));
  }
  return checkAcross(env, mb, which);
}

// The envelope of `mesh` along `motion` with default options (plus the given tolerance, and
// the given re-sweeps when not negative), and its expected ε.
inline steady::sweep::Envelope sweep(const Mesh& mesh, const steady::Motion3& motion, double relative = 1e-3,
                                     int refinements = -1) {
  steady::sweep::SweepOptions o;
  o.relative_tolerance = relative;
  if (refinements >= 0) o.refinements = refinements;
  return steady::sweep::sweptEnvelope(makeBody(mesh), motion, o);
}
inline double epsOf(const Mesh& mesh, double relative = 1e-3) { return relative * makeBody(mesh).box().diagonal(); }

}  // namespace steady_sweep_test
