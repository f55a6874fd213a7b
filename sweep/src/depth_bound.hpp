#pragma once
// A certified bound on the distance from a point to the boundary of a swept volume S, from the
// exact inside test alone (SweptVolume::contains, tolerance δ). Used for the vertices of the
// walls that the envelope keeps at mouths it could not close (Envelope::kept_wall_depth_bound).
// Internal to steady::sweep.
//
// Why it is a bound. The inside test reports a point inside only within 2δ of S, and outside
// only off the interior of S (inside.hpp). So when x and a point y with |x - y| <= r get
// different answers, the segment from x to y, its inside end moved by at most 2δ onto S, meets
// the boundary of S: some boundary point lies within r + 4δ of x. A probe that misses the
// nearest point on the other side can only overstate the distance, never understate it.
//
// The search. The probes lie on spheres about x of the radii `claim - 4δ`, for the claims
// kDepthClaims times ε in increasing order, along the caller's directions first and then the
// 26 directions to the faces, edges and corners of a cube; the first claim with a probe on the
// other side is the bound (infinity if none has one). The cube's directions are at most about
// 27.6° from any direction, so a point near a flat stretch of boundary, at depth d, finds a
// probe across it at the first radius above about d / cos 27.6° = 1.13 d. But near a vertex of
// the envelope the other side is often a layer far thinner than ε, which the fixed directions
// all miss, so the caller gives the surface's own directions (SurfaceProbes), probed at each
// claim's radius before the cube's and, for the first claim, after them also closer to x:
// - across the surface (the vertex and face normals, both ways) at the radii ε 2^-j - 4δ
//   (j up to kFineSteps): a thin layer beside the surface is crossed at about its distance;
// - along the surface (its edges from x, and directions in the planes of its normals) at
//   ε 2^-j - 4δ (j up to kTangentSteps): a thin layer in the tangent plane that reaches x;
// - just off each face at x: the points x + a t +- b n, t a unit direction from x into the
//   face and n its normal, with b = ε 2^-j/2 (half octaves, j = 2 .. 2 kFineSteps) and a =
//   ε - b - 5δ (nearly the whole radius), ε/2, ε/4 and ε/8 (all within ε - 4δ of x): a crack
//   whose walls are the faces at x, ending at x, is wider a little way along the faces than at
//   x (campaign case 604: its thin cracks met about 2% of all directions, all within a degree
//   of the tangent plane, at every radius from ε/2 to 2ε). t is first the direction to the
//   face's centroid, then kSectorSteps - 1 directions spread evenly between its two edges at
//   x. Such cracks often cover only part of a face's angle at x and lie within hundredths of ε
//   of its plane: beside the kept walls of campaign cases 604 and 4214 (a bracket polySAM),
//   18 vertices lie within ε of layers of outside space 0.004 to 0.03 ε thick, which 1 to 20
//   of 20,000 random directions meet. With t towards the centroid only, a = ε/2 .. ε/8 and b
//   at octaves, none of the 18 was certified within ε; with the directions between the edges,
//   3; with a near ε as well, 16; with the half octaves, all of them. The offsets b reach ε/2
//   (tilts of up to 45 degrees off the face, at a near ε): beside a thin fin of three faces of
//   campaign case 8054 (a star polySAM) the outside within 0.95 ε lies 11 to 20 degrees off the
//   fin, between the cube's directions, and with b at most ε/8 two vertices were left
//   uncertified.
#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

namespace steady::sweep::detail {

// The claims, in units of ε.
constexpr std::array<double, 6> kDepthClaims = {{1.0, 1.25, 1.5, 2.0, 4.0, 8.0}};
// Halvings of the first claim's radius across the surface (down to about 1e-6 ε) and along it.
constexpr int kFineSteps = 20;
constexpr int kTangentSteps = 4;
// Parts of a face's angle at the point, for the directions just off it (see the file comment).
constexpr int kSectorSteps = 8;

// A face at the point: unit directions from the point to its centroid and along its two edges,
// and its unit normal.
struct FaceAtPoint {
  Eigen::Vector3d into, edge_a, edge_b, normal;
};

// The directions of the surface at the point (unit vectors; see the file comment).
struct SurfaceProbes {
  std::vector<Eigen::Vector3d> normals;   // across the surface (both ways given)
  std::vector<Eigen::Vector3d> tangents;  // along it
  std::vector<FaceAtPoint> faces;
};

// The 26 unit directions to the faces, edges and corners of the cube [-1, 1]³, in that order.
inline const std::vector<Eigen::Vector3d>& cubeDirections() {
  static const std::vector<Eigen::Vector3d> dirs = [] {
    std::vector<Eigen::Vector3d> d;
    for (int n = 1; n <= 3; ++n)
      for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
          for (int k = -1; k <= 1; ++k)
            if (std::abs(i) + std::abs(j) + std::abs(k) == n) d.push_back(Eigen::Vector3d(i, j, k).normalized());
    return d;
  }();
  return dirs;
}

// The bound for point x (world units; see the file comment): the smallest claim times ε at
// which some probe gets the other answer than x from `inside` (a predicate with the inside
// test's guarantees, tolerance delta), or infinity. Claims whose radius would not be positive
// (ε not far above δ) are skipped. When `witness` is given and the bound is finite, it gets
// the probe that found the other side.
template <class Inside>
double depthBound(const Eigen::Vector3d& x, double eps, double delta, const Inside& inside,
                  const SurfaceProbes& surface = {}, Eigen::Vector3d* witness = nullptr) {
  // A pair first: when no witness is asked for, the probes along the first two normals at the
  // first claim's radius r are tested before x itself. Both lie within r of x, and so does the
  // segment between them; when they get different answers that segment, its inside end moved
  // by at most 2δ onto S, meets the boundary of S within r + 2δ of x, so the first claim is the
  // bound without testing x, the same bound the search below returns (it starts with those two
  // probes and stops at the first that differs from x). Otherwise their answers are kept for
  // the search. It pays when the two point opposite ways, as DepthTest::boundAt's n and -n do:
  // the fillings' probes took 59k inside tests instead of 83k on the elephant screw at 1e-3.
  std::array<Eigen::Vector3d, 2> known_at;
  std::array<bool, 2> known_in{};
  int known = 0;
  {
    const double claim = kDepthClaims[0] * eps, r = claim - 4 * delta;
    if (!witness && r > 0 && surface.normals.size() >= 2) {
      for (int k = 0; k < 2; ++k) {
        known_at[k] = x + r * surface.normals[k];
        known_in[k] = inside(known_at[k]);
      }
      known = 2;
      if (known_in[0] != known_in[1]) return claim;
    }
  }
  // (the search makes those two probes by the same expression, so as the same points)
  auto ask = [&](const Eigen::Vector3d& q) {
    for (int k = 0; k < known; ++k)
      if (q == known_at[k]) return known_in[k];
    return inside(q);
  };
  const bool in = inside(x);
  auto across = [&](const Eigen::Vector3d& q) {
    if (ask(q) == in) return false;
    if (witness) *witness = q;
    return true;
  };
  // Along each of `dirs` at the radii claim 2^-j - 4δ, j = from .. to (while positive).
  auto finer = [&](const std::vector<Eigen::Vector3d>& dirs, double claim, int from, int to) {
    for (const Eigen::Vector3d& d : dirs)
      for (int j = from; j <= to; ++j) {
        const double r = std::ldexp(claim, -j) - 4 * delta;
        if (!(r > 0)) break;
        if (across(x + r * d)) return true;
      }
    return false;
  };
  // Just off the faces at x (within claim - 4δ of x), into each along t.
  auto offFace = [&](const Eigen::Vector3d& t, const Eigen::Vector3d& n, double claim) {
    for (int i = 0; i <= 3; ++i)
      for (int j = 2; j <= 2 * kFineSteps; ++j) {
        const double b = claim * std::exp2(-0.5 * j);
        const double a = i == 0 ? claim - b - 5 * delta : std::ldexp(claim, -i);
        if (!(a + b + 4 * delta <= claim)) continue;
        if (across(x + a * t + b * n) || across(x + a * t - b * n)) return true;
      }
    return false;
  };
  auto offFaces = [&](double claim) {
    for (const FaceAtPoint& f : surface.faces)
      if (offFace(f.into, f.normal, claim)) return true;
    for (const FaceAtPoint& f : surface.faces)
      for (int k = 1; k < kSectorSteps; ++k) {
        const Eigen::Vector3d t = (kSectorSteps - k) * f.edge_a + k * f.edge_b;
        if (t.norm() > 0 && offFace(t.normalized(), f.normal, claim)) return true;
      }
    return false;
  };
  // (the probes at the claim's own radius first, which settle nearly every vertex; the closer
  // ones of the first claim after them)
  for (std::size_t i = 0; i < kDepthClaims.size(); ++i) {
    const double claim = kDepthClaims[i] * eps;
    const double r = claim - 4 * delta;
    if (!(r > 0)) continue;
    if (finer(surface.normals, claim, 0, 0) || finer(surface.tangents, claim, 0, 0)) return claim;
    for (const Eigen::Vector3d& d : cubeDirections())
      if (across(x + r * d)) return claim;
    if (i == 0 && (finer(surface.normals, claim, 1, kFineSteps) || finer(surface.tangents, claim, 1, kTangentSteps) ||
                   offFaces(claim)))
      return claim;
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace steady::sweep::detail
