// Seeded stress campaign of the swept envelope: random cases (a mesh, a random motion of one of
// five kinds, a tolerance) through the checks of the envelope tests (envelope_oracle.hpp), one
// log line per case. Not a ctest test: the 1,800 cases of the campaign take about six minutes
// on two cores. scripts/stress-sweep.sh runs a range of cases, each in its own process with a
// time limit (a crash or a hang loses that case only), and summarises the log.
//
//   steady_sweep_stress --first I [--end J]     cases I .. J-1 of the table (default: case I)
//   --smooth         with --first: the second table, smooth keyframe motions (see
//                    smoothCaseOf); with --case, KIND "smooth" draws such a motion
//   --shears         with --first: the third table, polySAMs of straight shears (see
//                    shearCaseOf); with --case, KIND "shears" draws such a motion
//   steady_sweep_stress --case MESH KIND SEED REL [--mesh-file F] [--motion-file F]
//                                               one case by its parameters; the files (as
//                                               written by --repro-dir) replace the generated
//                                               mesh or motion, the seed still seeds the checks
//                                               (a text OFF mesh file is read in double, so
//                                               it repeats the case bit for bit)
//   --dense          denser checks (480 posed points, 400 envelope vertices, 300 cross points)
//   --all-vertices   also every envelope vertex against the true boundary, not only a sample:
//                    against the posed bodies (checkVerticesInBox) and, for the vertices inside
//                    the swept volume, across its boundary (checkAcross)
//   --refinements N  re-sweeps allowed (SweepOptions::refinements; default 2): 0 checks the
//                    first sweep's envelope
//   --repro-dir DIR  for each failing case, and each whose envelope lists kept-wall vertices it
//                    could not certify, its motion (a motion file, every key pose at full
//                    precision) and its mesh (OFF) in DIR, for the steady CLI or --case
//   --log FILE       append each case's lines to FILE too (one write per case: several
//                    processes may share the file)
//   --list           print the cases of the range instead of running them
//
// Each case line starts with its status: PASS; VOID (the envelope has more than one shell, and
// every extra shell is verified to be a true cavity of the swept volume: only the one-shell
// expectation fails); FAIL (the failure messages follow the line); THROW (sweptEnvelope threw);
// SKIP (CGAL's sample meshes were not found when the build was configured).
// Exit status: 0 when every case is PASS, VOID or SKIP; 1 when one is FAIL or THROW; 2 for a bad
// argument or an unreadable file.
#include <steady/io/mesh.hpp>
#include <steady/io/motion_file.hpp>

#include "sweep/envelope_check.hpp"
#include "sweep/envelope_oracle.hpp"
#include "sweep/sweep_test.hpp"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#ifdef STEADY_CGAL_MESHES
#include "bench/sample_meshes.hpp"
#endif

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <numeric>
#include <chrono>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using steady::Motion3;
using steady::sweep::Envelope;
using namespace steady_sweep_test;

// ---- the case table ----------------------------------------------------------------------------

const char* const kMeshNames[] = {"box", "sphere", "L", "torus", "prism", "bracket", "cgalsphere", "convex", "star"};
constexpr int kMeshCount = 9;
const MotionKind kKinds[] = {MotionKind::Screw, MotionKind::Translation, MotionKind::Affine, MotionKind::ShearScale,
                             MotionKind::PolySam};
const char* const kKindNames[] = {"screw", "translation", "affine", "shearscale", "polysam"};
constexpr int kKindCount = 5;

struct Case {
  std::string mesh, kind;
  std::uint64_t seed = 0;
  double rel = 1e-3;
};

// Case i of the table: round i / 45 of every mesh with every motion kind, in that order. The
// seed depends on the round and the pair only, and the tolerance alternates between 1e-3 and
// 2e-3, so that a case keeps its number, motion and mesh however the table is cut into runs.
Case caseOf(long i) {
  const int combos = kMeshCount * kKindCount;
  const long round = i / combos;
  const int combo = static_cast<int>(i % combos);
  Case c;
  c.mesh = kMeshNames[combo / kKindCount];
  c.kind = kKindNames[combo % kKindCount];
  c.seed = 1000003ull * static_cast<std::uint64_t>(round) + 101ull * static_cast<std::uint64_t>(combo) + 7;
  c.rel = (round + combo) % 2 ? 2e-3 : 1e-3;
  return c;
}

// Case i of a table of one motion kind: every mesh in turn along a motion of that kind of its
// own, the tolerance alternating as in the first table; `salt` keeps the tables' seeds apart.
Case meshTableCaseOf(long i, const char* kind, std::uint64_t salt) {
  const long round = i / kMeshCount;
  const int m = static_cast<int>(i % kMeshCount);
  Case c;
  c.mesh = kMeshNames[m];
  c.kind = kind;
  c.seed = 1000003ull * static_cast<std::uint64_t>(round) + 101ull * static_cast<std::uint64_t>(m) + salt;
  c.rel = (round + m) % 2 ? 2e-3 : 1e-3;
  return c;
}

// Case i of the second table (--smooth): smooth keyframe motions (see randomSmoothMotion).
Case smoothCaseOf(long i) { return meshTableCaseOf(i, "smooth", 11); }

// Case i of the third table (--shears): polySAMs of straight shears (see randomShearPolySam).
Case shearCaseOf(long i) { return meshTableCaseOf(i, "shears", 13); }

std::string format(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* f, ...) {
  va_list ap;
  va_start(ap, f);
  va_list again;
  va_copy(again, ap);
  const int n = std::vsnprintf(nullptr, 0, f, ap);
  va_end(ap);
  std::string s(static_cast<std::size_t>(std::max(n, 0)) + 1, '\0');
  std::vsnprintf(s.data(), s.size(), f, again);
  va_end(again);
  s.pop_back();
  return s;
}

std::string caseName(const Case& c) {
  return format("%s/%s/s%llu/r%g", c.mesh.c_str(), c.kind.c_str(), static_cast<unsigned long long>(c.seed), c.rel);
}

// ---- meshes ------------------------------------------------------------------------------------

Mesh readAsIs(const std::string& path) {
  steady::io::TriangleMesh t = steady::io::readMesh(path);
  return Mesh{std::move(t.vertices), std::move(t.faces)};
}

// The prism over a random star-shaped polygon about the z axis (7 to 12 corners, alternately
// far and near), its caps fanned from their centres: non-convex, with sharp inner corners.
Mesh starPrism(std::mt19937_64& rng) {
  const int n = 7 + static_cast<int>(rng() % 6);
  const double z1 = uniform(rng, 0.3, 0.8);
  std::vector<std::array<double, 2>> corners;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * (k + uniform(rng, -0.3, 0.3)) / n;
    const double r = k % 2 ? uniform(rng, 0.25, 0.6) : uniform(rng, 0.7, 1.1);
    corners.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return starPrismOf(corners, z1);
}

// The case's mesh; none when it is CGAL's sphere and the build found no CGAL sample data.
// `seed` draws the random ones (convex, star) from a generator of its own.
std::optional<Mesh> makeMesh(const std::string& name, std::uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0x9E3779B97F4A7C15ull);
  if (name == "box") return box(V(-0.5, -0.3, -0.2), V(0.5, 0.3, 0.2));
  if (name == "sphere") return uvSphere(6, 10, 0.6);
  if (name == "L") return lShape(0.5);
  if (name == "torus") return torus(0.7, 0.25, 12, 6);
  if (name == "prism")
    return prism({{{0.6, 0}}, {{0.2, 0.55}}, {{-0.5, 0.35}}, {{-0.5, -0.35}}, {{0.2, -0.55}}}, -0.3, 0.3, 0);
  if (name == "bracket") return readAsIs(STEADY_DATA_DIR "/meshes/bracket.off");
  if (name == "cgalsphere") {
#ifdef STEADY_CGAL_MESHES
    // As the benchmarks take it: 320 faces, centred, scaled to a unit box diagonal.
    steady::io::TriangleMesh t = steady::io::readMesh(steady_bench::meshPath("sphere"));
    steady_bench::toUnitDiagonal(t);
    return Mesh{std::move(t.vertices), std::move(t.faces)};
#else
    return std::nullopt;
#endif
  }
  if (name == "convex") return randomConvex(rng, 10 + static_cast<int>(rng() % 7));
  if (name == "star") return starPrism(rng);
  throw std::logic_error("unknown mesh " + name);  // (names are checked with the arguments)
}

// A smooth keyframe motion as CAD and animation tools make them: a C1 bi-arc through five key
// poses at t = 0, 1/4, .., 1, replaced by SAM spans within 1e-3 of the body's diagonal
// (KeyframeMotion::toMotion; 24 to 128 spans in cases 0-899). From the identity, each key
// moves on by 0.3 to 0.9 along a direction that drifts; its rotation angle moves by up to 70
// degrees from the last key's, about an axis drawn anew at about half the keys; and one key
// in three is scaled (0.8 to 1.25, uniformly or along x). Unlike the table's polySAMs (2 or 3 large spans),
// consecutive spans nearly agree. Keys whose bi-arc has no SAM somewhere (Error NoRealLog, e.g.
// a half turn with a scaling between two of its poses) are drawn again.
Motion3 randomSmoothMotion(std::mt19937_64& rng, const steady::Box<3>& body) {
  for (;;) {
    std::vector<steady::Keyframe<3>> keys{{0.0, steady::Affine3()}};
    V pos = V::Zero(), dir = randomUnit(rng), axis = randomUnit(rng);
    double angle = 0;
    for (int k = 1; k <= 4; ++k) {
      dir = (dir + 0.6 * randomUnit(rng)).normalized();
      pos += uniform(rng, 0.3, 0.9) * dir;
      angle += uniform(rng, -70, 70) * M_PI / 180;
      if (uniform(rng, 0, 1) < 0.5) axis = randomUnit(rng);
      steady::Affine3 pose = steady::Affine3::translation(pos) * steady::Affine3::rotation(axis, angle);
      if (uniform(rng, 0, 1) < 1.0 / 3) {
        const double f = uniform(rng, 0.8, 1.25);
        pose = pose * steady::Affine3::scaling(uniform(rng, 0, 1) < 0.5 ? V(f, f, f) : V(f, 1, 1));
      }
      keys.push_back({k / 4.0, pose});
    }
    try {
      return steady::KeyframeMotion3(keys, steady::Interpolation::BiArc).toMotion(body);
    } catch (const steady::Error& e) {
      if (e.code() != steady::ErrorCode::NoRealLog) throw;
    }
  }
}

// A polySAM of 2 or 3 spans along each of which every point moves on a straight line at a
// constant speed: from a random rigid pose, each key is the last one moved by a shear
// x -> c + (I + u v^T)(x - c) + t with |v| = 1 and v . u = v . t = 0, whose log is
// [u v^T, t - u v^T c] (u v^T squares to zero). |u| is 0.5 to 2, c a point of the posed body's
// box (the plane of points that the shear part keeps is v . (x - c) = 0). A third of the spans
// have t = 0 (that plane is held fixed and crosses the body: fixed points on the body's edges,
// where the grazing chords lie), a third t along u, up to half the body's diagonal (the fixed
// plane shifted), and the rest t of 0.2 to 0.5 diagonals across v and u (no point is fixed).
// The first table's polySAMs have such spans only by chance (its "shearscale" kind also
// scales); along these the strips of grazing chords slide along themselves or stand still,
// and a cap's points at a joint are held fixed or placed on a line (cycle.cpp).
Motion3 randomShearPolySam(std::mt19937_64& rng, const steady::Box<3>& body) {
  const double reach = body.diagonal();
  std::vector<steady::Affine3> poses{randomRigidPose(rng, 0.5)};
  const int spans = 2 + static_cast<int>(rng() % 2);
  for (int k = 0; k < spans; ++k) {
    const V v = randomUnit(rng);
    const V across = v.unitOrthogonal(), third = v.cross(across);
    const double turn = uniform(rng, 0, 2 * M_PI);
    const V u = uniform(rng, 0.5, 2.0) * (std::cos(turn) * across + std::sin(turn) * third);
    V c = poses.back()(0.5 * (body.lo + body.hi));  // (then a point of the posed box)
    const V offset(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    c += poses.back().linear() * (0.5 * (body.hi - body.lo)).cwiseProduct(offset);
    V t = V::Zero();
    const int which = static_cast<int>(rng() % 3);
    if (which == 1) t = uniform(rng, -0.5, 0.5) * reach * u.normalized();
    if (which == 2) {
      const double a = uniform(rng, 0, 2 * M_PI);
      t = uniform(rng, 0.2, 0.5) * reach * (std::cos(a) * across + std::sin(a) * third);
    }
    const Eigen::Matrix3d L = Eigen::Matrix3d::Identity() + u * v.transpose();
    poses.push_back(steady::Affine3(L, c - L * c + t) * poses.back());
  }
  return Motion3::polySam(poses);
}

MotionKind kindOf(const std::string& name) {
  for (int i = 0; i < kKindCount; ++i)
    if (name == kKindNames[i]) return kKinds[i];
  throw std::logic_error("unknown motion kind " + name);
}

// ---- reproduction files ------------------------------------------------------------------------

// The motion as a motion file: every key pose as a 3 x 4 matrix, every number with 17 digits
// (it reads back to the same doubles), joined by SAMs as the generated motions are.
std::string motionFile(const Motion3& m) {
  std::string s = "{\"keyframes\": [\n";
  const auto keys = m.keyframes();
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const auto& L = keys[i].pose.linear();
    const auto& t = keys[i].pose.translation();
    s += format("  {\"t\": %.17g, \"pose\": [", keys[i].t);
    for (int r = 0; r < 3; ++r)
      s += format("[%.17g, %.17g, %.17g, %.17g]%s", L(r, 0), L(r, 1), L(r, 2), t(r), r < 2 ? ", " : "");
    s += i + 1 < keys.size() ? "]},\n" : "]}\n";
  }
  return s + "], \"interpolation\": \"polysam\"}\n";
}

// Writes the case's motion and mesh into `dir` (created if missing); returns the log line that
// names them, or says why they could not be written.
std::string writeReproduction(const std::string& dir, const Case& c, const Mesh& mesh, const Motion3& motion) {
  ::mkdir(dir.c_str(), 0755);  // (an existing directory is fine; the writes below report any other fault)
  const std::string base = format("%s/%s_%s_s%llu_r%g", dir.c_str(), c.mesh.c_str(), c.kind.c_str(),
                                  static_cast<unsigned long long>(c.seed), c.rel);
  try {
    steady::io::writeMesh(base + ".off", steady::io::TriangleMesh{mesh.v, mesh.f});
    std::ofstream(base + ".motion.json") << motionFile(motion);
  } catch (const steady::Error& e) {
    return format("    reproduction files not written: %s\n", e.what());
  }
  return "    motion: " + base + ".motion.json, mesh: " + base + ".off\n";
}

// ---- extra shells ------------------------------------------------------------------------------

// For an envelope of more than one shell: whether every shell but the largest is a true cavity
// of the swept volume (then only the one-shell expectation fails, and the case is a VOID). A
// solid extra shell cannot be right: the swept volume of a connected body is connected. A cavity
// is verified when
// - up to 300 of its vertices are within T of the true boundary, as in checkEnvelope (at most
//   2% undecided within the oracle's budget), and
// - at least 5 of up to 40 random points enclosed by it, and farther than k ε from the envelope,
//   are outside every posed body, none inside one (at most 10% undecided), and none is inside
//   the envelope as a whole (winding number) nor, for k = 3, inside by SweptVolume. If the
//   envelope is within ε of the true boundary, such a point is outside every posed body by
//   (k - 1) ε: k = 3 and decided at ε; for thin cavities, where too few points lie that far
//   from the walls, k = 1.5 decided at 0.4 ε, then k = 0.5 decided at any positive distance.
// Returns what is not verified ("" when all is); `summary` describes every shell.
std::string verifyExtraShells(const Mesh& mesh, const Motion3& motion, const Envelope& env, std::uint64_t seed,
                              std::string& summary) {
  const std::vector<V>& ev = env.vertices;
  const Faces& ef = env.triangles;
  const double eps = env.tolerance;
  const double T = eps * 1.01 + 1e-9 * (boxHi(ev) - boxLo(ev)).norm();
  const MovingBody mb(mesh, motion);
  const steady::sweep::SweptVolume sv(makeBody(mesh), motion);
  std::mt19937_64 rng(seed ^ 0x5EEDF00Dull);
  const std::vector<Faces> shells = edgeComponents(ef);
  std::string bad;
  summary = std::to_string(shells.size()) + " shells:";
  for (std::size_t c = 0; c < shells.size(); ++c) {
    const Faces& f = shells[c];
    const double vol = meshVolume(ev, f);
    summary += format(" [%zu tri V %.4g A %.4g]", f.size(), vol, meshArea(ev, f));
    if (c == 0) continue;
    if (vol > 0) {
      bad += format("shell %zu is solid (V %.4g, %zu tri); ", c, vol, f.size());
      continue;
    }
    // Its vertices in the order the faces first name them, then a seeded sample of them.
    std::vector<int> verts;
    std::vector<char> seen(ev.size(), 0);
    std::vector<V> corners;
    for (const auto& t : f)
      for (const int k : t) {
        corners.push_back(ev[static_cast<std::size_t>(k)]);
        if (!seen[static_cast<std::size_t>(k)]) seen[static_cast<std::size_t>(k)] = 1, verts.push_back(k);
      }
    std::shuffle(verts.begin(), verts.end(), rng);
    if (verts.size() > 300) verts.resize(300);
    int off_boundary = 0, vundecided = 0;
    double worst_off = 0;  // the largest lower bound of a distance off the true boundary, in eps
    for (const int i : verts) {
      const MinBracket b = boundaryBracket(mb, ev[static_cast<std::size_t>(i)], T);
      if (b.lo > T || b.hi < -T) ++off_boundary, worst_off = std::max({worst_off, b.lo / eps, -b.hi / eps});
      else if (!(b.hi <= T && b.lo >= -T)) ++vundecided;
    }
    const V lo = boxLo(corners), hi = boxHi(corners);
    int enclosed = 0, in_body = 0, pundecided = 0, in_sv = 0, in_env = 0;
    double k_used = 3;
    for (const double k : {3.0, 1.5, 0.5}) {
      k_used = k;
      enclosed = in_body = pundecided = in_sv = in_env = 0;
      const double decided = k == 3.0 ? eps : k == 1.5 ? 0.4 * eps : 0.0;
      for (int tries = 0; tries < 4000 && enclosed < 40; ++tries) {
        const V x(uniform(rng, lo.x(), hi.x()), uniform(rng, lo.y(), hi.y()), uniform(rng, lo.z(), hi.z()));
        if (windingNumber(ev, f, x) > -0.5) continue;  // not enclosed by this (inward) shell
        if (meshDistance(ev, ef, x) <= k * eps) continue;
        ++enclosed;
        if (std::abs(windingNumber(ev, ef, x)) >= 0.5) ++in_env;
        if (k == 3.0 && sv.contains(x)) ++in_sv;
        const MinBracket b =
            minSignedDistance(mb, x, [&](double blo, double bhi) { return blo > decided || bhi < -eps; }, 20000);
        if (b.hi < -eps) ++in_body;
        else if (!(b.lo > decided)) ++pundecided;
      }
      if (enclosed >= 5) break;
    }
    summary += format("{cavity: %zu vertices checked, %d off the true boundary (the farthest by at least %.3g eps), %d undecided; "
                      "%d points enclosed (>%g eps from the envelope), %d inside a posed body, %d undecided, %d inside "
                      "by SweptVolume, %d inside by winding number}",
                      verts.size(), off_boundary, worst_off, vundecided, enclosed, k_used, in_body, pundecided, in_sv,
                      in_env);
    const bool vertices_ok = off_boundary == 0 && vundecided <= static_cast<int>(verts.size()) / 50;
    const bool points_ok = enclosed >= 5 && in_body == 0 && in_sv == 0 && in_env == 0 && pundecided <= enclosed / 10;
    if (!vertices_ok || !points_ok)
      bad += format("cavity shell %zu not verified; ", c);
  }
  return bad;
}

// ---- one case ----------------------------------------------------------------------------------

struct Options {
  bool dense = false, all_vertices = false;
  int refinements = -1;  // (negative: SweepOptions' default)
  std::string repro_dir, log;
  std::string mesh_file, motion_file;  // (--case only)
};

double seconds() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

void appendToLog(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT, 0644);
  if (fd < 0 || ::write(fd, text.data(), text.size()) != static_cast<ssize_t>(text.size()))
    std::fprintf(stderr, "steady_sweep_stress: cannot append to %s\n", path.c_str());
  if (fd >= 0) ::close(fd);
}

// Runs one case and reports it (standard output, and the log). `index`: its number in the table,
// or -1. Returns its status.
std::string runCase(const Case& c, long index, const Options& opt) {
  const std::string name = caseName(c);
  std::string head = format("%s case=%s mesh=%s kind=%s seed=%llu rel=%g", name.c_str(),
                            index < 0 ? "-" : std::to_string(index).c_str(), c.mesh.c_str(), c.kind.c_str(),
                            static_cast<unsigned long long>(c.seed), c.rel);
  std::optional<Mesh> generated;
  if (opt.mesh_file.empty()) generated = makeMesh(c.mesh, c.seed);
  else generated = readAsIs(opt.mesh_file);
  if (!generated) {
    const std::string out = "SKIP  " + head + " | CGAL's sample meshes were not found when the build was configured\n";
    std::fputs(out.c_str(), stdout);
    if (!opt.log.empty()) appendToLog(opt.log, out);
    return "SKIP";
  }
  const Mesh& mesh = *generated;
  std::mt19937_64 motion_rng(c.seed);
  const Motion3 motion = !opt.motion_file.empty()
                             ? steady::io::readMotionFile(opt.motion_file).motion().toMotion(makeBody(mesh).box())
                         : c.kind == "smooth" ? randomSmoothMotion(motion_rng, makeBody(mesh).box())
                         : c.kind == "shears" ? randomShearPolySam(motion_rng, makeBody(mesh).box())
                                              : randomMotion(kindOf(c.kind), motion_rng);
  // The checks draw from a generator of their own, so that the motion does not depend on them.
  std::mt19937_64 check_rng(c.seed * 6364136223846793005ull + 1442695040888963407ull);
  head += format(" tri_in=%zu spans=%zu", mesh.f.size(), motion.spanCount());

  // Every failure of the gtest assertions below (and in checkEnvelope) lands here, not in a test.
  ::testing::TestPartResultArray failures;
  std::string status, detail;
  // (the envelope lists kept-wall or cavity vertices it could not certify, or took a deep filling)
  bool uncertified_listed = false;
  {
    ::testing::ScopedFakeTestPartResultReporter capture(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &failures);
    const double t0 = seconds();
    Envelope env;
    bool threw = false;
    try {
      env = sweep(mesh, motion, c.rel, opt.refinements);
    } catch (const steady::Error& e) {
      threw = true;
      detail = format("steady::Error %s: %s", steady::to_string(e.code()), e.what());
    } catch (const std::exception& e) {
      threw = true;
      detail = format("std::exception: %s", e.what());
    }
    const double t_sweep = seconds() - t0;
    if (threw) {
      ADD_FAILURE() << name << ": sweptEnvelope threw " << detail;
      status = "THROW";
      head += format(" | sweep %.3fs | %s", t_sweep, detail.c_str());
    } else {
      uncertified_listed =
          !env.kept_wall_uncertified.empty() || !env.cavity_uncertified.empty() ||
          !env.kept_wall_faces_uncertified.empty() || !env.cavity_faces_uncertified.empty() ||
          env.deep_fillings_taken > 0;
      const double t1 = seconds();
      // The library's own check of its output, beside checkEnvelope's inspectMesh.
      EXPECT_TRUE(env.check.closed) << "env.check.closed";
      EXPECT_TRUE(env.check.manifold) << "env.check.manifold";
      EXPECT_TRUE(env.check.oriented) << "env.check.oriented";
      EXPECT_EQ(env.check.self_intersections, 0) << "env.check.self_intersections";
      EXPECT_EQ(env.check.shells, 1) << "env.check.shells";
      EXPECT_GT(env.check.volume, 0) << "env.check.volume";
      EXPECT_EQ(env.pinches_touching, 0u) << "env.pinches_touching";
      // Fewer points than the envelope tests' defaults, for the number of cases; a random sweep
      // may enclose a void or close a handle, so the Euler characteristic is not checked.
      CheckOptions co;
      co.containment_points = opt.dense ? 480 : 120;
      co.boundary_vertices = opt.dense ? 400 : 60;
      co.cross_points = opt.dense ? 300 : 60;
      co.expected_euler = 99;
      CheckStats st;
      checkEnvelope(mesh, motion, env, epsOf(mesh, c.rel), check_rng, name, co, &st);
      std::string notes;
      bool voids = false;
      const MovingBody mb(mesh, motion);
      // Across the boundary of the swept volume (checkAcross): the vertices of kept walls that
      // the envelope's own certificate leaves uncertified within eps, or with --all-vertices every
      // vertex (a superset, so each is checked once); one that the oracle finds inside with no
      // outside point within T fails the case.
      std::vector<int> across_which = env.kept_wall_uncertified;
      across_which.insert(across_which.end(), env.cavity_uncertified.begin(), env.cavity_uncertified.end());
      if (opt.all_vertices) {
        across_which.resize(env.vertices.size());
        std::iota(across_which.begin(), across_which.end(), 0);
      }
      const AcrossCheck across = checkAcross(env, mb, across_which);
      for (std::size_t k = 0; k < across.deep.size() && k < static_cast<std::size_t>(kMaxMessages); ++k)
        ADD_FAILURE() << "envelope vertex " << across.deep[k] << " at " << env.vertices[across.deep[k]].transpose()
                      << " is inside the swept volume with no point outside it within 1.01 eps";
      if (!env.kept_wall_uncertified.empty()) {
        const auto listed = static_cast<std::size_t>(std::count_if(across.deep.begin(), across.deep.end(), [&](int v) {
          return std::binary_search(env.kept_wall_uncertified.begin(), env.kept_wall_uncertified.end(), v);
        }));
        notes += format(" | uncertified %zu: %zu deep", env.kept_wall_uncertified.size(), listed) +
                 (opt.all_vertices ? std::string() : format(", %d undecided", across.undecided));
      }
      if (!env.kept_wall_faces_uncertified.empty() || !env.cavity_faces_uncertified.empty())
        notes += format(" | faces uncertified %zu kept-wall, %zu cavity", env.kept_wall_faces_uncertified.size(),
                        env.cavity_faces_uncertified.size());
      if (env.deep_fillings_taken > 0)
        notes += format(" | deep fillings taken %zu, bound %.3g eps", env.deep_fillings_taken,
                        env.filling_depth_bound / env.tolerance);
      if (env.fillings_refined > 0) notes += format(" | fillings refined %zu", env.fillings_refined);
      if (env.uncertified_vertices_moved > 0) notes += format(" | moved onto the boundary %zu", env.uncertified_vertices_moved);
      if (env.resweeps > 0)
        notes += format(" | resweeps %zu (eps_t = eps / %.0f on %zu of %zu spans)", env.resweeps,
                        env.tolerance / env.tessellation_tolerance, env.spans_refined, env.spans);
      if (!env.cavity_uncertified.empty())
        notes += format(" | cavity vertices %zu, %zu uncertified, bound %.3g eps", env.cavity_vertices,
                        env.cavity_uncertified.size(), env.cavity_depth_bound / env.tolerance);
      if (env.check.shells > 1 && env.check.closed) {
        std::string summary;
        const std::string bad = verifyExtraShells(mesh, motion, env, c.seed, summary);
        notes += " | " + summary + (bad.empty() ? " VERIFIED" : " NOT VERIFIED: " + bad);
        if (!bad.empty()) ADD_FAILURE() << "extra shells: " << bad << summary;
        voids = bad.empty();
      }
      if (opt.all_vertices) {
        const V far = V::Constant(std::numeric_limits<double>::infinity());
        const NearCheck n = checkVerticesInBox(env, mb, -far, far);
        notes += format(" | all %d vertices: %d off the true boundary, %d undecided, worst %.3f eps; %d inside the "
                        "swept volume: %zu with no outside point within T, %d undecided",
                        n.checked, n.failed, n.undecided, n.worst, across.inside, across.deep.size(),
                        across.undecided);
      }
      const double t_check = seconds() - t1;
      // A VOID fails only the shell count: checkEnvelope's mc.shells and env.check.shells above.
      bool only_shell_count = true;
      for (int i = 0; i < failures.size(); ++i)
        if (std::string(failures.GetTestPartResult(i).message()).find(".shells") == std::string::npos)
          only_shell_count = false;
      status = failures.size() == 0 ? "PASS" : voids && only_shell_count ? "VOID" : "FAIL";
      head += format(" | sweep %.3fs check %.2fs | tri %zu V %.6g A %.6g | check: closed %d manifold %d "
                     "oriented %d selfint %ld degenerate %ld shells %d vol %.6g | out<=%.3feps (%d/%d) "
                     "bnd<=%.3feps (%d/%d, undec %d) cross %d/%d sides %d/%d (undec %d, worst %.3geps) | buried %zu "
                     "crack %zu mouths %zu thincav %zu thinsol %zu pinch %zu/%zu merged %zu retries %zu | kept %zu/%zu walls, %zu vertices, %zu "
                     "uncertified, bound %.3g eps",
                     t_sweep, t_check, env.triangles.size(), env.volume, env.area, env.check.closed, env.check.manifold,
                     env.check.oriented, env.check.self_intersections, env.check.degenerate_faces, env.check.shells,
                     env.check.volume, st.worst_outside, st.containment_failed, st.containment_checked,
                     st.worst_boundary, st.boundary_failed, st.boundary_checked, st.boundary_undecided,
                     st.cross_mismatched, st.cross_checked, st.sides_failed, st.sides_checked, st.sides_undecided,
                     st.worst_side,
                     env.buried_patches_removed, env.crack_faces_removed, env.pocket_mouths_filled,
                     env.thin_cavities_removed, env.thin_solids_removed, env.pinched_vertices_split,
                     env.pinches_touching, env.rounding_merged, env.ray_retries, env.buried_patches_kept,
                     env.crack_faces_kept, env.kept_wall_vertices, env.kept_wall_uncertified.size(),
                     env.kept_wall_depth_bound / env.tolerance) +
              notes;
    }
  }

  std::string out = format("%-5s ", status.c_str()) + head + "\n";
  if (status == "FAIL" || status == "THROW") {
    for (int i = 0; i < failures.size(); ++i) {
      const ::testing::TestPartResult& r = failures.GetTestPartResult(i);
      out += format("    ! %s:%d: %s\n", r.file_name() ? r.file_name() : "?", r.line_number(), r.message());
    }
  }
  if ((status == "FAIL" || status == "THROW" || uncertified_listed) && !opt.repro_dir.empty())
    out += writeReproduction(opt.repro_dir, c, mesh, motion);
  std::fputs(out.c_str(), stdout);
  std::fflush(stdout);
  if (!opt.log.empty()) appendToLog(opt.log, out);
  return status;
}

// ---- command line ------------------------------------------------------------------------------

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "steady_sweep_stress: %s\n"
               "usage: steady_sweep_stress (--first I [--end J] [--smooth | --shears] | --case MESH KIND SEED REL [--mesh-file F]\n"
               "       [--motion-file F]) [--dense] [--all-vertices] [--refinements N] [--repro-dir DIR] [--log FILE]\n"
               "       [--list]\n",
               why.c_str());
  std::exit(2);
}

long toLong(const std::string& s) {
  std::size_t used = 0;
  long v = -1;
  try {
    v = std::stol(s, &used);
  } catch (const std::exception&) {
    usage("not a number: " + s);
  }
  if (used != s.size() || v < 0) usage("not a non-negative whole number: " + s);
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  long first = -1, end = -1;
  std::optional<Case> custom;
  bool list = false, smooth = false, shears = false;
  std::vector<std::string> args(argv + 1, argv + argc);
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) usage(a + " needs a value");
      return args[++i];
    };
    if (a == "--first") first = toLong(value());
    else if (a == "--end") end = toLong(value());
    else if (a == "--case") {
      Case c;
      c.mesh = value();
      c.kind = value();
      c.seed = static_cast<std::uint64_t>(toLong(value()));
      const std::string rel = value();
      char* stop = nullptr;
      c.rel = std::strtod(rel.c_str(), &stop);
      if (*stop != '\0' || !(c.rel > 0)) usage("not a positive tolerance: " + rel);
      if (std::find(std::begin(kMeshNames), std::end(kMeshNames), c.mesh) == std::end(kMeshNames))
        usage("unknown mesh " + c.mesh);
      if (c.kind != "smooth" && c.kind != "shears" &&
          std::find(std::begin(kKindNames), std::end(kKindNames), c.kind) == std::end(kKindNames))
        usage("unknown motion kind " + c.kind);
      custom = c;
    } else if (a == "--mesh-file") opt.mesh_file = value();
    else if (a == "--motion-file") opt.motion_file = value();
    else if (a == "--dense") opt.dense = true;
    else if (a == "--all-vertices") opt.all_vertices = true;
    else if (a == "--refinements") opt.refinements = static_cast<int>(toLong(value()));
    else if (a == "--repro-dir") opt.repro_dir = value();
    else if (a == "--log") opt.log = value();
    else if (a == "--list") list = true;
    else if (a == "--smooth") smooth = true;
    else if (a == "--shears") shears = true;
    else usage("unknown argument " + a);
  }
  if (custom.has_value() == (first >= 0)) usage("give either --first or --case");
  if (!custom && end < 0) end = first + 1;
  if (!custom && end <= first) usage("--end must be greater than --first");
  if (custom && smooth) usage("--smooth goes with --first (with --case, give KIND smooth)");
  if (custom && shears) usage("--shears goes with --first (with --case, give KIND shears)");
  if (smooth && shears) usage("give --smooth or --shears, not both");
  if (!custom && !(opt.mesh_file.empty() && opt.motion_file.empty()))
    usage("--mesh-file and --motion-file go with --case");

  std::vector<std::pair<long, Case>> cases;
  if (custom) cases.emplace_back(-1, *custom);
  for (long i = first; !custom && i < end; ++i) cases.emplace_back(i, smooth ? smoothCaseOf(i) : shears ? shearCaseOf(i) : caseOf(i));
  bool failed = false;
  try {
    for (const auto& [index, c] : cases) {
      if (list) {
        std::printf("%ld %s\n", index, caseName(c).c_str());
        continue;
      }
      const std::string status = runCase(c, index, opt);
      failed = failed || status == "FAIL" || status == "THROW";
    }
  } catch (const steady::Error& e) {  // an unreadable mesh or motion file
    std::fprintf(stderr, "steady_sweep_stress: %s: %s\n", steady::to_string(e.code()), e.what());
    return 2;
  }
  return failed ? 1 : 0;
}
