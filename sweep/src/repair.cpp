// Opt-in mesh repair (repair.hpp): CGAL's polygon-soup repair and orientation, with a count of
// every change. CGAL (Epick: exact predicates on the double coordinates, which are only copied)
// stays in this translation unit.

#include <steady/sweep/repair.hpp>

#include <steady/core/error.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <utility>

namespace steady::sweep {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Polygon = std::vector<std::size_t>;
using Mesh = CGAL::Surface_mesh<Point>;

// Records the non-manifold edges and vertices orient_polygon_soup() meets. CGAL copies the
// visitor, so it points to the sets it fills.
struct OrientationVisitor : PMP::Default_orientation_visitor {
  std::set<std::pair<std::size_t, std::size_t>>* edges = nullptr;
  std::set<std::size_t>* vertices = nullptr;
  void non_manifold_edge(std::size_t a, std::size_t b, std::size_t) { edges->insert(std::minmax(a, b)); }
  void non_manifold_vertex(std::size_t v, std::size_t) { vertices->insert(v); }
};

bool hasRepeatedVertex(const Polygon& p) {
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j)
      if (p[i] == p[j]) return true;
  return false;
}

// The polygon rotated to start at its smallest index (the same face, however it is listed).
Polygon canonical(Polygon p) {
  std::rotate(p.begin(), std::min_element(p.begin(), p.end()), p.end());
  return p;
}

Eigen::Vector3d toEigen(const Point& p) { return {p.x(), p.y(), p.z()}; }

// Whether triangle `now` (positions) is the reverse of `before`: both hold the same three
// distinct positions, possibly rotated.
bool reversed(const std::array<Point, 3>& before, const std::array<Point, 3>& now) {
  for (int k = 0; k < 3; ++k)
    if (before[static_cast<std::size_t>(k)] == now[0]) return !(before[static_cast<std::size_t>((k + 1) % 3)] == now[1]);
  return false;  // not the same triangle (cannot happen): not counted
}

std::size_t find(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

std::string count(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

bool RepairReport::changed() const {
  return duplicate_vertices_merged + degenerate_faces_removed + duplicate_faces_removed + opposite_faces_removed +
             isolated_vertices_removed + faces_flipped + vertices_duplicated + hole_faces_added >
         0;
}

bool RepairReport::usable() const {
  return closed && oriented_outward && degenerate_faces == 0 && faces_out > 0;
}

RepairReport repairMesh(std::vector<Eigen::Vector3d>& vertices, std::vector<std::array<int, 3>>& faces,
                        const RepairOptions& options) {
  if (!(std::isfinite(options.degenerate_tolerance) && options.degenerate_tolerance >= 0))
    throw Error(ErrorCode::InvalidArgument,
                "repairMesh: degenerate_tolerance must be finite and >= 0, got " +
                    std::to_string(options.degenerate_tolerance));
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (!vertices[i].allFinite())
      throw Error(ErrorCode::NonFinite, "repairMesh: vertex " + std::to_string(i) +
                                            " has a NaN or infinite coordinate; a repair cannot guess it: fix "
                                            "or remove it in the file");
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (const int k : faces[f])
      if (k < 0 || static_cast<std::size_t>(k) >= vertices.size())
        throw Error(ErrorCode::InvalidArgument, "repairMesh: face " + std::to_string(f) + " refers to vertex " +
                                                    std::to_string(k) + ", but there are " +
                                                    std::to_string(vertices.size()) + " vertices");

  RepairReport report;
  report.vertices_in = vertices.size();
  report.faces_in = faces.size();

  std::vector<Point> points;
  points.reserve(vertices.size());
  for (const auto& v : vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<Polygon> polygons;
  polygons.reserve(faces.size());
  for (const auto& f : faces)
    polygons.push_back({static_cast<std::size_t>(f[0]), static_cast<std::size_t>(f[1]), static_cast<std::size_t>(f[2])});

  // 1-5: the soup.
  report.duplicate_vertices_merged = PMP::merge_duplicate_points_in_polygon_soup(points, polygons);
  const std::size_t before_degenerate = polygons.size();
  polygons.erase(std::remove_if(polygons.begin(), polygons.end(), hasRepeatedVertex), polygons.end());
  report.degenerate_faces_removed = before_degenerate - polygons.size();
  // CGAL moves the faces it keeps; their input order is restored below.
  std::map<Polygon, std::size_t> first_position;
  for (std::size_t i = polygons.size(); i-- > 0;) first_position[canonical(polygons[i])] = i;
  report.duplicate_faces_removed = PMP::merge_duplicate_polygons_in_polygon_soup(
      points, polygons, CGAL::parameters::require_same_orientation(true).erase_all_duplicates(false));
  // Only opposite pairs are duplicates now; both faces of each go.
  report.opposite_faces_removed = PMP::merge_duplicate_polygons_in_polygon_soup(
      points, polygons, CGAL::parameters::require_same_orientation(false).erase_all_duplicates(true));
  std::sort(polygons.begin(), polygons.end(), [&](const Polygon& a, const Polygon& b) {
    return first_position.at(canonical(a)) < first_position.at(canonical(b));
  });
  report.isolated_vertices_removed = PMP::remove_isolated_points_in_polygon_soup(points, polygons);

  // The triangles as they are now: the input orientation of every face that is kept.
  std::vector<std::array<Point, 3>> before(polygons.size());
  for (std::size_t i = 0; i < polygons.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k) before[i][k] = points[polygons[i][k]];

  // 6: consistent orientation; CGAL cuts the mesh where it cannot.
  std::set<std::pair<std::size_t, std::size_t>> nm_edges;
  std::set<std::size_t> nm_vertices;
  OrientationVisitor visitor;
  visitor.edges = &nm_edges;
  visitor.vertices = &nm_vertices;
  const std::size_t points_before = points.size();
  PMP::orient_polygon_soup(points, polygons, CGAL::parameters::visitor(visitor));
  report.vertices_duplicated = points.size() - points_before;
  report.non_manifold_edges = nm_edges.size();
  report.non_manifold_vertices = nm_vertices.size();

  Mesh mesh;
  std::vector<std::array<std::size_t, 3>> out_faces;
  std::vector<Point> out_points;
  if (!polygons.empty() && PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
    // Vertex i is point i and face i polygon i (no point is isolated; faces are added in order).
    PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);

    // 7: holes, one border halfedge each.
    if (options.fill_holes) {
      std::vector<Mesh::Halfedge_index> holes;
      std::vector<bool> seen(mesh.number_of_halfedges(), false);
      for (const auto h : mesh.halfedges()) {
        if (!mesh.is_border(h) || seen[h.idx()]) continue;
        holes.push_back(h);
        for (auto g = h; !seen[g.idx()]; g = mesh.next(g)) seen[g.idx()] = true;
      }
      for (const auto h : holes) {
        std::vector<Mesh::Face_index> added;
        PMP::triangulate_hole(mesh, h, std::back_inserter(added));
        if (added.empty()) {
          ++report.holes_not_filled;
        } else {
          ++report.holes_filled;
          report.hole_faces_added += added.size();
        }
      }
    }

    // 8: outward, when there is an inside. Not with zero-area faces, nor with a connected
    // component that encloses no volume (|volume| <= 1e-12 diagonal^3, Body's flat test):
    // CGAL's inside test (a vertical ray cast, retried with other rays while a ray meets an
    // edge or a vertex) never ended on two small closed STLs of that kind (mesh fuzz inputs).
    bool flat = false;
    for (const auto f : mesh.faces()) flat = flat || PMP::is_degenerate_triangle_face(f, mesh);
    if (!flat && CGAL::is_closed(mesh)) {
      std::vector<int> comp(mesh.num_faces(), -1);
      std::vector<double> volume;
      std::vector<CGAL::Bbox_3> box;
      for (const auto seed : mesh.faces()) {
        if (comp[seed.idx()] >= 0) continue;
        const int c = static_cast<int>(volume.size());
        volume.push_back(0.0);
        box.emplace_back();
        std::vector<Mesh::Face_index> stack{seed};
        comp[seed.idx()] = c;
        while (!stack.empty()) {
          const auto f = stack.back();
          stack.pop_back();
          Point p[3];
          int k = 0;
          for (const auto h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh)) {
            if (k < 3) p[k++] = mesh.point(mesh.target(h));
            const auto g = mesh.face(mesh.opposite(h));
            if (g != Mesh::null_face() && comp[g.idx()] < 0) {
              comp[g.idx()] = c;
              stack.push_back(g);
            }
          }
          volume[c] += CGAL::scalar_product(p[0] - CGAL::ORIGIN, CGAL::cross_product(p[1] - CGAL::ORIGIN, p[2] - CGAL::ORIGIN)) / 6;
          box[c] += p[0].bbox() + p[1].bbox() + p[2].bbox();
        }
      }
      for (std::size_t c = 0; c < volume.size(); ++c) {
        const double dx = box[c].xmax() - box[c].xmin(), dy = box[c].ymax() - box[c].ymin(), dz = box[c].zmax() - box[c].zmin();
        const double diag = std::sqrt(dx * dx + dy * dy + dz * dz);
        flat = flat || !(std::abs(volume[c]) > 1e-12 * diag * diag * diag);
      }
    }
    if (CGAL::is_closed(mesh) && !flat) {
      PMP::orient_to_bound_a_volume(mesh);
      report.oriented_outward = true;
    }

    out_points.reserve(mesh.number_of_vertices());
    for (const auto v : mesh.vertices()) out_points.push_back(mesh.point(v));
    out_faces.reserve(mesh.number_of_faces());
    for (const auto f : mesh.faces()) {
      std::array<std::size_t, 3> t{};
      std::size_t k = 0;
      for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
        if (k < 3) t[k] = v.idx();
        ++k;
      }
      out_faces.push_back(t);
    }
    for (const auto h : mesh.halfedges()) report.boundary_edges += mesh.is_border(h) ? 1 : 0;
  } else {
    // Empty, or a soup CGAL could not make a mesh of (never seen after orient_polygon_soup):
    // kept as it is, consistently oriented as far as it goes.
    out_points = points;
    for (const auto& p : polygons) out_faces.push_back({p[0], p[1], p[2]});
    std::set<std::pair<std::size_t, std::size_t>> directed;
    for (const auto& t : out_faces)
      for (std::size_t k = 0; k < 3; ++k) directed.insert({t[k], t[(k + 1) % 3]});
    for (const auto& e : directed) report.boundary_edges += directed.count({e.second, e.first}) == 0 ? 1 : 0;
  }

  // Net flips: the kept faces keep their index through steps 6-8 (filled holes come after).
  // Each kept face starts again at its first corner of the input (the half-edge mesh may
  // rotate its corners), so that a mesh without defects comes back exactly as it was.
  for (std::size_t i = 0; i < before.size() && i < out_faces.size(); ++i) {
    auto& t = out_faces[i];
    for (int turn = 0; turn < 2 && !(out_points[t[0]] == before[i][0]); ++turn) std::rotate(t.begin(), t.begin() + 1, t.end());
    const std::array<Point, 3> now{out_points[t[0]], out_points[t[1]], out_points[t[2]]};
    report.faces_flipped += reversed(before[i], now) ? 1 : 0;
  }

  // Holes (boundary cycles), components, zero-area faces of the result.
  {
    std::vector<std::size_t> parent(out_faces.size());
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    std::vector<std::pair<std::pair<std::size_t, std::size_t>, std::size_t>> edges;  // (sorted edge, face)
    edges.reserve(3 * out_faces.size());
    for (std::size_t f = 0; f < out_faces.size(); ++f)
      for (std::size_t k = 0; k < 3; ++k)
        edges.push_back({std::minmax(out_faces[f][k], out_faces[f][(k + 1) % 3]), f});
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i + 1 < edges.size(); ++i)
      if (edges[i].first == edges[i + 1].first) parent[find(parent, edges[i].second)] = find(parent, edges[i + 1].second);
    for (std::size_t f = 0; f < out_faces.size(); ++f) report.components += find(parent, f) == f ? 1 : 0;
  }
  if (!mesh.is_empty()) {
    std::vector<bool> seen(mesh.number_of_halfedges(), false);
    for (const auto h : mesh.halfedges()) {
      if (!mesh.is_border(h) || seen[h.idx()]) continue;
      ++report.holes;
      for (auto g = h; !seen[g.idx()]; g = mesh.next(g)) seen[g.idx()] = true;
    }
  } else if (report.boundary_edges > 0) {
    report.holes = 1;  // at least one; the soup has no cycles to walk
  }
  for (const auto& t : out_faces) {
    const Eigen::Vector3d a = toEigen(out_points[t[0]]), b = toEigen(out_points[t[1]]), c = toEigen(out_points[t[2]]);
    const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (!((b - a).cross(c - a).norm() > options.degenerate_tolerance * longest)) ++report.degenerate_faces;
  }
  report.closed = !out_faces.empty() && report.boundary_edges == 0;

  // The vertices in the order of the input (CGAL moves the last vertices into the places of
  // removed ones); the copies CGAL made at non-manifold places come last.
  std::map<std::array<double, 3>, std::size_t> first_index;
  for (std::size_t i = vertices.size(); i-- > 0;) first_index[{vertices[i].x(), vertices[i].y(), vertices[i].z()}] = i;
  std::vector<std::size_t> key(out_points.size());
  std::set<std::size_t> used;
  for (std::size_t i = 0; i < out_points.size(); ++i) {
    const std::size_t k = first_index.at({out_points[i].x(), out_points[i].y(), out_points[i].z()});
    key[i] = used.insert(k).second ? k : vertices.size() + i;
  }
  std::vector<std::size_t> order(out_points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  std::vector<int> new_index(out_points.size());
  std::vector<Eigen::Vector3d> new_vertices;
  new_vertices.reserve(out_points.size());
  for (const std::size_t i : order) {
    new_index[i] = static_cast<int>(new_vertices.size());
    new_vertices.push_back(toEigen(out_points[i]));
  }
  std::vector<std::array<int, 3>> new_faces;
  new_faces.reserve(out_faces.size());
  for (const auto& t : out_faces) new_faces.push_back({new_index[t[0]], new_index[t[1]], new_index[t[2]]});
  vertices = std::move(new_vertices);
  faces = std::move(new_faces);
  report.vertices_out = vertices.size();
  report.faces_out = faces.size();
  return report;
}

std::string describe(const RepairReport& r) {
  std::vector<std::string> changes;
  if (r.duplicate_vertices_merged) changes.push_back("merged " + count(r.duplicate_vertices_merged, "duplicate vertex", "duplicate vertices"));
  if (r.degenerate_faces_removed) changes.push_back("removed " + count(r.degenerate_faces_removed, "face", "faces") + " with a repeated vertex");
  if (r.duplicate_faces_removed) changes.push_back("removed " + count(r.duplicate_faces_removed, "duplicate face", "duplicate faces"));
  if (r.opposite_faces_removed)
    changes.push_back("removed " + count(r.opposite_faces_removed / 2, "opposite face pair", "opposite face pairs"));
  if (r.isolated_vertices_removed) changes.push_back("removed " + count(r.isolated_vertices_removed, "unused vertex", "unused vertices"));
  if (r.faces_flipped) changes.push_back("flipped " + count(r.faces_flipped, "face", "faces"));
  if (r.vertices_duplicated) {
    std::string where;
    if (r.non_manifold_edges) where = count(r.non_manifold_edges, "non-manifold edge", "non-manifold edges");
    if (r.non_manifold_vertices)
      where += (where.empty() ? "" : " and ") + count(r.non_manifold_vertices, "non-manifold vertex", "non-manifold vertices");
    if (where.empty()) where = "a non-orientable strip";
    changes.push_back("duplicated " + count(r.vertices_duplicated, "vertex", "vertices") + " to cut " + where);
  }
  if (r.holes_filled)
    changes.push_back("filled " + count(r.holes_filled, "hole", "holes") + " with " + count(r.hole_faces_added, "triangle", "triangles"));
  std::string s;
  for (std::size_t i = 0; i < changes.size(); ++i) s += (i ? ", " : "") + changes[i];
  if (s.empty()) s = "no change";
  s += "; ";
  if (r.faces_out == 0) {
    s += "no face left";
  } else if (r.closed) {
    s += r.oriented_outward ? "closed and outward" : "closed";
  } else {
    s += "open: " + count(r.boundary_edges, "boundary edge", "boundary edges") + " in " + count(r.holes, "hole", "holes");
    if (r.holes_not_filled) s += " (" + count(r.holes_not_filled, "hole", "holes") + " could not be filled)";
    else s += " (not filled)";
  }
  if (r.degenerate_faces) s += ", " + count(r.degenerate_faces, "zero-area face", "zero-area faces") + " left";
  s += ", " + count(r.components, "component", "components") + ", " + count(r.vertices_out, "vertex", "vertices") + ", " +
       count(r.faces_out, "face", "faces");
  return s;
}

}  // namespace steady::sweep
