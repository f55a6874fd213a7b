// Contact queries of a prepared moving mesh (a body-space box hierarchy built once) against a
// static scene (its own box hierarchy, next to the Embree BVH): a search through time in order,
// descending both hierarchies, with the exact pair solves of collide.cpp at the bottom (see
// PreparedMesh in collide.hpp).
#include <steady/collide/collide.hpp>

#include "internal.hpp"
#include "isolate.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <utility>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace steady {

using namespace detail;

// ---- the static scene's box hierarchy ----------------------------------------------------------

namespace detail {

namespace {

// The binary hierarchy first (median splits, one face per leaf), then collapsed to four
// children a node.
struct StaticBuilder {
  struct BinNode {
    float lo[3], hi[3];
    unsigned first = 0, count = 0;  // count > 0: a leaf of faces[first]; else children first, first + 1
  };
  std::vector<float> lo, hi, centre;  // per face, 3 each: box (rounded outward) and its centre
  std::vector<unsigned> faces;         // in leaf order
  std::vector<BinNode> bin;

  void build(std::size_t node, unsigned begin, unsigned end) {
    float blo[3] = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                    std::numeric_limits<float>::infinity()};
    float bhi[3] = {-blo[0], -blo[1], -blo[2]};
    float clo[3] = {blo[0], blo[1], blo[2]}, chi[3] = {bhi[0], bhi[1], bhi[2]};
    for (unsigned i = begin; i < end; ++i) {
      const std::size_t f = faces[i];
      for (int k = 0; k < 3; ++k) {
        blo[k] = std::min(blo[k], lo[3 * f + k]);
        bhi[k] = std::max(bhi[k], hi[3 * f + k]);
        clo[k] = std::min(clo[k], centre[3 * f + k]);
        chi[k] = std::max(chi[k], centre[3 * f + k]);
      }
    }
    BinNode& n = bin[node];
    std::copy(blo, blo + 3, n.lo);
    std::copy(bhi, bhi + 3, n.hi);
    // One face per leaf: against the benchmark's scene of small sphere copies, leaves of up to
    // four faces let the moving triangles reach the face tests with most of them far away
    // (bunny00 screw 0.201 -> 0.163 ms, armadillo 0.093 -> 0.073 ms, others within noise).
    if (end - begin <= 1) {
      n.first = begin;
      n.count = end - begin;
      return;
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
    const unsigned mid = begin + (end - begin) / 2;
    std::nth_element(faces.begin() + begin, faces.begin() + mid, faces.begin() + end,
                     [&](unsigned x, unsigned y) { return centre[3 * x + axis] < centre[3 * y + axis]; });
    const auto left = static_cast<unsigned>(bin.size());
    bin[node].first = left;  // (n may dangle after the resize below)
    bin[node].count = 0;
    bin.resize(bin.size() + 2);
    build(left, begin, mid);
    build(left + 1, mid, end);
  }

  // Puts binary node b in slot k of out[node]: its box, and the node made of its children and
  // grandchildren (or its face, for a leaf).
  void place(std::vector<StaticNode>& out, std::size_t node, int k, unsigned b) {
    const BinNode& x = bin[b];
    float size = 0;
    for (int j = 0; j < 3; ++j) {
      out[node].lo[j][k] = x.lo[j];
      out[node].hi[j][k] = x.hi[j];
      size = std::max(size, x.hi[j] - x.lo[j]);
    }
    out[node].size[k] = size;
    if (x.count > 0) {
      out[node].child[k] = -1 - static_cast<int>(faces[x.first]);
      return;
    }
    unsigned slots[4];
    int n = 0;
    for (unsigned c : {x.first, x.first + 1}) {
      if (bin[c].count > 0) {
        slots[n++] = c;
      } else {
        slots[n++] = bin[c].first;
        slots[n++] = bin[c].first + 1;
      }
    }
    const std::size_t made = out.size();
    out.push_back(emptyNode());
    out[node].child[k] = static_cast<int>(made);
    for (int j = 0; j < n; ++j) place(out, made, j, slots[j]);
  }

  static StaticNode emptyNode() {
    StaticNode e;
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 4; ++k) {
        e.lo[j][k] = std::numeric_limits<float>::infinity();
        e.hi[j][k] = -std::numeric_limits<float>::infinity();
      }
    for (int k = 0; k < 4; ++k) {
      e.size[k] = std::numeric_limits<float>::infinity();
      e.child[k] = 0;
    }
    return e;
  }
};

}  // namespace

void buildStaticTree(SceneData& s) {
  const std::size_t nf = s.F.size();
  // (references 4 node + child are 32-bit, and there are fewer nodes than faces)
  if (nf > (std::size_t{1} << 29))
    throw Error(ErrorCode::InvalidArgument, "a static scene holds at most 2^29 faces, got " + std::to_string(nf) +
                                                "; split it into several scenes");
  StaticBuilder b;
  b.lo.resize(3 * nf);
  b.hi.resize(3 * nf);
  b.centre.resize(3 * nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const Vec& p = s.V[s.F[f][0]];
    const Vec& q = s.V[s.F[f][1]];
    const Vec& r = s.V[s.F[f][2]];
    RTCBounds bb;
    storeBounds(&bb, p.cwiseMin(q).cwiseMin(r), p.cwiseMax(q).cwiseMax(r));
    const float l[3] = {bb.lower_x, bb.lower_y, bb.lower_z}, h[3] = {bb.upper_x, bb.upper_y, bb.upper_z};
    for (int k = 0; k < 3; ++k) {
      b.lo[3 * f + k] = l[k];
      b.hi[3 * f + k] = h[k];
      b.centre[3 * f + k] = 0.5f * (l[k] + h[k]);
    }
  }
  b.faces.resize(nf);
  std::iota(b.faces.begin(), b.faces.end(), 0u);
  b.bin.reserve(2 * nf);  // 2 nf - 1 nodes for leaves of one face
  b.bin.emplace_back();
  b.build(0, 0, static_cast<unsigned>(nf));
  s.tree.clear();
  s.tree.reserve(nf / 2 + 2);  // (the median splits make about nf / 3 nodes)
  s.tree.push_back(StaticBuilder::emptyNode());  // the root's box is child 0 of node 0
  b.place(s.tree, 0, 0, 0);
  s.tree.shrink_to_fit();
}

}  // namespace detail

// ---- the prepared mesh ---------------------------------------------------------------------------

namespace detail {
// A node of the moving mesh's hierarchy, in body coordinates: a box (centre c, half extents h,
// which contain the faces' vertices up to rounding: the search adds a relative margin), the
// children left and left + 1 (left < 0 for a leaf) and, for a leaf, its face.
struct BodyNode {
  Vec c, h;
  double hn = 0;  // |h|
  double chn = 0;  // |c| + |h|
  int left = -1;
  int face = -1;
};

// The prepared mesh's data (PreparedMesh::Impl adds nothing: it only names it for the header).
struct BodyTree {
  std::vector<Vec> V;
  Faces F;
  std::vector<BodyNode> nodes;  // root first
  double diag = 0;
  double mean_extent = 0;
  double vmax = 0;  // largest |vertex| (body coordinates)

  void build(std::size_t node, std::vector<unsigned>& order, const std::vector<Vec>& centre, std::size_t begin,
             std::size_t end) {
    Vec lo = Vec::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    Vec clo = lo, chi = hi;
    for (std::size_t i = begin; i < end; ++i) {
      const auto& f = F[order[i]];
      for (int k = 0; k < 3; ++k) {
        lo = lo.cwiseMin(V[f[k]]);
        hi = hi.cwiseMax(V[f[k]]);
      }
      clo = clo.cwiseMin(centre[order[i]]);
      chi = chi.cwiseMax(centre[order[i]]);
    }
    nodes[node].c = 0.5 * (lo + hi);
    nodes[node].h = (hi - nodes[node].c).cwiseMax(nodes[node].c - lo);
    nodes[node].hn = nodes[node].h.norm();
    nodes[node].chn = nodes[node].c.norm() + nodes[node].hn;
    if (end - begin == 1) {
      nodes[node].face = static_cast<int>(order[begin]);
      return;
    }
    int axis = 0;
    (chi - clo).maxCoeff(&axis);
    const std::size_t mid = begin + (end - begin) / 2;
    std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(begin), order.begin() + static_cast<std::ptrdiff_t>(mid),
                     order.begin() + static_cast<std::ptrdiff_t>(end),
                     [&](unsigned x, unsigned y) { return centre[x][axis] < centre[y][axis]; });
    const auto left = static_cast<int>(nodes.size());
    nodes[node].left = left;
    nodes.resize(nodes.size() + 2);
    build(static_cast<std::size_t>(left), order, centre, begin, mid);
    build(static_cast<std::size_t>(left) + 1, order, centre, mid, end);
  }
};
}  // namespace detail

struct PreparedMesh::Impl : detail::BodyTree {};

PreparedMesh::PreparedMesh(std::vector<Vec> vertices, Faces faces) : impl_(std::make_unique<Impl>()) {
  checkMesh(vertices, faces, "the moving");
  Impl& m = *impl_;
  m.V = std::move(vertices);
  m.F = std::move(faces);
  m.diag = boxDiagonal(m.V);
  m.mean_extent = meanFaceExtent(m.V, m.F);
  for (const Vec& p : m.V) m.vmax = std::max(m.vmax, p.norm());
  std::vector<Vec> centre(m.F.size());
  for (std::size_t f = 0; f < m.F.size(); ++f) centre[f] = (m.V[m.F[f][0]] + m.V[m.F[f][1]] + m.V[m.F[f][2]]) / 3.0;
  std::vector<unsigned> order(m.F.size());
  std::iota(order.begin(), order.end(), 0u);
  m.nodes.reserve(2 * m.F.size());
  m.nodes.emplace_back();
  m.build(0, order, centre, 0, m.F.size());
}

PreparedMesh::~PreparedMesh() = default;
PreparedMesh::PreparedMesh(PreparedMesh&&) noexcept = default;
PreparedMesh& PreparedMesh::operator=(PreparedMesh&&) noexcept = default;
const std::vector<Vec>& PreparedMesh::vertices() const { return impl_->V; }
const Faces& PreparedMesh::faces() const { return impl_->F; }

// ---- the search ------------------------------------------------------------------------------------

namespace {

using Clock = std::chrono::steady_clock;

enum class Mode { First, All, Any };

class TreeQuery {
 public:
  TreeQuery(const SceneData& st, const BodyTree& body, const Motion3& motion, const CollideOptions& o,
            Mode mode)
      : st_(st), body_(body), o_(o), mode_(mode) {
    if (o.slices < 1 || o.slices > 128)
      throw Error(ErrorCode::InvalidArgument, "CollideOptions::slices must be in 1..128, got " + std::to_string(o.slices));
    if (!(o.contact_tolerance >= 0) || !std::isfinite(o.contact_tolerance))
      throw Error(ErrorCode::InvalidArgument, "CollideOptions::contact_tolerance must be finite and >= 0");
    if (!(o.roots.time_tolerance > 0) || !(o.roots.value_ulps >= 1) || o.roots.max_intervals < 1)
      throw Error(ErrorCode::InvalidArgument,
                  "RootOptions: time_tolerance must be > 0, value_ulps >= 1, max_intervals >= 1");
    tol_ = o.contact_tolerance * std::max(st.diag, body.diag);
    margin_ = tol_ + 1e-12 * (st.diag + body.diag);
    feature_ = std::max(st.mean_extent, body.mean_extent);
    spans_.resize(motion.spanCount());
    for (std::size_t i = 0; i < spans_.size(); ++i) {
      SpanCtx& sc = spans_[i];
      sc.span = &motion.span(i);
      sc.t0 = motion.spanBegin(i);
      sc.t1 = motion.spanEnd(i);
      sc.M = sc.span->log().M;
      sc.u = sc.span->log().u;
      sc.mu = spectralBound(sc.M);
      sc.row = sc.M.rowwise().norm() * (1 + 1e-12);
    }
  }

  std::vector<Contact> run() {
    const auto start = Clock::now();
    for (Level& l : levels_) l.front.clear(), l.pool.clear();
    found_.clear(), work_.clear(), reached_.clear(), local_faces_.clear();
    levels_[0].front.assign(1, Entry{0, 0, 1});
    levels_[0].pool.assign(1, 0u);
    for (std::size_t i = 0; i < spans_.size() && !done_; ++i) interval(i, 0.0, 1.0, 0);
    std::vector<Contact> out;
    if (mode_ == Mode::All) {
      out = std::move(all_);
      mergeContactEvents(out);
    } else if (best_) {
      out.push_back(*best_);
    }
    stats.broad_seconds = std::chrono::duration<double>(Clock::now() - start).count() - stats.narrow_seconds;
    return out;
  }

  CollideStats stats;

 private:
  static constexpr unsigned kPowers = 16;
  struct SpanCtx {
    const Span3* span = nullptr;
    double t0 = 0, t1 = 1;
    Eigen::Matrix3d M;
    Vec u;
    double mu = 0;
    Vec row;  // |M_k|: norms of the rows of M (rounded up)
    std::unique_ptr<SpanRoots> fwd, inv;  // built on the span's first exact solve
    // A^m for the latest kPowers middles m of intervals, in a ring: the triangles that an
    // interval reaches are refined alone on the same halves, quarters, ... of it, one after
    // another, and find their powers here.
    std::array<std::uint64_t, kPowers> power_at{};  // the bits of m
    std::array<Affine3, kPowers> powers;
    unsigned power_count = 0;  // powers made so far
  };
  // The middle pose of span time [a, b]: A^m (Pm), the body-to-world pose (P = A^m start), |L| of
  // P entrywise, magnitudes for the rounding margin, and the factor that turns a speed at the
  // middle into a travel bound over the interval.
  struct Frame {
    Affine3 Pm, P;
    Eigen::Matrix3d Labs;
    double lnorm, tnorm, grow;
    double lscale;  // |L|_F / sqrt 3: the scale of P (exact for motions and uniform scalings)
    // Rounding margin of any vertex placed in this frame: kRound times bounds of |x| at the
    // middle and at span time 0 (from the largest body vertex).
    double round;
    double mag;  // a bound of the coordinates met in the separating-axis tests
    // Travel along axis k of a point at y (world, middle) over the interval: at most
    // r |v_k(y)| + |M_k| rxm |v(y)|, M_k the k-th row of M. Along the path
    // v(x(s)) = L^(s-m) v(y), and e_k . (L^t - 1) v = sum_(j>=1) t^j M_k . M^(j-1) v / j!, so
    // |e_k . (L^t - 1) v| <= |M_k| |v| (e^(|t| |M|) - 1) / |M|, whose integral over |t| <= r is
    // |M_k| |v| r^2 phi2(r |M|) = |M_k| |v| rxm. (An axis along which the motion is a pure
    // translation, M_k = 0, thus travels exactly r |v_k|. grow = r phi1(r |M|) bounds the whole
    // displacement.)
    double r, rxm;
    std::uint64_t id = 0;  // distinct per call of frame() on a thread (see VertexSlot)
  };
  // A moving node (index into body_.nodes) paired with static tree nodes pool[begin, end).
  struct Entry {
    unsigned node, begin, end;
  };
  // A conservative world box of what a moving node sweeps over an interval, with its size (the
  // largest side), its travel bound and its own radius.
  struct Swept {
    Vec lo, hi;
    Vec pad;  // per axis: how far any of its points travels along the axis (plus rounding)
    double size, path, rho;  // path = largest pad
    double mag = 0;  // (triangles) the frame's coordinate bound, for rounding margins
  };

  // Halving stops at this depth (2^-24 of a span).
  static constexpr int kMaxDepth = 24;
  // Rules of the search (measured on the benchmark scenes; any values keep the guarantee). An
  // inner moving node whose travel over an interval exceeds kNodeWait of its radius, or the
  // bounds of both its children (see waitBound), waits for the interval to be halved, otherwise
  // its children are tried; a triangle waits while its travel exceeds kLeafWait of max(its
  // radius, kLeafFloor typical triangle sizes), otherwise its static candidates are gathered and
  // it is refined alone (see local) until its travel is at most kLocal of max(its radius,
  // kLocalFloor typical triangle sizes), then solved.
  static constexpr double kNodeWait = 0.3;
  static constexpr double kLeafWait = 0.2;
  static constexpr double kLeafFloor = 0.5;
  static constexpr double kLocal = 0.1;
  static constexpr double kLocalFloor = 0.05;
  // Relative rounding margin of the posed boxes (positions, velocities and their norms are a few
  // dozen flops of the magnitudes |x|, |L| |c|, |t|, each rounded by 2^-53).
  static constexpr double kRound = 1e-13;

  Frame frame(SpanCtx& sc, double a, double b) {
    Frame f;
    const double r = 0.5 * (b - a);
    const double m = 0.5 * (a + b);
    std::uint64_t key;
    std::memcpy(&key, &m, sizeof key);
    const unsigned kept = std::min(sc.power_count, kPowers);
    unsigned k = 0;
    while (k < kept && sc.power_at[k] != key) ++k;
    if (k == kept) {
      k = sc.power_count++ % kPowers;
      sc.power_at[k] = key;
      sc.powers[k] = sc.span->power(m);
    }
    f.Pm = sc.powers[k];
    f.P = f.Pm * sc.span->start();
    f.Labs = f.P.linear().cwiseAbs();
    f.lnorm = f.P.linear().norm();
    f.tnorm = f.P.translation().norm();
    f.lscale = f.lnorm / std::sqrt(3.0);
    const Affine3& B = sc.span->start();
    const double xmid = f.tnorm + f.lnorm * body_.vmax;
    const double x0 = B.translation().norm() + B.linear().norm() * body_.vmax;
    f.round = kRound * (xmid + x0 + f.Pm.translation().norm() + f.Pm.linear().norm() * x0);
    f.mag = std::max(xmid, st_.lo.cwiseAbs().cwiseMax(st_.hi.cwiseAbs()).maxCoeff());
    const detail::Phis p = detail::phis(r * sc.mu);
    f.grow = r * p.p1 * kBoundSlack * (1 + 1e-12);
    f.r = r * kBoundSlack * (1 + 1e-12);
    f.rxm = r * r * p.p2 * kBoundSlack * (1 + 1e-12);
    f.id = ++scratch_.frames;
    return f;
  }

  // Swept box of an inner node: its body box posed at the middle is a parallelepiped inside the
  // world box cw +- |L| h, whose points y lie within rho = ||L| h| of cw. Since
  // v(y) - v(cw) = M (y - cw), |v_k(y)| <= |v_k(cw)| + |M_k| rho (M_k the k-th row) and
  // |v(y)| <= |v(cw)| + |M| rho; the travel bound of Frame applies to each axis.
  Swept nodeBox(const SpanCtx& sc, const Frame& f, const BodyNode& n, Vec& cw) const {
    cw = f.P.applyPoint(n.c);
    const Vec ext = f.Labs * n.h;
    const Vec vc = sc.M * cw + sc.u;
    Swept s;
    s.rho = ext.norm();
    const double round = margin_ + kRound * (cw.lpNorm<1>() + f.lnorm * n.chn + f.tnorm + s.rho);  // (|cw|_1 >= |cw|)
    s.pad = f.r * (vc.cwiseAbs() + sc.row * s.rho) + sc.row * ((vc.norm() + sc.mu * s.rho) * f.rxm) + Vec::Constant(round);
    s.path = s.pad.maxCoeff();
    s.lo = cw - ext - s.pad;
    s.hi = cw + ext + s.pad;
    s.size = (s.hi - s.lo).maxCoeff();
    return s;
  }

  // A leaf's triangle placed as the exact solves need it (vertices at the middle, each with its
  // travel bound plus rounding; the vertices at span time 0 are filled in by solve), and its
  // swept box.
  Swept triangleBox(const SpanCtx& sc, const Frame& f, unsigned node, MovingTriangle& t) const {
    const int face = body_.nodes[node].face;
    t.face = face;
    t.v = body_.F[static_cast<std::size_t>(face)];
    Swept s;
    s.lo = Vec::Constant(std::numeric_limits<double>::infinity());
    s.hi = -s.lo;
    s.pad = Vec::Zero();
    for (int k = 0; k < 3; ++k) {
      VertexSlot& slot = vertex_slots_[static_cast<unsigned>(t.v[k]) % kVertexSlots];
      if (slot.frame != f.id || slot.vertex != t.v[k]) {
        slot.frame = f.id;
        slot.vertex = t.v[k];
        slot.mid = f.P.applyPoint(body_.V[static_cast<std::size_t>(t.v[k])]);
        const Vec v = sc.M * slot.mid + sc.u;
        const double vn = v.norm(), round = f.round;
        slot.rad = vn * f.grow + round;
        // (each axis also within the whole displacement bound rad)
        slot.pad = (f.r * v.cwiseAbs() + sc.row * (vn * f.rxm) + Vec::Constant(round)).cwiseMin(slot.rad);
      }
      t.mid[k] = slot.mid;
      t.rad[k] = slot.rad;
      const Vec& pad = slot.pad;
      s.lo = s.lo.cwiseMin(t.mid[k] - pad);
      s.hi = s.hi.cwiseMax(t.mid[k] + pad);
      s.pad = s.pad.cwiseMax(pad);
    }
    s.path = s.pad.maxCoeff();
    s.lo -= Vec::Constant(margin_);
    s.hi += Vec::Constant(margin_);
    s.rho = body_.nodes[node].hn * f.lscale;
    s.mag = f.mag;
    s.size = (s.hi - s.lo).maxCoeff();
    return s;
  }

  // The travel over the interval above which moving node n (of radius rho when posed by f)
  // waits for the interval to be halved. A triangle waits while its travel exceeds kLeafWait of
  // max(rho, kLeafFloor typical triangle sizes); an inner node while it exceeds kNodeWait of
  // its radius, or while both its children would wait on that travel (their own travels are
  // about as large): descending would only put them in the queue of the halves one by one.
  double waitBound(const BodyNode& n, double rho, const Frame& f) const {
    if (n.left < 0) return kLeafWait * std::max(rho, kLeafFloor * feature_);
    double child = 0;
    for (int c = 0; c < 2; ++c) {
      const BodyNode& x = body_.nodes[static_cast<std::size_t>(n.left + c)];
      const double r = x.hn * f.lscale;
      child = std::max(child, x.left < 0 ? kLeafWait * std::max(r, kLeafFloor * feature_) : kNodeWait * r);
    }
    return std::min(kNodeWait * rho, child);
  }

  // A swept box rounded outward to float, to meet the static boxes (floats) in float compares:
  // a static box meets it whenever it meets the double box (rounding only adds near-ties).
  // Rounding to nearest moves x by at most 2^-24 |x| (or 2^-150 below float's normal range), so
  // x -+ (2^-22 |x| + 1e-38) rounds to a float on the far side of x.
  struct FloatBox {
    float lo[3], hi[3];
    float size;
  };
  static FloatBox floatBox(const Swept& s) {
    FloatBox b;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = static_cast<float>(s.lo[k] - (0x1p-22 * std::abs(s.lo[k]) + 1e-38));
      b.hi[k] = static_cast<float>(s.hi[k] + (0x1p-22 * std::abs(s.hi[k]) + 1e-38));
    }
    b.size = static_cast<float>(s.size);
    return b;
  }
  // The children of static node n whose boxes meet b, as bits (bit k: child k).
  static unsigned meets(const StaticNode& n, const FloatBox& b) {
#if defined(__SSE__) && !defined(STEADY_SCALAR_STATIC_TEST)
    __m128 ok = _mm_and_ps(_mm_cmple_ps(_mm_load_ps(n.lo[0]), _mm_set1_ps(b.hi[0])),
                           _mm_cmple_ps(_mm_load_ps(n.lo[1]), _mm_set1_ps(b.hi[1])));
    ok = _mm_and_ps(ok, _mm_cmple_ps(_mm_load_ps(n.lo[2]), _mm_set1_ps(b.hi[2])));
    ok = _mm_and_ps(ok, _mm_cmple_ps(_mm_set1_ps(b.lo[0]), _mm_load_ps(n.hi[0])));
    ok = _mm_and_ps(ok, _mm_cmple_ps(_mm_set1_ps(b.lo[1]), _mm_load_ps(n.hi[1])));
    ok = _mm_and_ps(ok, _mm_cmple_ps(_mm_set1_ps(b.lo[2]), _mm_load_ps(n.hi[2])));
    return static_cast<unsigned>(_mm_movemask_ps(ok));
#else
    unsigned m = 0;
    for (int k = 0; k < 4; ++k)
      m |= static_cast<unsigned>((n.lo[0][k] <= b.hi[0]) & (n.lo[1][k] <= b.hi[1]) & (n.lo[2][k] <= b.hi[2]) &
                                 (b.lo[0] <= n.hi[0][k]) & (b.lo[1] <= n.hi[1][k]) & (b.lo[2] <= n.hi[2][k]))
           << k;
    return m;
#endif
  }
  // The face of static reference r (4 node + slot), which names a face (a leaf child).
  unsigned refFace(unsigned r) const { return static_cast<unsigned>(-1 - st_.tree[r >> 2].child[r & 3]); }

  // What the plane test (planeApart) knows of a moving node beyond its swept box: an inner
  // node's body box posed at the middle (centre cw, P's linear part L, body half sides h), or a
  // leaf's triangle placed at the middle.
  struct Shape {
    const Eigen::Matrix3d* L = nullptr;
    Vec cw, h;
    const MovingTriangle* t = nullptr;
  };

  // Appends to pool the static references (see StaticNode) under pool[begin, end) whose boxes
  // meet s: faces, or nodes no larger than s (all the way to faces when to_leaves; otherwise the
  // faces met pass planeApart first, with the node's shape).
  void filterStatic(const Swept& s, const Shape& shape, double mag, unsigned begin, unsigned end, bool to_leaves,
                    std::vector<unsigned>& pool) const {
    const FloatBox fb = floatBox(s);
    // A depth-first walk: the stack holds at most three references a level plus one, and a tree
    // of at most 2^29 faces (median splits) has at most 15 levels of four children.
    unsigned stack[64];
    for (unsigned i = begin; i < end; ++i) {
      const unsigned r0 = pool[i];
      if (!((meets(st_.tree[r0 >> 2], fb) >> (r0 & 3)) & 1u)) continue;
      int top = 0;
      stack[top++] = r0;
      while (top > 0) {
        const unsigned r = stack[--top];
        const StaticNode& n = st_.tree[r >> 2];
        const unsigned k = r & 3;
        const int c = n.child[k];
        if (c < 0) {
          if (!to_leaves && planeApart(s, shape, static_cast<unsigned>(-1 - c), mag)) continue;
          pool.push_back(r);
        } else if (!to_leaves && n.size[k] <= fb.size) {
          pool.push_back(r);
        } else {
          const unsigned m = meets(st_.tree[static_cast<unsigned>(c)], fb);
          for (unsigned j = 0; j < 4; ++j)
            if ((m >> j) & 1u) stack[top++] = 4 * static_cast<unsigned>(c) + j;
        }
      }
    }
  }

  // The end of span time [a, b] left to search in span i: in a first-contact (or any) query,
  // the best contact so far in this span, when it is inside. A contact that comes before it
  // has a time no later, hence a span time no later (the global time t0 + s (t1 - t0) grows
  // with s), so the closed interval [a, best span time] holds every contact that can still
  // win; solve cuts the exact solves at the same span time.
  double capEnd(std::size_t i, double a, double b) const {
    if (mode_ == Mode::All || !best_ || best_->span != i || !(best_->span_time < b)) return b;
    return std::max(a, best_->span_time);
  }

  // The range of n . mid_k over the corners of moving triangle t (placed at the middle of an
  // interval), widened by grow on both sides: with grow >= |n|.pad, it holds the triangle's
  // projection over the whole interval (each corner stays within mid_k +- pad, and the
  // triangle's points are convex combinations of its corners).
  static void cornerRange(const MovingTriangle& t, const Vec& n, double grow, double& lo, double& hi) {
    const double a0 = n.dot(t.mid[0]), a1 = n.dot(t.mid[1]), a2 = n.dot(t.mid[2]);
    lo = std::min({a0, a1, a2}) - grow;
    hi = std::max({a0, a1, a2}) + grow;
  }

  // Whether static face g stays apart along its unit normal n from all that a moving node
  // (swept box s, shape) reaches over the interval: the face's projection onto n is the range
  // of its vertices' projections (kept with the scene), the node's one of
  // - an inner node: its posed body box cw + L [-h, h] moved by at most s.pad along each axis,
  //   n.cw +- (|L^T n|.h + |n|.s.pad) (the box's own extent along n, not that of its world box
  //   cw +- (|L| h + s.pad), which a turned box overstates: a cube turned 45 degrees about z,
  //   measured along the diagonal of x and y, spans h there against 2 h for its world box);
  // - a triangle: its vertices at the middle, each moved by at most s.pad along each axis, plus
  //   the contact distance (margin_, added to the box by triangleBox), the range of n.mid_k
  //   widened by |n|.(s.pad + margin_).
  // A gap along n means no contact there with the node or any node under it, on the interval or
  // any part of it (it is applied to the static leaves met by inner nodes and waiting triangles;
  // the face tests of candidate cover the rest). Rounding: cw, L^T n and the dot products are
  // within a few 2^-53 of magnitudes |cw| + |L| |h| and mag (mag bounds the static coordinates and
  // the moving vertices at the middle); a node's pad holds kRound of those on every axis (see
  // nodeBox), and the margin 1e-12 (mag + size) the rest.
  bool planeApart(const Swept& s, const Shape& shape, unsigned g, double mag) const {
    const Vec& nv = st_.normal[g];
    double lo, hi;
    if (shape.L) {
      const double pc = nv.dot(shape.cw);
      const double ph = (shape.L->transpose() * nv).cwiseAbs().dot(shape.h) + nv.cwiseAbs().dot(s.pad);
      lo = pc - ph;
      hi = pc + ph;
    } else {
      cornerRange(*shape.t, nv, nv.cwiseAbs().dot(s.pad + Vec::Constant(margin_)), lo, hi);
    }
    const double e = 1e-12 * (mag + s.size);
    return lo > st_.plane_range[g][1] + e || st_.plane_range[g][0] > hi + e;
  }

  // Whether moving triangle t (placed on the current interval, swept box s) stays apart from
  // static face g over the whole interval, by a separating axis. Each vertex stays within the
  // box mid +- s.pad of its middle position, and each point of the triangle is a convex
  // combination of its vertices, so over the interval the triangle stays inside its middle
  // triangle plus the box [-pad, pad]: along an axis n its projection stays within
  // [min n.mid - |n|.pad, max n.mid + |n|.pad] (|n| entrywise). The axes are the two normals
  // and the nine edge cross products (the separating axes of two triangles); an axis whose
  // projections are apart by more than that, the contact distance and a rounding margin
  // separates them. Axes of (nearly) parallel edges are skipped: no decision, no harm.
  bool separated(const MovingTriangle& t, const Swept& s, unsigned g) const {
    const auto& gf = st_.F[g];
    const Vec* q[3] = {&st_.V[gf[0]], &st_.V[gf[1]], &st_.V[gf[2]]};
    // Contact distance and rounding of the dot products (~1e-15 of |n| times the coordinates),
    // times |n|_1 >= |n|.
    const double extra = margin_ + 1e-12 * (s.mag + s.path);
    auto apart = [&](const Vec& n) {
      const Vec na = n.cwiseAbs();
      const double grow = na.dot(s.pad) + extra * (na.x() + na.y() + na.z());
      double amin, amax;
      cornerRange(t, n, grow, amin, amax);
      const double b0 = n.dot(*q[0]), b1 = n.dot(*q[1]), b2 = n.dot(*q[2]);
      const double bmin = std::min({b0, b1, b2}), bmax = std::max({b0, b1, b2});
      return amin > bmax || bmin > amax;
    };
    const Vec ea[3] = {t.mid[1] - t.mid[0], t.mid[2] - t.mid[1], t.mid[0] - t.mid[2]};
    const Vec eb[3] = {*q[1] - *q[0], *q[2] - *q[1], *q[0] - *q[2]};
    if (apart(st_.normal[g]) || apart(ea[0].cross(ea[1]))) return true;
    for (const Vec& x : ea)
      for (const Vec& y : eb) {
        const Vec n = x.cross(y);
        if (n.squaredNorm() > 1e-20 * x.squaredNorm() * y.squaredNorm() && apart(n)) return true;
      }
    return false;
  }

  double globalTime(const SpanCtx& sc, double s) const { return sc.t0 + s * (sc.t1 - sc.t0); }

  // Span time [a, b] of span i, with the moving nodes still paired with static nodes: the
  // entries levels_[depth].front, whose ranges index levels_[depth].pool. Both were filled by
  // the parent interval and are read, not changed, here (the sibling interval reads them next);
  // this interval appends its own scratch ranges to the pool and takes them off again before
  // returning, and fills levels_[depth + 1] for its halves. A triangle reached is refined and
  // solved at once (local); in a first-contact (or any) query, a contact found there cuts the
  // interval at its span time (capEnd), and the nodes still to come, and those that were to wait
  // for the halves, are placed on the part left: smaller swept boxes. (The pools and waiting
  // nodes gathered on the longer interval hold every static node that the shorter one can
  // meet. Taking the waiting nodes back: elephant screw 117 triangle and 227 node placements
  // instead of 132 and 234, 31 -> 29 us.)
  void interval(std::size_t i, double a, double b, int depth) {
    SpanCtx& sc = spans_[i];
    if (done_) return;
    if (mode_ != Mode::All && best_ && globalTime(sc, a) > best_->t) {
      done_ = true;  // every later interval starts later still
      return;
    }
    b = capEnd(i, a, b);
    Frame f = frame(sc, a, b);
    const auto d = static_cast<std::size_t>(depth);
    std::vector<unsigned>& pool = levels_[d].pool;
    const std::size_t pool_size = pool.size();
    std::vector<Entry>& work = work_;
    work.assign(levels_[d].front.rbegin(), levels_[d].front.rend());  // popped from the back: in front order
    std::vector<Entry>& wait = levels_[d + 1].front;
    std::vector<unsigned>& wait_pool = levels_[d + 1].pool;
    wait.clear();
    wait_pool.clear();
    const bool can_halve = depth < kMaxDepth;
    bool requeue = false;  // (a contact found cut the interval: see below)
    while (!work.empty()) {
      const Entry e = work.back();
      work.pop_back();
      const BodyNode& n = body_.nodes[e.node];
      MovingTriangle t;
      const bool leaf = n.left < 0;
      Shape shape;
      if (leaf) {
        shape.t = &t;
      } else {
        shape.L = &f.P.linear();
        shape.h = n.h;
      }
      const Swept s = leaf ? triangleBox(sc, f, e.node, t) : nodeBox(sc, f, n, shape.cw);
      const bool halve = can_halve && s.path > waitBound(n, s.rho, f);
      const auto mark = static_cast<unsigned>(pool.size());
      filterStatic(s, shape, f.mag, e.begin, e.end, leaf && !halve, pool);
      const auto stop = static_cast<unsigned>(pool.size());
      if (stop == mark) continue;
      if (halve) {
        const auto wb = static_cast<unsigned>(wait_pool.size());
        wait_pool.insert(wait_pool.end(), pool.begin() + mark, pool.end());
        wait.push_back({e.node, wb, static_cast<unsigned>(wait_pool.size())});
      } else if (!leaf) {
        work.push_back({static_cast<unsigned>(n.left) + 1, mark, stop});
        work.push_back({static_cast<unsigned>(n.left), mark, stop});
      } else {
        local_faces_.clear();
        for (unsigned k = mark; k < stop; ++k) {
          const unsigned g = refFace(pool[k]);  // (filtered to the leaves)
          if (candidate(t, s, g)) local_faces_.push_back(g);
        }
        if (!local_faces_.empty()) {
          reached_.assign(1, LocalItem{a, b, depth, e.node, t, s, 0, static_cast<unsigned>(local_faces_.size())});
          local(i, reached_);
          if (done_) break;
          const double cut = capEnd(i, a, b);
          if (cut < b) {
            b = cut;
            f = frame(sc, a, b);
            requeue = true;
          }
        }
      }
      if (halve || leaf) pool.resize(mark);  // (children of an inner node keep [mark, stop))
      if (requeue) {
        // The nodes that chose to wait did so on the longer interval, and on the part left they
        // may not need to: they rejoin the work list in front order, their static nodes copied
        // to the top of the pool (whose ranges for work entries stay until the interval ends).
        requeue = false;
        for (std::size_t k = wait.size(); k-- > 0;) {
          const auto from = static_cast<unsigned>(pool.size());
          pool.insert(pool.end(), wait_pool.begin() + wait[k].begin, wait_pool.begin() + wait[k].end);
          work.push_back({wait[k].node, from, static_cast<unsigned>(pool.size())});
        }
        wait.clear();
        wait_pool.clear();
      }
    }
    pool.resize(pool_size);
    if (wait.empty() || done_) return;
    const double m = 0.5 * (a + b);
    interval(i, a, m, depth + 1);
    interval(i, m, b, depth + 1);
  }

  // Whether static face g may meet moving triangle t (placed on the current interval, swept box
  // s): the boxes meet and no separating axis parts them.
  bool candidate(const MovingTriangle& t, const Swept& s, unsigned g) const {
    const auto& gf = st_.F[g];
    const Vec glo = st_.V[gf[0]].cwiseMin(st_.V[gf[1]]).cwiseMin(st_.V[gf[2]]);
    const Vec ghi = st_.V[gf[0]].cwiseMax(st_.V[gf[1]]).cwiseMax(st_.V[gf[2]]);
    if ((glo.array() > s.hi.array()).any() || (s.lo.array() > ghi.array()).any()) return false;
    return !separated(t, s, g);
  }

  // A moving triangle placed on span time [a, b] (swept box s) with the static faces that may
  // meet it there: local_faces_[begin, end).
  struct LocalItem {
    double a, b;
    int depth;
    unsigned node;
    MovingTriangle t;
    Swept s;
    unsigned begin, end;
  };
  // Scratch of one depth of the interval recursion (see interval).
  struct Level {
    std::vector<Entry> front;
    std::vector<unsigned> pool;
  };

  // A triangle an interval reached (the one item of heap), halved in time for itself alone,
  // earliest sub-interval first (a heap on a), while its travel exceeds kLocal of its radius (a
  // halving costs a placement and a separating-axis test per face, against about a microsecond
  // per exact pair solve), then solved exactly. In a first-contact query, the sub-intervals that
  // start after the earliest contact found are never refined nor solved.
  void local(std::size_t i, std::vector<LocalItem>& heap) {
    SpanCtx& sc = spans_[i];
    auto later = [](const LocalItem& x, const LocalItem& y) { return x.a > y.a; };
    std::make_heap(heap.begin(), heap.end(), later);
    while (!heap.empty() && !done_) {
      std::pop_heap(heap.begin(), heap.end(), later);
      LocalItem it = std::move(heap.back());
      heap.pop_back();
      if (mode_ != Mode::All && best_ && globalTime(sc, it.a) > best_->t) break;  // the rest start later
      // (its placement on the uncut interval stays valid on the part left)
      it.b = capEnd(i, it.a, it.b);
      if (it.depth >= kMaxDepth || it.s.path <= kLocal * std::max(it.s.rho, kLocalFloor * feature_)) {
        stats.candidate_pairs += it.end - it.begin;
        solve(i, it.a, it.b, it.t, it.begin, it.end);
        continue;
      }
      const double m = 0.5 * (it.a + it.b);
      for (int half = 0; half < 2; ++half) {
        LocalItem h;
        h.a = half ? m : it.a;
        h.b = half ? it.b : m;
        h.depth = it.depth + 1;
        h.node = it.node;
        const Frame f = frame(sc, h.a, h.b);
        h.s = triangleBox(sc, f, it.node, h.t);
        // (the halves' faces go to the end of local_faces_; the parent's range stays valid)
        h.begin = static_cast<unsigned>(local_faces_.size());
        for (unsigned k = it.begin; k < it.end; ++k)
          if (candidate(h.t, h.s, local_faces_[k])) local_faces_.push_back(local_faces_[k]);
        h.end = static_cast<unsigned>(local_faces_.size());
        if (h.end == h.begin) continue;
        heap.push_back(std::move(h));
        std::push_heap(heap.begin(), heap.end(), later);
      }
    }
    heap.clear();
    local_faces_.clear();
  }

  // Solves moving triangle `placed` against the static faces local_faces_[begin, end).
  void solve(std::size_t i, double a, double b, const MovingTriangle& placed, unsigned begin, unsigned end) {
    const auto start = Clock::now();
    SpanCtx& sc = spans_[i];
    if (!sc.fwd) {
      sc.fwd = std::make_unique<SpanRoots>(*sc.span, o_.roots, false);
      sc.inv = std::make_unique<SpanRoots>(inverseOf(*sc.span), o_.roots, false);
    }
    const PairSpan ps{i, sc.t0, sc.t1, sc.fwd.get(), sc.inv.get()};
    MovingTriangle t = placed;
    for (int k = 0; k < 3; ++k) t.W0[k] = sc.span->start().applyPoint(body_.V[static_cast<std::size_t>(t.v[k])]);
    for (unsigned k = begin; k < end; ++k) {
      const unsigned g = local_faces_[k];
      const double hi = mode_ != Mode::All && best_ && best_->span == i ? std::min(b, best_->span_time) : b;
      if (hi < a) continue;
      found_.clear();
      solveTrianglePair(st_, ps, t, g, a, hi, tol_, margin_, stats, found_);
      for (const Contact& c : found_) {
        if (mode_ == Mode::All) all_.push_back(c);
        else if (!best_ || contactBefore(c, *best_)) best_ = c;
      }
      if (mode_ == Mode::Any && best_) {
        done_ = true;
        break;
      }
    }
    stats.narrow_seconds += std::chrono::duration<double>(Clock::now() - start).count();
  }

  const SceneData& st_;
  const BodyTree& body_;
  const CollideOptions& o_;
  Mode mode_;
  double tol_ = 0, margin_ = 0, feature_ = 0;
  std::vector<SpanCtx> spans_;
  std::optional<Contact> best_;
  std::vector<Contact> all_;
  bool done_ = false;
  // Body vertices placed in one frame, shared by the triangles around them (which the search
  // tends to place on the same interval one after another): a direct-mapped table by vertex
  // number, each slot tagged with its vertex and frame, so a hit gives the same doubles.
  // (Frame numbers grow across the queries of a thread: a slot left by an earlier query never
  // matches.)
  struct VertexSlot {
    std::uint64_t frame = 0;
    int vertex = -1;
    Vec mid, pad;
    double rad = 0;
  };
  static constexpr unsigned kVertexSlots = 256;
  // The working memory of the queries of one thread, kept from query to query: a first contact
  // takes microseconds, and allocating these anew took several percent of it. Each query
  // empties what it reads before it reads it (run), so nothing carries over but capacity.
  struct Scratch {
    std::vector<Contact> found;
    std::vector<Level> levels = std::vector<Level>(kMaxDepth + 2);  // by depth (see interval)
    std::vector<Entry> work;
    std::vector<LocalItem> reached;      // the heap of local
    std::vector<unsigned> local_faces;  // the static faces of the LocalItems of one triangle (see local)
    std::vector<VertexSlot> vertex_slots = std::vector<VertexSlot>(kVertexSlots);
    std::uint64_t frames = 0;  // frames made so far (Frame::id)
  };
  static Scratch& threadScratch() {
    thread_local Scratch scratch;
    return scratch;
  }
  Scratch& scratch_ = threadScratch();
  std::vector<Contact>& found_ = scratch_.found;
  std::vector<Level>& levels_ = scratch_.levels;
  std::vector<Entry>& work_ = scratch_.work;
  std::vector<LocalItem>& reached_ = scratch_.reached;
  std::vector<unsigned>& local_faces_ = scratch_.local_faces;
  std::vector<VertexSlot>& vertex_slots_ = scratch_.vertex_slots;
};

}  // namespace

std::optional<Contact> StaticScene::firstContact(const PreparedMesh& mesh, const Motion3& motion,
                                                 const CollideOptions& options, CollideStats* stats) const {
  TreeQuery q(*impl_, *mesh.impl_, motion, options, Mode::First);
  std::vector<Contact> c = q.run();
  if (stats) *stats = q.stats;
  if (c.empty()) return std::nullopt;
  return c.front();
}

std::vector<Contact> StaticScene::contacts(const PreparedMesh& mesh, const Motion3& motion,
                                           const CollideOptions& options, CollideStats* stats) const {
  TreeQuery q(*impl_, *mesh.impl_, motion, options, Mode::All);
  std::vector<Contact> c = q.run();
  if (stats) *stats = q.stats;
  return c;
}

bool StaticScene::touches(const PreparedMesh& mesh, const Motion3& motion, const CollideOptions& options) const {
  TreeQuery q(*impl_, *mesh.impl_, motion, options, Mode::Any);
  return !q.run().empty();
}

}  // namespace steady
