// Validation of a sweep body: geometry first (finite, indices, face areas), then topology
// (closed, edge-manifold, consistently oriented, vertex-manifold), then orientation (volume).
#include <steady/sweep/body.hpp>

#include <steady/core/error.hpp>

#include <Eigen/Geometry>  // cross products

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>

namespace steady::sweep {

namespace {

using Vec = Eigen::Vector3d;

std::string str(const Vec& p) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

std::string str(const std::array<int, 3>& f) {
  return "(" + std::to_string(f[0]) + ", " + std::to_string(f[1]) + ", " + std::to_string(f[2]) + ")";
}

// "1 face has" / "3 faces have".
std::string count(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

[[noreturn]] void fail(ErrorCode code, const std::string& message) {
  throw Error(code, "body mesh: " + message);
}

// One face's use of an edge, in the direction of the face's winding.
struct HalfEdge {
  int lo, hi;   // vertex indices, lo < hi
  int face;
  int corner;   // the edge runs from corner `corner` to corner `corner + 1` of `face`
  bool forward; // the face traverses lo -> hi
};

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

}  // namespace

Body::Body(std::vector<Vec> vertices, std::vector<std::array<int, 3>> faces, const BodyOptions& options)
    : vertices_(std::move(vertices)), faces_(std::move(faces)) {
  if (!(std::isfinite(options.degenerate_tolerance) && options.degenerate_tolerance >= 0) ||
      !(std::isfinite(options.volume_tolerance) && options.volume_tolerance >= 0))
    throw Error(ErrorCode::InvalidArgument,
                "BodyOptions: degenerate_tolerance and volume_tolerance must be finite and >= 0");
  const std::vector<Vec>& V = vertices_;
  const std::vector<std::array<int, 3>>& F = faces_;
  const std::size_t nv = V.size(), nf = F.size();

  // --- geometry ---------------------------------------------------------------------------
  if (nv == 0 || nf == 0)
    fail(ErrorCode::DegenerateInput, "the mesh is empty (" + std::to_string(nv) + " vertices, " +
                                         std::to_string(nf) + " faces); a body needs a closed "
                                         "triangle surface (at least 4 vertices and 4 faces)");
  {
    std::size_t bad = 0, first = 0;
    for (std::size_t i = 0; i < nv; ++i)
      if (!V[i].allFinite() && bad++ == 0) first = i;
    if (bad)
      fail(ErrorCode::NonFinite, count(bad, "vertex is", "vertices are") + " not finite, the first is vertex " +
                                     std::to_string(first) + " " + str(V[first]) +
                                     "; remove or repair NaN/Inf coordinates");
  }
  {
    std::size_t bad = 0, first = 0;
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k)
        if (F[f][k] < 0 || static_cast<std::size_t>(F[f][k]) >= nv) {
          if (bad++ == 0) first = f;
          break;
        }
    if (bad)
      fail(ErrorCode::InvalidArgument, count(bad, "face refers", "faces refer") +
                                           " to vertices outside [0, " + std::to_string(nv) +
                                           "), the first is face " + std::to_string(first) + " " +
                                           str(F[first]) + "; fix the face indices (they are 0-based)");
  }
  normals_.resize(nf);
  {
    std::size_t bad = 0, first = 0;
    for (std::size_t f = 0; f < nf; ++f) {
      const Vec &a = V[F[f][0]], &b = V[F[f][1]], &c = V[F[f][2]];
      const Vec n = (b - a).cross(c - a);
      const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
      const double twice_area = n.norm();
      // `!(x > y)` also catches a repeated vertex (0 > 0 is false).
      if (!(twice_area > options.degenerate_tolerance * longest)) {
        if (bad++ == 0) first = f;
        continue;
      }
      normals_[f] = n / twice_area;
    }
    if (bad) {
      std::ostringstream tol;
      tol << options.degenerate_tolerance;
      fail(ErrorCode::DegenerateInput,
           count(bad, "face is", "faces are") + " degenerate (twice the area at most " + tol.str() +
               " times the squared longest edge), the first is face " + std::to_string(first) + " " +
               str(F[first]) + "; remove degenerate faces or merge their coincident vertices");
    }
  }

  // --- topology: edges ----------------------------------------------------------------------
  std::vector<HalfEdge> half;
  half.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F[f][k], b = F[f][(k + 1) % 3];
      half.push_back({std::min(a, b), std::max(a, b), static_cast<int>(f), k, a < b});
    }
  std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.face < y.face;
  });
  // Group the half-edges of each undirected edge: [begin, end) ranges.
  std::vector<std::pair<std::size_t, std::size_t>> groups;
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i + 1;
    while (j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi) ++j;
    groups.emplace_back(i, j);
    i = j;
  }
  auto edgeName = [&](const HalfEdge& h) {
    return "(" + std::to_string(h.lo) + ", " + std::to_string(h.hi) + ")";
  };
  {
    std::size_t open = 0, multi = 0, same = 0;
    const HalfEdge *first_open = nullptr, *first_multi = nullptr, *first_same = nullptr;
    std::size_t multi_count = 0;
    for (const auto& [b, e] : groups) {
      const std::size_t n = e - b;
      if (n == 1) {
        if (open++ == 0) first_open = &half[b];
      } else if (n > 2) {
        if (multi++ == 0) first_multi = &half[b], multi_count = n;
      } else if (half[b].forward == half[b + 1].forward) {
        if (same++ == 0) first_same = &half[b];
      }
    }
    if (open)
      fail(ErrorCode::DegenerateInput,
           "the mesh is open: " + count(open, "boundary edge is", "boundary edges are") +
               " used by one face only, the first is edge " + edgeName(*first_open) + " of face " +
               std::to_string(first_open->face) + "; close the holes so that the surface bounds a volume");
    if (multi)
      fail(ErrorCode::DegenerateInput,
           "the mesh is not manifold: " + count(multi, "edge is", "edges are") +
               " shared by more than two faces, the first is edge " + edgeName(*first_multi) + " with " +
               std::to_string(multi_count) + " faces (face " + std::to_string(first_multi->face) +
               " and others); separate the sheets that meet there (duplicate the edge's vertices)");
    if (same) {
      const HalfEdge& h = *first_same;
      const HalfEdge& g = *(first_same + 1);
      const int from = h.forward ? h.lo : h.hi, to = h.forward ? h.hi : h.lo;
      fail(ErrorCode::DegenerateInput,
           "the mesh is not consistently oriented: " +
               count(same, "edge is", "edges are") + " traversed twice in the same direction, the first is edge " +
               std::to_string(from) + " -> " + std::to_string(to) + " in faces " + std::to_string(h.face) +
               " and " + std::to_string(g.face) +
               "; reorient the faces so that neighbours traverse their shared edge in opposite directions");
    }
  }
  edges_.resize(groups.size());
  face_edges_.assign(nf, {{-1, -1, -1}});
  for (std::size_t e = 0; e < groups.size(); ++e) {
    const HalfEdge& h0 = half[groups[e].first];
    const HalfEdge& h1 = half[groups[e].first + 1];
    const HalfEdge& fwd = h0.forward ? h0 : h1;
    const HalfEdge& bwd = h0.forward ? h1 : h0;
    edges_[e].vertices = {{h0.lo, h0.hi}};
    edges_[e].faces = {{fwd.face, bwd.face}};
    face_edges_[fwd.face][fwd.corner] = static_cast<int>(e);
    face_edges_[bwd.face][bwd.corner] = static_cast<int>(e);
  }

  // --- topology: vertex fans ------------------------------------------------------------------
  // Corners (f, k) around a vertex that are joined across a shared edge belong to one fan.
  {
    UnionFind uf(3 * nf);
    auto corner = [&](int f, int v) {
      for (int k = 0; k < 3; ++k)
        if (F[f][k] == v) return 3 * f + k;
      return -1;  // unreachable: v is a vertex of f
    };
    for (const Edge& e : edges_)
      for (int v : e.vertices) uf.unite(corner(e.faces[0], v), corner(e.faces[1], v));
    std::vector<std::vector<int>> roots(nv);
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const int v = F[f][k], r = uf.find(static_cast<int>(3 * f + k));
        auto& rs = roots[v];
        if (std::find(rs.begin(), rs.end(), r) == rs.end()) rs.push_back(r);
      }
    std::size_t bad = 0, first = 0;
    for (std::size_t v = 0; v < nv; ++v)
      if (roots[v].size() > 1 && bad++ == 0) first = v;
    if (bad)
      fail(ErrorCode::DegenerateInput,
           "the mesh is not manifold at " + count(bad, "vertex", "vertices") +
               " (the faces around it form more than one fan), the first is vertex " + std::to_string(first) +
               " with " + std::to_string(roots[first].size()) +
               " fans; give each fan its own copy of the vertex");
  }

  // --- volume, area, box ----------------------------------------------------------------------
  box_ = Box<3>::of(V);
  const Vec o = 0.5 * (box_.lo + box_.hi);  // reference point: keeps the terms small
  double vol6 = 0.0, area2 = 0.0;
  for (std::size_t f = 0; f < nf; ++f) {
    const Vec a = V[F[f][0]] - o, b = V[F[f][1]] - o, c = V[F[f][2]] - o;
    vol6 += a.dot(b.cross(c));
    area2 += (b - a).cross(c - a).norm();
  }
  volume_ = vol6 / 6.0;
  area_ = area2 / 2.0;
  if (volume_ < 0 && std::abs(volume_) > options.volume_tolerance * std::pow(box_.diagonal(), 3)) {
    std::ostringstream s;
    s.precision(6);
    s << "the mesh is oriented inward (signed volume " << volume_
      << " < 0); flip the faces (reverse the vertex order of every triangle) so that normals point out";
    fail(ErrorCode::InvalidArgument, s.str());
  }
  if (!(std::abs(volume_) > options.volume_tolerance * std::pow(box_.diagonal(), 3))) {
    std::ostringstream s;
    s << "the mesh encloses no volume (signed volume " << volume_ << " for a bounding-box diagonal of "
      << box_.diagonal() << "); a sweep body must be a solid, not a folded or doubled surface";
    fail(ErrorCode::DegenerateInput, s.str());
  }
}

}  // namespace steady::sweep
