// Fuzz target of the sweep (see tests/fuzz/README.md): small closed bodies along polySAMs whose
// key poses come from the input, through sweptEnvelope() on one thread.
//
// Input: byte 0 chooses the body (bits 0-1: a tetrahedron, a cube, a non-convex L-shaped prism,
// a thin plate), how pose entries are read (bit 2: raw doubles, 8 bytes each, or small exact
// values, one signed byte each divided by 16: exact half and quarter turns, shears, repeated
// eigenvalues, zero entries), whether the motion has one span or two (bit 3), and the relative
// tolerance (bits 4-5: 2e-2, 5e-2, 1e-1 or 1e-2). Then the key poses after the identity, each
// the 3x4 matrix [L | t] row by row; missing entries are those of the identity.
//
// Motions whose spans' logs are large (|M| > 6 or |u| > 8 in body units) are skipped: they are
// valid, but their sweeps take minutes under the sanitizers, and libFuzzer would report them as
// timeouts.
//
// Checks, beyond "a result or a steady::Error":
// - the envelope has finite vertices and indices in range;
// - with STEADY_FUZZ_STRICT set in the environment (the replay test sets it), the envelope
//   passes its own check (passedCheck); otherwise a failed check, which the library reports,
//   is accepted;
// - when the envelope passes its own check (passedCheck: closed, manifold, one orientation, no
//   self-intersection, positive volume), an independent test written here: every body vertex
//   posed at 17 times (the key times among them) has a winding number of one with respect to
//   the envelope or lies within 2ε of it (the envelope is within ε of the true boundary, and
//   the body is inside the swept volume); and the envelope's volume is at least that of the
//   larger end pose less its area times ε.
#include "fuzz_check.hpp"

#include <steady/core/ear.hpp>
#include <steady/core/motion.hpp>
#include <steady/sweep/body.hpp>
#include <steady/sweep/envelope.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

namespace {

using Vec = Eigen::Vector3d;
using Tri = std::array<int, 3>;

struct Mesh {
  std::vector<Vec> vertices;
  std::vector<Tri> faces;
};

// A prism over a polygon in the xy-plane (counter-clockwise, star-shaped from its vertex 0),
// from z = 0 to z = h, faces outward.
Mesh prism(const std::vector<Eigen::Vector2d>& polygon, double h) {
  Mesh m;
  const int n = static_cast<int>(polygon.size());
  for (const auto& p : polygon) m.vertices.emplace_back(p.x(), p.y(), 0.0);
  for (const auto& p : polygon) m.vertices.emplace_back(p.x(), p.y(), h);
  for (int i = 1; i + 1 < n; ++i) {
    m.faces.push_back({0, i + 1, i});          // bottom, seen from below
    m.faces.push_back({n, n + i, n + i + 1});  // top
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.faces.push_back({i, j, n + j});
    m.faces.push_back({i, n + j, n + i});
  }
  return m;
}

Mesh body(int which) {
  switch (which) {
    case 0:
      return {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
    case 1:
      return prism({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1.0);
    case 2:  // an L, star-shaped from its reflex corner (listed first)
      return prism({{1, 1}, {1, 2}, {0, 2}, {0, 0}, {2, 0}, {2, 1}}, 0.5);
    default:  // a thin plate
      return prism({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 0.02);
  }
}

// Winding number of the closed triangle mesh (V, F) around x (solid angles, Van Oosterom and
// Strackee), and the distance from x to the mesh. (Written here on purpose, not taken from the
// library's inside tests: the check is meant to be independent of them.)
double windingNumber(const std::vector<Vec>& V, const std::vector<Tri>& F, const Vec& x) {
  double sum = 0;
  for (const Tri& f : F) {
    const Vec a = V[f[0]] - x, b = V[f[1]] - x, c = V[f[2]] - x;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    sum += 2 * std::atan2(num, den);
  }
  return sum / (4 * M_PI);
}

double pointTriangleDistance(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
  // the nearest point of the plane when it is inside the triangle; else the nearest of the edges
  const Vec n = (b - a).cross(c - a);
  const double nn = n.squaredNorm();
  if (nn > 0) {
    const Vec q = p - n * (n.dot(p - a) / nn);
    const bool inside = n.dot((b - a).cross(q - a)) >= 0 && n.dot((c - b).cross(q - b)) >= 0 &&
                        n.dot((a - c).cross(q - c)) >= 0;
    if (inside) return (p - q).norm();
  }
  const auto segment = [&](const Vec& u, const Vec& v) {
    const Vec d = v - u;
    const double dd = d.squaredNorm();
    const double s = dd > 0 ? std::clamp(d.dot(p - u) / dd, 0.0, 1.0) : 0.0;
    return (p - (u + s * d)).norm();
  };
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

double distanceToMesh(const std::vector<Vec>& V, const std::vector<Tri>& F, const Vec& x) {
  double best = INFINITY;
  for (const Tri& f : F) best = std::min(best, pointTriangleDistance(x, V[f[0]], V[f[1]], V[f[2]]));
  return best;
}

double signedVolume(const std::vector<Vec>& V, const std::vector<Tri>& F) {
  double v = 0;
  for (const Tri& f : F) v += V[f[0]].dot(V[f[1]].cross(V[f[2]]));
  return v / 6;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const Mesh m = body(data[0] & 3);
  const bool raw = data[0] & 4;
  const int keys = (data[0] & 8) ? 3 : 2;
  static const double kTolerance[4] = {2e-2, 5e-2, 1e-1, 1e-2};
  steady::fuzz::NumberReader in(data + 1, size - 1, raw);
  std::vector<steady::Affine3> poses(1);
  for (int k = 1; k < keys; ++k) {
    steady::Affine3::Linear L = steady::Affine3::Linear::Identity();
    steady::Affine3::Vector t = steady::Affine3::Vector::Zero();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) L(r, c) = in.next(L(r, c));
      t(r) = in.next(0.0);
    }
    poses.emplace_back(L, t);
  }

  std::unique_ptr<steady::Motion3> made;
  if (!steady::fuzz::typedOrOk("polySam", [&] { made = std::make_unique<steady::Motion3>(steady::Motion3::polySam(poses)); }))
    return 0;
  const steady::Motion3& motion = *made;
  for (std::size_t i = 0; i < motion.spanCount(); ++i) {
    const auto& lg = motion.span(i).log();
    if (!(lg.M.norm() <= 6 && lg.u.norm() <= 8)) return 0;  // (see the file comment)
  }
  std::vector<Vec> vertices = m.vertices;
  std::vector<Tri> faces = m.faces;
  std::unique_ptr<steady::sweep::Body> b;
  const bool built = steady::fuzz::typedOrOk("Body", [&] { b = std::make_unique<steady::sweep::Body>(vertices, faces); });
  FUZZ_CHECK(built, "a bundled fuzz body was refused");

  steady::sweep::SweepOptions options;
  options.relative_tolerance = kTolerance[(data[0] >> 4) & 3];
  options.threads = 1;
  options.refinements = 1;
  steady::sweep::Envelope env;
  if (!steady::fuzz::typedOrOk("sweptEnvelope", [&] { env = steady::sweep::sweptEnvelope(*b, motion, options); })) return 0;
  for (const Vec& v : env.vertices) FUZZ_CHECK(v.allFinite(), "an envelope vertex is not finite");
  for (const Tri& f : env.triangles)
    for (const int v : f)
      FUZZ_CHECK(v >= 0 && static_cast<std::size_t>(v) < env.vertices.size(), "an envelope index is out of range");
  if (!steady::sweep::passedCheck(env)) {
    // A failed check is the library's own report, an accepted answer by default; with
    // STEADY_FUZZ_STRICT set (the replay test sets it) it is a finding.
    static const bool strict = std::getenv("STEADY_FUZZ_STRICT") != nullptr;
    if (strict) {
      const steady::sweep::MeshCheck& c = env.check;
      std::fprintf(stderr, "envelope check: closed %d, manifold %d, oriented %d, %ld crossing pairs, %d shells\n",
                   static_cast<int>(c.closed), static_cast<int>(c.manifold), static_cast<int>(c.oriented),
                   c.self_intersections, c.shells);
      FUZZ_CHECK(false, "the envelope failed its own check (STEADY_FUZZ_STRICT)");
    }
    return 0;
  }

  const double eps = env.tolerance;
  for (int s = 0; s <= 16; ++s) {
    const double t = motion.beginTime() + (motion.endTime() - motion.beginTime()) * s / 16.0;
    const steady::Affine3 pose = motion.pose(t);
    for (const Vec& p : m.vertices) {
      const Vec x = pose(p);
      const double w = windingNumber(env.vertices, env.triangles, x);
      if (std::abs(w - 1) < 0.5) continue;
      const double d = distanceToMesh(env.vertices, env.triangles, x);
      if (!(d <= 2 * eps)) {
        std::fprintf(stderr, "posed vertex (%g, %g, %g) at t = %g: winding number %g, %g from the envelope (eps %g)\n",
                     x.x(), x.y(), x.z(), t, w, d, eps);
        FUZZ_CHECK(false, "a posed body vertex lies outside the envelope by more than 2 eps");
      }
    }
  }
  const double body_volume = signedVolume(m.vertices, m.faces);
  const double end_volume = body_volume * std::max(std::abs(poses.front().linear().determinant()),
                                                   std::abs(motion.pose(motion.endTime()).linear().determinant()));
  const double volume = signedVolume(env.vertices, env.triangles);
  if (!(volume >= end_volume - env.area * eps - 1e-12)) {
    std::fprintf(stderr, "envelope volume %g, end pose %g, area %g, eps %g\n", volume, end_volume, env.area, eps);
    FUZZ_CHECK(false, "the envelope holds less volume than an end pose");
  }
  if (std::getenv("STEADY_FUZZ_VERBOSE"))
    std::fprintf(stderr, "  checked: %zu triangles, volume %g (end pose %g), %zu posed vertices inside\n", env.triangles.size(),
                 volume, end_volume, 17 * m.vertices.size());
  return 0;
}
