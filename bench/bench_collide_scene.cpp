// First-contact queries of CGAL's sample meshes against a static scene of about one million
// triangles, in the steady_bench binary, with FCL 0.7 as the peer when it is available.
//
// Scene: 3,200 copies of CGAL's sphere.off (320 faces each, 1,024,000 triangles), diameter 0.1,
// on a 64 x 50 grid of spacing 0.12 in the plane z = 0. Moving body: a CGAL sample mesh scaled
// to a bounding-box diagonal of 1, starting with its lowest point 0.3 above the spheres' tops,
// over the grid's centre. Motions (one SAM span each, ending one body diameter lower):
//   screw  - a half turn about the vertical axis through the body's centre plus the descent;
//   affine - a 60 degree turn about a tilted axis, scaling (1.3, 0.8, 1.1), a shear of 0.2 and
//            the descent.
// Benchmarks (one query per iteration; the scene and FCL's BVHs are built once, outside):
//   BM_SteadyFirstContact/<mesh>/<motion>    StaticScene::firstContact of a PreparedMesh, exact.
//                                             The moving mesh's hierarchy is built once outside
//                                             the timed loop, as FCL's BVH of the moving mesh is
//                                             for BM_FclSampled (a like-for-like comparison)
//   BM_SteadyFirstContactUnprepared/<mesh>/<motion>  the same query from plain vertex and face
//                                             arrays (no hierarchy kept between queries)
//   BM_FclSampled<N>/<mesh>/<motion>          fcl::collide at N+1 poses of the same SAM (N = 100,
//                                             1000), stopping at the first colliding pose; the
//                                             counter `late` is how much later than steady's
//                                             exact time that pose is
//   BM_SteadyClearance/<mesh>/screw          StaticScene::clearance over a half turn that stops
//                                             0.05 above the spheres (bracket within 1%)
//   BM_FclConservativeAdvancement/<mesh>/screw  fcl::continuousCollide (screw motion, conservative
//                                             advancement), with `error` = its time - steady's
// DoNotOptimize gets doubles as const references: Debian's Google Benchmark 1.7 mis-compiles the
// read-write form for a double under GCC (the value comes back as garbage).
// Meshes come from Debian's libcgal-demo (/usr/share/doc/libcgal-dev/data.tar.gz), extracted at
// configure time into STEADY_CGAL_MESHES; without them these benchmarks are not registered.
#include "sample_meshes.hpp"
#include <steady/collide/collide.hpp>
#include <steady/io/mesh.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#ifdef STEADY_BENCH_FCL
#include <fcl/fcl.h>
#endif

namespace {

using V = Eigen::Vector3d;

struct Scene {
  steady::io::TriangleMesh mesh;
  std::unique_ptr<steady::StaticScene> steady;
  double build_seconds = 0;
#ifdef STEADY_BENCH_FCL
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl;
#endif
};

#ifdef STEADY_BENCH_FCL
// An FCL BVH (OBBRSS) over shared vertices, so that replaceSubModel can re-pose it.
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fclModel(const steady::io::TriangleMesh& m) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Triangle> tris;
  tris.reserve(m.faces.size());
  for (const auto& f : m.faces)
    tris.emplace_back(static_cast<std::size_t>(f[0]), static_cast<std::size_t>(f[1]), static_cast<std::size_t>(f[2]));
  model->beginModel();
  model->addSubModel(m.vertices, tris);
  model->endModel();
  return model;
}
#endif

using steady_bench::meshPath;

Scene& scene() {
  static Scene s = [] {
    Scene out;
    const steady::io::TriangleMesh sphere = steady::io::readMesh(meshPath("sphere"));
    V lo = sphere.vertices.front(), hi = lo;
    for (const V& p : sphere.vertices) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double scale = 0.1 / (hi - lo).maxCoeff();
    const V c = 0.5 * (lo + hi);
    for (int i = 0; i < 64; ++i)
      for (int j = 0; j < 50; ++j) {
        const steady::Affine3 place = steady::Affine3::translation(V(0.12 * (i - 31.5), 0.12 * (j - 24.5), 0)) *
                                      steady::Affine3::scaling(scale) * steady::Affine3::translation(-c);
        steady::io::append(out.mesh, steady::io::transformed(sphere, place));
      }
    const auto t0 = std::chrono::steady_clock::now();
    out.steady = std::make_unique<steady::StaticScene>(out.mesh.vertices, out.mesh.faces);
    out.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
#ifdef STEADY_BENCH_FCL
    out.fcl = fclModel(out.mesh);
#endif
    return out;
  }();
  return s;
}

// The moving body, scaled to diagonal 1, centred at the origin (body coordinates).
struct Body {
  steady::io::TriangleMesh mesh;
  std::unique_ptr<steady::PreparedMesh> prepared;  // built once, like FCL's BVH below
  double half_height = 0;
#ifdef STEADY_BENCH_FCL
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl;
#endif
};

const Body& body(const std::string& name) {
  static std::map<std::string, Body> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  Body b;
  b.mesh = steady::io::readMesh(meshPath(name));
  steady_bench::toUnitDiagonal(b.mesh);
  double zlo = b.mesh.vertices.front().z(), zhi = zlo;
  for (const V& p : b.mesh.vertices) zlo = std::min(zlo, p.z()), zhi = std::max(zhi, p.z());
  b.half_height = 0.5 * (zhi - zlo);
  b.prepared = std::make_unique<steady::PreparedMesh>(b.mesh.vertices, b.mesh.faces);
#ifdef STEADY_BENCH_FCL
  b.fcl = fclModel(b.mesh);
#endif
  return cache.emplace(name, std::move(b)).first->second;
}

// Start pose: lowest point 0.3 above the spheres' tops (z = 0.05); end: one diameter (1) lower.
steady::Motion3 motionFor(const Body& b, bool screw) {
  const steady::Affine3 B = steady::Affine3::translation(V(0.03, -0.02, 0.05 + 0.3 + b.half_height));
  steady::Affine3 C;
  if (screw) {
    C = steady::Affine3::translation(V(0.03, -0.02, 0.05 + 0.3 + b.half_height - 1.0)) *
        steady::Affine3::rotation(V(0, 0, 1), M_PI * (1 - 1e-9));  // just under a half turn: one SAM
  } else {
    Eigen::Matrix3d shear = Eigen::Matrix3d::Identity();
    shear(0, 2) = 0.2;
    C = steady::Affine3::translation(V(0.1, 0.05, 0.05 + 0.3 + b.half_height - 1.0)) *
        steady::Affine3::rotation(V(1, 1, 3), M_PI / 3) * steady::Affine3(shear, V::Zero()) *
        steady::Affine3::scaling(V(1.3, 0.8, 1.1));
  }
  return steady::Motion3::polySam(std::vector<steady::Affine3>{B, C});
}

double steadyFirst(const Body& b, const steady::Motion3& m, steady::CollideStats* stats = nullptr,
                   bool prepared = true) {
  const auto c = prepared ? scene().steady->firstContact(*b.prepared, m, {}, stats)
                          : scene().steady->firstContact(b.mesh.vertices, b.mesh.faces, m, {}, stats);
  return c ? c->t : 2.0;
}

void BM_SteadyFirstContact(benchmark::State& state, const std::string& name, bool screw, bool prepared) {
  scene();  // built once, outside the timed loop
  const Body& b = body(name);
  const steady::Motion3 m = motionFor(b, screw);
  steady::CollideStats stats;
  double t = 2;
  for (auto _ : state) {
    stats = {};
    t = steadyFirst(b, m, &stats, prepared);
    benchmark::DoNotOptimize(static_cast<const double&>(t));
  }
  state.counters["t_contact"] = t;
  state.counters["faces"] = static_cast<double>(b.mesh.faces.size());
  state.counters["scene_faces"] = static_cast<double>(scene().mesh.faces.size());
  state.counters["scene_build_s"] = scene().build_seconds;
  state.counters["pairs"] = static_cast<double>(stats.pairs_solved);
  state.counters["solves"] = static_cast<double>(stats.feature_solves);
  state.counters["broad_ms"] = 1e3 * stats.broad_seconds;
  state.counters["narrow_ms"] = 1e3 * stats.narrow_seconds;
}

// Clearance over a screw that stops short of the scene: a half turn while descending 0.25 of
// the 0.3 gap (the distance never reaches 0).
void BM_SteadyClearance(benchmark::State& state, const std::string& name) {
  scene();
  const Body& b = body(name);
  const steady::Affine3 B = steady::Affine3::translation(V(0.03, -0.02, 0.05 + 0.3 + b.half_height));
  const steady::Affine3 C = steady::Affine3::translation(V(0.03, -0.02, 0.05 + 0.05 + b.half_height)) *
                            steady::Affine3::rotation(V(0, 0, 1), M_PI * (1 - 1e-9));
  const steady::Motion3 m = steady::Motion3::polySam(std::vector<steady::Affine3>{B, C});
  steady::Clearance c;
  for (auto _ : state) {
    c = scene().steady->clearance(b.mesh.vertices, b.mesh.faces, m);
    benchmark::DoNotOptimize(static_cast<const double&>(c.upper));
  }
  state.counters["lower"] = c.lower;
  state.counters["upper"] = c.upper;
  state.counters["t"] = c.t;
  state.counters["evaluations"] = static_cast<double>(c.evaluations);
}

#ifdef STEADY_BENCH_FCL
fcl::Transform3d toFcl(const steady::Affine3& a) {
  fcl::Transform3d t = fcl::Transform3d::Identity();
  t.linear() = a.linear();
  t.translation() = a.translation();
  return t;
}

// FCL sampling: N+1 poses of the same SAM. FCL's BVH models take rigid transforms; for the affine
// motion the moving vertices are re-posed and the hierarchy refitted at each sample instead.
void BM_FclSampled(benchmark::State& state, const std::string& name, bool screw, int N) {
  const Body& b = body(name);
  const steady::Motion3 m = motionFor(b, screw);
  const double exact = steadyFirst(b, m);
  double found = 2;
  std::vector<V> posed(b.mesh.vertices.size());
  for (auto _ : state) {
    found = 2;
    for (int k = 0; k <= N; ++k) {
      const double t = static_cast<double>(k) / N;
      const steady::Affine3 P = m.pose(t);
      fcl::CollisionRequestd req;
      fcl::CollisionResultd res;
      if (screw) {
        fcl::collide(b.fcl.get(), toFcl(P), scene().fcl.get(), fcl::Transform3d::Identity(), req, res);
      } else {
        for (std::size_t i = 0; i < posed.size(); ++i) posed[i] = P.applyPoint(b.mesh.vertices[i]);
        b.fcl->beginReplaceModel();
        b.fcl->replaceSubModel(posed);
        b.fcl->endReplaceModel(true, true);  // refit the hierarchy bottom-up
        fcl::collide(b.fcl.get(), fcl::Transform3d::Identity(), scene().fcl.get(), fcl::Transform3d::Identity(), req, res);
      }
      if (res.isCollision()) {
        found = t;
        break;
      }
    }
    benchmark::DoNotOptimize(static_cast<const double&>(found));
  }
  if (!screw) {  // restore the body-frame model for the other benchmarks
    b.fcl->beginReplaceModel();
    b.fcl->replaceSubModel(b.mesh.vertices);
    b.fcl->endReplaceModel(true, true);
  }
  state.counters["t_found"] = found;
  state.counters["late"] = found - exact;
}

void BM_FclConservativeAdvancement(benchmark::State& state, const std::string& name) {
  const Body& b = body(name);
  const steady::Motion3 m = motionFor(b, true);
  const double exact = steadyFirst(b, m);
  fcl::ContinuousCollisionRequestd req;
  req.ccd_motion_type = fcl::CCDM_SCREW;
  req.ccd_solver_type = fcl::CCDC_CONSERVATIVE_ADVANCEMENT;
  req.num_max_iterations = 100;
  double toc = 2;
  bool hit = false;
  for (auto _ : state) {
    fcl::ContinuousCollisionResultd res;
    fcl::continuousCollide(b.fcl.get(), toFcl(m.pose(0)), toFcl(m.pose(1)), scene().fcl.get(),
                           fcl::Transform3d::Identity(), fcl::Transform3d::Identity(), req, res);
    hit = res.is_collide;
    toc = res.time_of_contact;
    benchmark::DoNotOptimize(static_cast<const double&>(toc));
  }
  state.counters["t_found"] = hit ? toc : 2.0;
  state.counters["error"] = (hit ? toc : 2.0) - exact;
}
#endif

// Registers the benchmarks for the meshes that exist.
const bool registered = [] {
  for (const char* name : {"elephant", "knot1", "armadillo", "bunny00"}) {
    if (!std::ifstream(meshPath(name)).good()) continue;
    for (bool screw : {true, false}) {
      const std::string tag = std::string(name) + "/" + (screw ? "screw" : "affine");
      benchmark::RegisterBenchmark(("BM_SteadyFirstContact/" + tag).c_str(), BM_SteadyFirstContact, std::string(name),
                                   screw, true)
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark(("BM_SteadyFirstContactUnprepared/" + tag).c_str(), BM_SteadyFirstContact,
                                   std::string(name), screw, false)
          ->Unit(benchmark::kMillisecond);
#ifdef STEADY_BENCH_FCL
      for (int n : {100, 1000})
        benchmark::RegisterBenchmark(("BM_FclSampled" + std::to_string(n) + "/" + tag).c_str(), BM_FclSampled,
                                     std::string(name), screw, n)
            ->Unit(benchmark::kMillisecond);
#endif
    }
    benchmark::RegisterBenchmark(("BM_SteadyClearance/" + std::string(name) + "/screw").c_str(), BM_SteadyClearance,
                                 std::string(name))
        ->Unit(benchmark::kMillisecond);
#ifdef STEADY_BENCH_FCL
    benchmark::RegisterBenchmark(("BM_FclConservativeAdvancement/" + std::string(name) + "/screw").c_str(),
                                 BM_FclConservativeAdvancement, std::string(name))
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
#endif
  }
  return true;
}();

}  // namespace
