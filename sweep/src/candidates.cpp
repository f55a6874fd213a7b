// Candidate surface of a sweep: caps and adaptively tessellated swept grazing segments.
//
// Error bound of the tessellation (the guarantee documented in candidates.hpp).
//
// A body point at world position X0 at span time 0 is at X(τ) = A^τ X0. Its velocity is
// X'(τ) = v(X(τ)) = L^τ v(X0) (the field is stationary and equivariant), so
//   X''(τ) = M v(X(τ))  and, for τ in [τk, τk + h],  X''(τ) = L^(τ-τk) M v(X(τk)),
// since M and L^σ = exp(σM) commute. For any w and σ in [0, h], with μ >= |M|_2 (an upper
// bound of the spectral norm), |L^σ| <= e^(σμ) gives |L^σ w| <= e^(hμ) |w|, and Taylor's
// formula e^(σM) w = w + σ M w + ∫_0^σ (σ - s) e^(sM) M² w ds gives
// |L^σ w| <= |w| + h |M w| + h²/2 e^(hμ) |M² w|; B_h(w) denotes the first, or the second where
// it is less than half of the first (detail::flowFactor; the second is exact for shears, where
// M² w = 0). The chord of X over
// [τk, τk + h] is within h²/8 max|X''| <= h²/8 B_h(M v(X(τk))) of X (linear interpolation
// error). On a grazing segment the point set at time τk is the segment [Pk, Qk] (A^τ is affine)
// and |M^j v| is convex along it (v is affine), so each of |M v|, |M² v|, |M³ v| is at most its
// largest value over the end points of the component's segments at τk, and both bounds are
// increasing in each. The τ grid is chosen so that
//   (1)  h²/8 B_h(M v) <= ε/2   (M v at the end points at τk).
// Let F(s, τ) = (1 - s) X_P(τ) + s X_Q(τ) be the true strip of a segment. F is affine in s, so its
// bilinear interpolant Bil on a cell [si, si+1] x [τk, τk+1] differs from F by at most the
// chordal error (1) of the two edge trajectories. The two triangles split along the cell's
// diagonal differ from Bil by at most |d|/4, d = F(si+1,τk+1) - F(si,τk+1) - F(si+1,τk) + F(si,τk)
// the cell's twist: with Bil = a + b s + c w + d s w in local coordinates, the interpolant of sw
// on the triangle {w <= s} is w, and |sw - w| = w(1 - s) <= 1/4 there (symmetric on the other).
// d = Δs ∫ ∂τ (X_Q - X_P) dτ = Δs ∫ L^(τ-τk) M ek dτ with ek = Qk - Pk (the segment at τk), so
//   |d| <= Δs h B_h(M ek),
// and the number of pieces m (Δs = 1/m) is chosen so that
//   (2)  h B_h(M ek) / (4 m) <= ε/2   on every cell of the segment's grid.
// Any true strip point is thus within ε/2 + ε/2 = ε of the triangles of its own cell.
#include <steady/sweep/candidates.hpp>

#include <steady/core/error.hpp>

#include "tessellation.hpp"

#include <Eigen/Geometry>  // cross products

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace steady::sweep {

namespace {

using Vec = Eigen::Vector3d;
using detail::spectralBound;

// Zero-area test for output triangles (same relative rule as Body's default).
bool degenerate(const Vec& a, const Vec& b, const Vec& c) {
  const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return !((b - a).cross(c - a).norm() > 1e-12 * longest);
}

int findRoot(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// Appends a body posed by `pose` as a cap; returns the index of its first vertex.
int appendCap(CandidateSurface& out, const Body& body, const Affine3& pose, CandidateKind kind, int span) {
  const int base = static_cast<int>(out.vertices.size());
  for (const Vec& p : body.vertices()) out.vertices.push_back(pose(p));
  for (std::size_t f = 0; f < body.faces().size(); ++f) {
    const auto& t = body.faces()[f];
    out.triangles.push_back({{base + t[0], base + t[1], base + t[2]}});
    CandidateTag tag;
    tag.kind = kind;
    tag.span = span;
    tag.face = static_cast<int>(f);
    out.tags.push_back(tag);
  }
  return base;
}

double resolveTolerance(const Body& body, const CandidateOptions& o) {
  if (o.max_steps < 1)
    throw Error(ErrorCode::InvalidArgument, "CandidateOptions::max_steps must be >= 1, got " + std::to_string(o.max_steps));
  if (o.tolerance) {
    if (!(std::isfinite(*o.tolerance) && *o.tolerance > 0))
      throw Error(ErrorCode::InvalidArgument, "CandidateOptions::tolerance must be finite and > 0, got " +
                                                  std::to_string(*o.tolerance) +
                                                  "; leave it unset for relative_tolerance times the body size");
    return *o.tolerance;
  }
  if (!(std::isfinite(o.relative_tolerance) && o.relative_tolerance > 0))
    throw Error(ErrorCode::InvalidArgument, "CandidateOptions::relative_tolerance must be finite and > 0, got " +
                                                std::to_string(o.relative_tolerance));
  return o.relative_tolerance * body.box().diagonal();
}

// Appends the candidates of one span to `out`.
void appendSpan(CandidateSurface& out, const Body& body, const Span3& span, int span_index, double eps,
                const CandidateOptions& options) {
  GrazingSet gs = grazingSet(body, span, options.grazing);
  const Affine3 start = span.start();
  const Affine3 end = span.pose(1.0);
  if (!end.isFinite())
    throw Error(ErrorCode::NonFinite, "spanCandidates: the end pose of span " + std::to_string(span_index) +
                                          " is not finite");
  const int start_base = appendCap(out, body, start, CandidateKind::StartCap, span_index);
  const int end_base = appendCap(out, body, end, CandidateKind::EndCap, span_index);

  const Eigen::Matrix3d& M = span.log().M;
  const Vec& u = span.log().u;
  const double mu = spectralBound(M);
  const auto& pts = gs.points;
  const auto& segs = gs.segments;

  // Connected components of the grazing curves (points joined by non-degenerate segments).
  std::vector<int> parent(pts.size());
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> live(segs.size(), 0);
  for (std::size_t j = 0; j < segs.size(); ++j) {
    const auto& sp = segs[j].points;
    live[j] = (pts[sp[0]].world - pts[sp[1]].world).norm() > 0;
    if (live[j]) parent[findRoot(parent, sp[0])] = findRoot(parent, sp[1]);
  }
  std::vector<int> group_of_root(pts.size(), -1), group_of_point(pts.size(), -1);
  std::vector<std::vector<int>> group_points;
  for (std::size_t j = 0; j < segs.size(); ++j)
    if (live[j])
      for (int q : segs[j].points) {
        if (group_of_point[q] >= 0) continue;
        int& g = group_of_root[findRoot(parent, q)];
        if (g < 0) {
          g = static_cast<int>(group_points.size());
          group_points.emplace_back();
        }
        group_of_point[q] = g;
        group_points[g].push_back(q);
      }

  // Pose of the body at a grid time: exactly the cap poses at 0 and 1.
  auto poseAt = [&](double tau) { return tau == 0.0 ? start : tau == 1.0 ? end : span.pose(tau); };

  // Per group: the τ grid (condition (1)) and a vertex per point per row.
  const int grid_base = static_cast<int>(out.grids.size());
  std::vector<std::vector<std::vector<int>>> row_vertex(group_points.size());  // [group][k][local]
  std::vector<int> local_index(pts.size(), -1);
  for (std::size_t g = 0; g < group_points.size(); ++g) {
    const auto& gp = group_points[g];
    for (std::size_t i = 0; i < gp.size(); ++i) local_index[gp[i]] = static_cast<int>(i);
    TimeGrid grid;
    grid.span = span_index;
    grid.points = gp;
    grid.tau.push_back(0.0);
    auto& rows = row_vertex[g];
    double tau = 0.0;
    for (;;) {
      // Row at tau: vertices (cap vertices where the point is a body vertex at τ = 0 or 1).
      const Affine3 pose = poseAt(tau);
      std::vector<int> row(gp.size());
      detail::FlowNorms accel;  // of M v over the points (tessellation.hpp)
      for (std::size_t i = 0; i < gp.size(); ++i) {
        const GrazingPoint& q = pts[gp[i]];
        const Vec x = pose(q.body);
        accel.include(detail::FlowNorms::of(M, M * (M * x + u)));
        if (q.vertex >= 0 && (tau == 0.0 || tau == 1.0)) {
          row[i] = (tau == 0.0 ? start_base : end_base) + q.vertex;
        } else {
          row[i] = static_cast<int>(out.vertices.size());
          out.vertices.push_back(x);
        }
      }
      rows.push_back(std::move(row));
      if (tau == 1.0) break;
      if (static_cast<int>(grid.tau.size()) > options.max_steps)
        throw Error(ErrorCode::InvalidArgument,
                    "spanCandidates: more than " + std::to_string(options.max_steps) + " time steps on span " +
                        std::to_string(span_index) + " for tolerance " + std::to_string(eps) +
                        "; raise the tolerance (or max_steps)");
      tau = detail::nextGridTime(tau, accel, mu, eps);
      grid.tau.push_back(tau);
    }
    out.grids.push_back(std::move(grid));
  }

  // Strips: pieces per segment (condition (2)), then two triangles per cell.
  for (std::size_t j = 0; j < segs.size(); ++j) {
    if (!live[j]) continue;
    const GrazingSegment& seg = segs[j];
    const int g = group_of_point[seg.points[0]];
    const TimeGrid& grid = out.grids[grid_base + g];
    const auto& rows = row_vertex[g];
    const int a = local_index[seg.points[0]], b = local_index[seg.points[1]];
    const std::size_t K = grid.tau.size() - 1;
    double twist = 0.0;  // max over cells of h max_σ |L^σ M ek| / 4
    for (std::size_t k = 0; k < K; ++k) {
      const double h = grid.tau[k + 1] - grid.tau[k];
      const Vec ek = out.vertices[rows[k][b]] - out.vertices[rows[k][a]];
      twist = std::max(twist, detail::cellTwist(h, mu, detail::FlowNorms::of(M, M * ek)));
    }
    const int m = detail::piecesFor(twist, eps, options.max_steps,
                                    "spanCandidates: segment " + std::to_string(j) + " of span " +
                                        std::to_string(span_index));

    CandidateStrip strip;
    strip.span = span_index;
    strip.segment = static_cast<int>(j);
    strip.group = grid_base + g;
    strip.pieces = m;
    strip.first_triangle = out.triangles.size();
    CandidateTag tag;
    tag.kind = CandidateKind::Swept;
    tag.span = span_index;
    tag.face = seg.face;
    tag.edge = seg.edge;
    tag.segment = static_cast<int>(j);
    tag.segment_kind = seg.kind;
    tag.group = grid_base + g;
    // Vertex (i, k) of the strip: the shared trajectory vertices at i = 0 and i = m, new
    // interpolated vertices between (the segment at time τk is straight).
    std::vector<int> prev, cur;
    for (std::size_t k = 0; k <= K; ++k) {
      cur.assign(static_cast<std::size_t>(m) + 1, -1);
      cur[0] = rows[k][a];
      cur[m] = rows[k][b];
      const Vec P = out.vertices[cur[0]], Q = out.vertices[cur[m]];
      for (int i = 1; i < m; ++i) {
        const double s = static_cast<double>(i) / m;
        cur[i] = static_cast<int>(out.vertices.size());
        out.vertices.push_back((1 - s) * P + s * Q);
      }
      if (k > 0)
        for (int i = 0; i < m; ++i) {
          // Cell corners: (i, k-1), (i+1, k-1), (i+1, k), (i, k); split along (i,k-1)-(i+1,k).
          const std::array<std::array<int, 3>, 2> tris{{{{prev[i], prev[i + 1], cur[i + 1]}},
                                                        {{prev[i], cur[i + 1], cur[i]}}}};
          for (const auto& t : tris) {
            if (degenerate(out.vertices[t[0]], out.vertices[t[1]], out.vertices[t[2]])) {
              ++out.degenerate_dropped;
              continue;
            }
            out.triangles.push_back(t);
            out.tags.push_back(tag);
          }
        }
      prev.swap(cur);
    }
    strip.triangle_count = out.triangles.size() - strip.first_triangle;
    out.strips.push_back(strip);
  }
  out.grazing.push_back(std::move(gs));
}

}  // namespace

const char* to_string(CandidateKind k) noexcept {
  switch (k) {
    case CandidateKind::StartCap: return "start-cap";
    case CandidateKind::EndCap: return "end-cap";
    case CandidateKind::Swept: return "swept";
  }
  return "?";
}

CandidateSurface spanCandidates(const Body& body, const Span3& span, const CandidateOptions& options) {
  CandidateSurface out;
  out.tolerance = resolveTolerance(body, options);
  appendSpan(out, body, span, 0, out.tolerance, options);
  return out;
}

CandidateSurface motionCandidates(const Body& body, const Motion3& motion, const CandidateOptions& options) {
  CandidateSurface out;
  out.tolerance = resolveTolerance(body, options);
  for (std::size_t i = 0; i < motion.spanCount(); ++i)
    appendSpan(out, body, motion.span(i), static_cast<int>(i), out.tolerance, options);
  return out;
}

}  // namespace steady::sweep
