// The inside test of a swept volume (see inside.hpp for the method, the tolerance and what is
// guaranteed): a static test at the motion start (distance to the posed surface, then ray
// parity with filtered orientation signs), then, span by span, the roots of the point/plane
// functions of the faces near the trajectory of the point seen from the body.
#include <steady/sweep/inside.hpp>

#include <steady/core/error.hpp>

#include "face_tree.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace steady::sweep {

namespace {

using Vec = Eigen::Vector3d;
using detail::FaceTree;
constexpr double kUlp = 0x1.0p-52;
constexpr double kInf = std::numeric_limits<double>::infinity();

// An upper bound of the spectral norm |A|_2 (eigen-solve of A^T A, inflated against its own
// rounding, capped by the Frobenius norm, which is always an upper bound).
double spectralBound(const Eigen::Matrix3d& A) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(A.transpose() * A, Eigen::EigenvaluesOnly);
  return std::min(A.norm(), std::sqrt(std::max(0.0, es.eigenvalues().maxCoeff())) * (1 + 1e-12) + 1e-300);
}

double segmentDistance(const Vec& p, const Vec& a, const Vec& b) {
  const Vec e = b - a;
  const double ee = e.squaredNorm();
  double t = ee > 0 ? (p - a).dot(e) / ee : 0.0;
  t = std::min(1.0, std::max(0.0, t));
  return (p - (a + t * e)).norm();
}

// Distance from p to the closed triangle (a, b, c): the distance to its plane when the foot
// of the perpendicular is inside (all three edge tests on the same side as the normal),
// otherwise the distance to the nearest edge.
double triangleDistance(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
  const Vec n = (b - a).cross(c - a);
  const double nn = n.squaredNorm();
  if (nn > 0) {
    const double off = n.dot(p - a);
    const Vec q = p - (off / nn) * n;
    if ((b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 && (a - c).cross(q - c).dot(n) >= 0)
      return std::abs(off) / std::sqrt(nn);
  }
  return std::min({segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)});
}

// Distance between the segments [p1, q1] and [p2, q2]: the smallest |p1 + s d1 - p2 - t d2|
// over the unit square of (s, t), at the stationary point of this convex quadratic when it
// lies inside the square (segments that are not parallel), else on one of the square's sides
// (an end of one segment against the other segment).
double segmentsDistance(const Vec& p1, const Vec& q1, const Vec& p2, const Vec& q2) {
  double best = std::min({segmentDistance(p1, p2, q2), segmentDistance(q1, p2, q2), segmentDistance(p2, p1, q1),
                          segmentDistance(q2, p1, q1)});
  const Vec d1 = q1 - p1, d2 = q2 - p2, w = p1 - p2;
  const double a = d1.squaredNorm(), b = d1.dot(d2), c = d2.squaredNorm(), d = d1.dot(w), e = d2.dot(w);
  const double det = a * c - b * b;
  if (det > 1e-12 * a * c) {
    const double s = (b * e - c * d) / det, t = (a * e - b * d) / det;
    if (s > 0 && s < 1 && t > 0 && t < 1) best = std::min(best, (w + s * d1 - t * d2).norm());
  }
  return best;
}

// Distance from the segment [p, q] to the closed triangle (a, b, c). A closest pair has an end
// of the segment, or an edge of the triangle, or (the segment piercing the triangle) the point
// where the segment meets the triangle's plane; a segment parallel to the plane and closest to
// its interior is as close at its ends.
double segmentTriangleDistance(const Vec& p, const Vec& q, const Vec& a, const Vec& b, const Vec& c) {
  double best = std::min({triangleDistance(p, a, b, c), triangleDistance(q, a, b, c), segmentsDistance(p, q, a, b),
                          segmentsDistance(p, q, b, c), segmentsDistance(p, q, c, a)});
  const Vec n = (b - a).cross(c - a);
  const double dp = n.dot(p - a), dq = n.dot(q - a);
  if ((dp <= 0 && dq >= 0) || (dp >= 0 && dq <= 0)) {
    const double s = dp == dq ? 0.0 : dp / (dp - dq);
    best = std::min(best, triangleDistance(p + s * (q - p), a, b, c));
  }
  return best;
}

// Sign of det[a - d, b - d, c - d], or 0 when its magnitude does not exceed the rounding bound
// of its evaluation (a static filter in the manner of Shewchuk's orient3d, with a factor 8 ulp
// of the permanent: about twice his bound). `bound` receives the bound.
int orient(const Vec& a, const Vec& b, const Vec& c, const Vec& d, double& bound) {
  const Vec p = a - d, q = b - d, r = c - d;
  const double m0 = q.y() * r.z() - q.z() * r.y();
  const double m1 = q.x() * r.z() - q.z() * r.x();
  const double m2 = q.x() * r.y() - q.y() * r.x();
  const double det = p.x() * m0 - p.y() * m1 + p.z() * m2;
  const double perm = std::abs(p.x()) * (std::abs(q.y() * r.z()) + std::abs(q.z() * r.y())) +
                      std::abs(p.y()) * (std::abs(q.x() * r.z()) + std::abs(q.z() * r.x())) +
                      std::abs(p.z()) * (std::abs(q.x() * r.y()) + std::abs(q.y() * r.x()));
  bound = 8 * kUlp * perm;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return 0;
}

// 32 fixed ray directions, spread over the sphere (a spherical Fibonacci set rotated off the
// coordinate axes and planes).
const std::array<Vec, 32>& rayDirections() {
  static const std::array<Vec, 32> dirs = [] {
    std::array<Vec, 32> d;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4123, Vec(0.31, 0.77, 0.56).normalized()).toRotationMatrix();
    for (int i = 0; i < 32; ++i) {
      const double z = 1.0 - (2.0 * i + 1.0) / 32.0;
      const double rho = std::sqrt(1.0 - z * z), phi = golden * i + 0.271;
      d[static_cast<std::size_t>(i)] = R * Vec(rho * std::cos(phi), rho * std::sin(phi), z);
    }
    return d;
  }();
  return dirs;
}

}  // namespace

struct SweptVolume::Impl {
  // The pose that takes world points back along the span to span time τ: A^-τ, and the norms
  // of its linear part and translation.
  struct BackPose {
    Affine3 pose;
    double lnorm = 0, tnorm = 0;
  };
  static BackPose backPose(const Span3& span, double tau) {
    BackPose b{span.power(-tau), 0.0, 0.0};
    b.lnorm = b.pose.linear().norm();
    b.tnorm = b.pose.translation().norm();
    return b;
  }
  // The time grid of SpanData::back: kGrid steps per span.
  static constexpr int kGrid = 1024;

  struct SpanData {
    explicit SpanData(SpanRoots r) : roots(std::move(r)) {}
    SpanRoots roots;
    double t0 = 0, t1 = 1;  // times reported for span time 0 and 1
    Eigen::Matrix3d M;
    Vec u;
    double mu = 0;         // >= |M|_2
    double grow_span = 0;  // e^mu
    // e^(r mu) for the half widths r = 2^j / (2 kGrid) of visit()'s intervals, by j (their
    // widths are powers of two times 1 / kGrid, exactly)
    std::array<double, 11> grow_half{};
    static_assert(kGrid == 1 << 10, "grow_half holds the half widths of a grid of 2^10 steps");
    Affine3 Binv;          // inverse start pose
    double binv_norm = 0;  // >= |L_B^-1|_2
    double b_norm = 0;     // >= |L_B|_2
    std::vector<Vec> W;    // body vertices posed by the start pose
    double w_max = 0;      // largest |W|
    std::vector<Vec> m;    // face planes m . z = h in the frame of the span start
    std::vector<double> h;
    std::vector<double> m_norm;  // |m|
    // Per face, per edge j (from corner j to j + 1): the unit normal s of the plane through the
    // edge perpendicular to the face, pointing away from the face, and s . (corner j); zero when
    // the face has no usable normal (then it never prunes). The face lies on the inner side of
    // all three planes, so a segment farther than r outside one of them is farther than r from
    // the face.
    std::vector<std::array<Eigen::Vector4d, 3>> sides;
    // A^-τ at τ = k / kGrid, k = 0 .. kGrid, with the norms `at` needs: every time visit()
    // evaluates is on this grid (intervals halve from [0, 1] while their half width exceeds
    // 2^-10 of the span, so their ends and middles are multiples of 2^-10).
    std::vector<BackPose> back;
  };

  struct Hit {
    double tau = kInf;
    int face = -1;
  };

  std::vector<Vec> P;                      // body vertices
  std::vector<std::array<int, 3>> F;       // body faces
  std::vector<SpanData> spans;
  FaceTree tree;
  Vec box_lo, box_hi;
  double diag = 0;    // body bounding-box diagonal (body coordinates)
  double delta = 0;   // δ, world units

  Impl(const Body& body, const InsideOptions& o) : P(body.vertices()), F(body.faces()) {
    if (o.tolerance) {
      if (!std::isfinite(*o.tolerance) || !(*o.tolerance > 0))
        throw Error(ErrorCode::InvalidArgument, "InsideOptions::tolerance must be finite and positive, got " +
                                                    std::to_string(*o.tolerance) + "; leave it unset to use relative_tolerance");
    } else if (!std::isfinite(o.relative_tolerance) || !(o.relative_tolerance > 0)) {
      throw Error(ErrorCode::InvalidArgument, "InsideOptions::relative_tolerance must be finite and positive, got " +
                                                  std::to_string(o.relative_tolerance) + " (the default is 1e-9)");
    }
    box_lo = body.box().lo;
    box_hi = body.box().hi;
    diag = body.box().diagonal();
    delta = o.tolerance ? *o.tolerance : o.relative_tolerance * diag;
    tree.build(P, F, 1, true);  // (the boxes kept: see FaceTree::build)
  }

  void addSpan(const Span3& span, double t0, double t1, const RootOptions& ro) {
    SpanData sd(SpanRoots(span, ro));
    sd.t0 = t0;
    sd.t1 = t1;
    sd.M = span.log().M;
    sd.u = span.log().u;
    sd.Binv = span.start().inverse();
    sd.back.reserve(kGrid + 1);
    for (int k = 0; k <= kGrid; ++k) sd.back.push_back(backPose(span, static_cast<double>(k) / kGrid));
    sd.mu = sd.roots.logNorm();
    sd.grow_span = std::exp(sd.mu);
    for (int j = 0; j < static_cast<int>(sd.grow_half.size()); ++j)
      sd.grow_half[static_cast<std::size_t>(j)] = std::exp(0.5 * (std::ldexp(1.0, j) / kGrid) * sd.mu);
    sd.binv_norm = spectralBound(sd.Binv.linear());
    sd.b_norm = spectralBound(span.start().linear());
    sd.W.resize(P.size());
    for (std::size_t i = 0; i < P.size(); ++i) {
      sd.W[i] = span.start().applyPoint(P[i]);
      sd.w_max = std::max(sd.w_max, sd.W[i].norm());
      if (!sd.W[i].allFinite())
        throw Error(ErrorCode::NonFinite, "SweptVolume: the body posed at the start of span " + std::to_string(spans.size()) +
                                              " overflows (vertex " + std::to_string(i) + "); scale the scene down");
    }
    sd.m.resize(F.size());
    sd.h.resize(F.size());
    sd.m_norm.resize(F.size());
    sd.sides.resize(F.size());
    for (std::size_t f = 0; f < F.size(); ++f) {
      const Vec& a = sd.W[F[f][0]];
      sd.m[f] = (sd.W[F[f][1]] - a).cross(sd.W[F[f][2]] - a);
      sd.h[f] = sd.m[f].dot(a);
      sd.m_norm[f] = sd.m[f].norm();
      for (int j = 0; j < 3; ++j) {
        const Vec& p = sd.W[F[f][j]];
        const Vec side = (sd.W[F[f][(j + 1) % 3]] - p).cross(sd.m[f]);
        const double len = side.norm();
        sd.sides[f][j] = len > 0 && std::isfinite(len) ? Eigen::Vector4d(side.x() / len, side.y() / len, side.z() / len,
                                                                         side.dot(p) / len)
                                                       : Eigen::Vector4d::Zero();
      }
      if (!sd.m[f].allFinite() || !std::isfinite(sd.h[f]))
        throw Error(ErrorCode::NonFinite, "SweptVolume: the plane of face " + std::to_string(f) + " at the start of span " +
                                              std::to_string(spans.size()) + " overflows; scale the scene down");
    }
    spans.push_back(std::move(sd));
  }

  // --- static test at the start of the motion ------------------------------------------------

  bool nearSurfaceAtStart(const Vec& x, const Vec& y) const {
    const SpanData& sd = spans.front();
    const double rho = delta * sd.binv_norm * (1 + 1e-9) + 64 * kUlp * (y.norm() + diag);
    bool near = false;
    tree.overlapping(y - Vec::Constant(rho), y + Vec::Constant(rho), [&](int f) {
      if (!near && triangleDistance(x, sd.W[F[f][0]], sd.W[F[f][1]], sd.W[F[f][2]]) <= delta) near = true;
    });
    return near;
  }

  // Ray parity of the body point y (body coordinates), known to be farther than δ_b from the
  // surface. Returns 1 inside, 0 outside, -1 when every direction was ambiguous.
  int parity(const Vec& y, double delta_b) const {
    const Vec centre = 0.5 * (box_lo + box_hi);
    const double reach = 2 * ((y - centre).norm() + diag) + 1;
    const double pad = 1e-9 * diag + 64 * kUlp * (y.norm() + reach);
    for (const Vec& dir : rayDirections()) {
      const Vec q = y + reach * dir;
      const Vec dq = q - y;
      const double dqn = dq.norm();
      int crossings = 0;
      bool ambiguous = false;
      tree.alongSegment(y, q, pad, [&](int f) {
        if (ambiguous) return;
        const Vec& a = P[F[f][0]];
        const Vec& b = P[F[f][1]];
        const Vec& c = P[F[f][2]];
        double by = 0, bq = 0, be = 0;
        const int sy = orient(a, b, c, y, by), sq = orient(a, b, c, q, bq);
        if (sq == 0) {
          ambiguous = true;
          return;
        }
        if (sy == 0) {
          // y is within rounding of the triangle's plane; the segment meets the plane within
          // 2 by / (|n| |cos|) of y, which is farther than δ_b from the triangle: no crossing
          // when that radius is below δ_b / 2 (the segment is transversal enough).
          const Vec n = (b - a).cross(c - a);
          const double cosine = std::abs(n.dot(dq)) / (n.norm() * dqn);
          if (2 * by <= 0.5 * delta_b * n.norm() * cosine) return;
          ambiguous = true;
          return;
        }
        if (sy == sq) return;
        const int e0 = orient(y, q, a, b, be), e1 = orient(y, q, b, c, be), e2 = orient(y, q, c, a, be);
        // Two certain signs that differ: the line passes outside the triangle.
        if ((e0 != 0 && e1 != 0 && e0 != e1) || (e1 != 0 && e2 != 0 && e1 != e2) || (e0 != 0 && e2 != 0 && e0 != e2)) return;
        if (e0 == 0 || e1 == 0 || e2 == 0) {
          ambiguous = true;
          return;
        }
        ++crossings;
      });
      if (!ambiguous) return crossings & 1;
    }
    return -1;
  }

  // Generalized winding number of the body surface about y (body coordinates): the sum of the
  // signed solid angles of the faces (Van Oosterom and Strackee) over 4 pi.
  double winding(const Vec& y) const {
    double total = 0;
    for (const auto& f : F) {
      const Vec a = P[f[0]] - y, b = P[f[1]] - y, c = P[f[2]] - y;
      const double la = a.norm(), lb = b.norm(), lc = c.norm();
      const double num = a.dot(b.cross(c));
      const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
      total += 2 * std::atan2(num, den);
    }
    return total / (4 * M_PI);
  }

  bool containsAtStart(const Vec& x) const {
    const SpanData& sd = spans.front();
    const Vec y = sd.Binv.applyPoint(x);
    if (!y.allFinite()) throw Error(ErrorCode::NonFinite, "SweptVolume: the point in body coordinates overflows");
    // Far outside the (δ-inflated) body box: outside.
    const double rho = delta * sd.binv_norm * (1 + 1e-9) + 64 * kUlp * (y.norm() + diag);
    if ((y.array() < box_lo.array() - rho).any() || (y.array() > box_hi.array() + rho).any()) return false;
    if (nearSurfaceAtStart(x, y)) return true;
    // Farther than δ (world) from the surface, so farther than δ / |L_B|_2 in body coordinates.
    const int p = parity(y, delta / sd.b_norm);
    if (p >= 0) return p == 1;
    return std::abs(winding(y)) >= 0.5;
  }

  // --- static tests at a time (hints) --------------------------------------------------------

  // Whether x lies strictly inside the body posed at span time tau: its body point y, computed
  // through the span's power at -tau, lies farther than a margin plus its error from every face
  // and inside by ray parity. The error bound (1e-12 of the magnitudes involved) covers the
  // rounding of y and the error of the computed power (about 1e-14, see the core's accuracy),
  // so the true point at tau is inside too. False means "not shown", never "outside".
  bool insideAt(const SpanData& sd, double tau, const Vec& x) const {
    const Affine3 back = sd.roots.span().power(-tau);
    const Vec y = sd.Binv.applyPoint(back.applyPoint(x));
    if (!y.allFinite()) return false;
    const double err =
        1e-12 * (y.norm() + diag + sd.binv_norm * (back.linear().norm() * x.norm() + back.translation().norm()));
    if ((y.array() < box_lo.array() - err).any() || (y.array() > box_hi.array() + err).any()) return false;
    const double margin = std::max(delta * sd.binv_norm, err), rho = margin + err;
    bool near = false;
    tree.overlappingUntil(y - Vec::Constant(rho), y + Vec::Constant(rho), [&](int f) {
      near = triangleDistance(y, P[F[f][0]], P[F[f][1]], P[F[f][2]]) <= rho;
      return !near;
    });
    return !near && parity(y, 0.5 * margin) == 1;  // (half: the distances above are rounded)
  }

  // The hint's scan (see SweptVolume::hint): from the time query() found, steps of kHintStep
  // until a static test shows x inside (at most kHintSteps of them), then steps doubling from
  // there while it stays inside (at most kHintSteps steps away); the hint is the middle of the
  // run found. (A linear scan of the whole run would take up to 256 static tests; this takes
  // about ten.)
  static constexpr double kHintStep = 0x1.0p-16;
  static constexpr int kHintSteps = 256;

  std::optional<InsideHint> hint(const Vec& x) const {
    const InsideResult r = query(x);
    if (!r.inside) return std::nullopt;
    const SpanData& sd = spans[r.span];
    const double from = r.face < 0 ? 0.0 : std::min(1.0, std::max(0.0, (r.time - sd.t0) / (sd.t1 - sd.t0)));
    double first = -1;
    for (int k = r.face < 0 ? 0 : 1; k <= kHintSteps && first < 0; ++k) {
      const double tau = from + k * kHintStep;
      if (tau > 1) break;
      if (insideAt(sd, tau, x)) first = tau;
    }
    if (first < 0) return std::nullopt;
    double last = first;
    for (int k = 1; k <= kHintSteps; k *= 2) {
      const double tau = first + k * kHintStep;
      if (tau > 1 || !insideAt(sd, tau, x)) break;
      last = tau;
    }
    return InsideHint{r.span, 0.5 * (first + last)};
  }

  // --- crossings along a span ----------------------------------------------------------------

  // World distance from x to face f posed at span time tau, and the largest speed of its corners.
  double faceDistance(const SpanData& sd, int f, double tau, const Vec& x, double& speed) const {
    const Affine3 A = sd.roots.span().power(tau);
    const Vec a = A.applyPoint(sd.W[F[f][0]]), b = A.applyPoint(sd.W[F[f][1]]), c = A.applyPoint(sd.W[F[f][2]]);
    speed = std::max({(sd.M * a + sd.u).norm(), (sd.M * b + sd.u).norm(), (sd.M * c + sd.u).norm()});
    const double d = triangleDistance(x, a, b, c);
    return std::isfinite(d) ? d : kInf;
  }

  // Records tau as a hit on face f when earlier than the current one.
  static void record(Hit& hit, double tau, int f) {
    if (tau < hit.tau) {
      hit.tau = tau;
      hit.face = f;
    }
  }

  // Checks a root of face f's plane function (span times s = -tau), or, when the root is a
  // wide band, the band's ends and the crossings of the planes through the face's edges.
  // `edges` is false for the recursive calls on those planes (which check the same face).
  void checkRoot(const SpanData& sd, int f, const ContactRoot& r, const Vec& x, Hit& hit, bool edges) const {
    const double tlo = std::max(0.0, -r.hi), thi = std::min(1.0, -r.lo);
    const double tt = std::min(thi, std::max(tlo, -r.t));
    const double width = thi - tlo;
    double speed = 0;
    const double d = faceDistance(sd, f, tt, x, speed);
    const double slack = width * std::exp(sd.mu * width) * speed * (1 + 1e-12);
    if (slack <= delta) {
      if (d <= delta + slack) record(hit, tt, f);
      return;
    }
    // A wide bracket: the point slides in (or grazes) the plane over [tlo, thi].
    double unused = 0;
    for (const double tau : {tlo, tt, thi}) {
      if (tau >= hit.tau) break;
      if ((tau == tt ? d : faceDistance(sd, f, tau, x, unused)) <= delta) {
        record(hit, tau, f);
        break;
      }
    }
    if (!edges || tlo >= hit.tau) return;
    const Vec& n = sd.m[f];
    for (int j = 0; j < 3; ++j) {
      const Vec& p = sd.W[F[f][j]];
      const Vec& q = sd.W[F[f][(j + 1) % 3]];
      const Vec me = n.cross(q - p);
      if (!(me.norm() > 0)) continue;
      std::vector<ContactRoot> sub;
      sd.roots.pointPlane(x, me, me.dot(p), -std::min(thi, hit.tau), -tlo, sub);
      for (const ContactRoot& r2 : sub) checkRoot(sd, f, r2, x, hit, false);
    }
  }

  // A point of the trajectory z, computed, with a bound of its rounding.
  struct TrajectoryPoint {
    Vec z;
    double round = 0;
  };
  // At span time k / kGrid (0 <= k <= kGrid).
  TrajectoryPoint at(const SpanData& sd, const Vec& x, int k) const {
    const BackPose& back = sd.back[static_cast<std::size_t>(k)];
    TrajectoryPoint t{back.pose.applyPoint(x), 0.0};
    if (!t.z.allFinite()) throw Error(ErrorCode::NonFinite, "SweptVolume: the point's trajectory overflows");
    t.round = 64 * kUlp * (t.z.norm() + back.lnorm * x.norm() + back.tnorm);
    return t;
  }

  // The earliest hit over span times [a, b], whose ends the trajectory passes at za and zb,
  // halving while the faces in reach of its chord are many. Returns true when a hit was found
  // (hits in [a, b] are earlier than in (b, 1]).
  bool visit(const SpanData& sd, const Vec& x, int ka, int kb, const TrajectoryPoint& za,
             const TrajectoryPoint& zb, Hit& hit, std::vector<int>& cand, std::vector<ContactRoot>& roots) const {
    const int kc = (ka + kb) / 2;  // (ka and kb differ by an even number: see can_halve)
    const double a = static_cast<double>(ka) / kGrid, b = static_cast<double>(kb) / kGrid;
    const double r = 0.5 * (b - a);
    const TrajectoryPoint zc = at(sd, x, kc);
    const double speed = (sd.M * zc.z + sd.u).norm();
    // Over [a, b] the trajectory stays within `chord` of the chord [z(a), z(b)]: linear
    // interpolation over a step h = 2r errs by at most h²/8 max|z''|, and z'' = M v(z) with
    // |v(z(τ))| <= e^(|τ - c|μ) |v(z(c))| (v(z(τ)) = L^(c - τ) v(z(c))). Every face that can hit
    // lies within e^μ (δ + η) <= 2 δ e^μ of z(τ) (frame of the span start), so within `reach`
    // of the computed chord (whose ends are off by their rounding).
    // (e^(r mu); kb - ka is 2^j)
    const double grow = sd.grow_half[static_cast<std::size_t>(__builtin_ctz(static_cast<unsigned>(kb - ka)))];
    const double chord = 0.5 * r * r * sd.mu * grow * (speed + sd.mu * zc.round) * (1 + 1e-12);
    const double reach = chord + std::max(za.round, zb.round) + 2 * delta * sd.grow_span * (1 + 1e-9);
    const Vec ya = sd.Binv.applyPoint(za.z), yb = sd.Binv.applyPoint(zb.z);
    const double ry = reach * sd.binv_norm * (1 + 1e-12) + 64 * kUlp * (std::max(ya.norm(), yb.norm()) + diag);
    // More than 8 faces in reach halve the interval (down to 2^-10 of the span): the search for
    // candidates stops at the 9th then, so that the wide reach of the first intervals does not
    // list most of the body. (8 rather than 16: the output stage 14% faster on the elephant
    // screw and 9% on bunny00's at 1e-2 eps, now that the distance to the chord rather than
    // the roots is most of a candidate's cost; 4 was slower on the elephant.)
    const bool can_halve = r > 1.0 / 1024;
    bool many = false;
    cand.clear();
    tree.overlappingUntil(ya.cwiseMin(yb) - Vec::Constant(ry), ya.cwiseMax(yb) + Vec::Constant(ry), [&](int f) {
      cand.push_back(f);
      many = can_halve && cand.size() > 8;
      return !many;
    });
    if (cand.empty()) return false;
    if (many) {
      if (visit(sd, x, ka, kc, za, zc, hit, cand, roots)) return true;
      return visit(sd, x, kc, kb, zc, zb, hit, cand, roots);
    }
    // A face farther than `reach` from the chord cannot hit in [a, b] (its box only met the
    // chord's box): its distance, computed in doubles, is trusted to 1e-9 of the magnitudes
    // involved.
    const double far = reach + 1e-9 * (reach + std::max(za.z.norm(), zb.z.norm()) + sd.w_max);
    for (const int f : cand) {
      // (first the distance to the face's plane, a lower bound: most faces are pruned by it)
      const Vec &w0 = sd.W[F[f][0]], &w1 = sd.W[F[f][1]], &w2 = sd.W[F[f][2]];
      const double plane_far = far * sd.m_norm[f];
      const double dpa = sd.m[f].dot(za.z - w0), dpb = sd.m[f].dot(zb.z - w0);
      if ((dpa > plane_far && dpb > plane_far) || (dpa < -plane_far && dpb < -plane_far)) continue;
      // (then the planes through its edges, see SpanData::sides: a third fewer distances
      // computed, BM_SweptContains/elephant/screw/boundary 12% faster; their rounding, a few
      // ulps of the magnitudes, lies far inside the 1e-9 of `far`)
      bool beside = false;
      for (const Eigen::Vector4d& e : sd.sides[static_cast<std::size_t>(f)]) {
        const Vec s = e.head<3>();
        if (s.dot(za.z) - e[3] > far && s.dot(zb.z) - e[3] > far) {
          beside = true;
          break;
        }
      }
      if (beside) continue;
      if (segmentTriangleDistance(za.z, zb.z, w0, w1, w2) > far) continue;
      roots.clear();
      sd.roots.pointPlane(x, sd.m[f], sd.h[f], -std::min(b, hit.tau), -a, roots);
      // Roots come in increasing s, i.e. decreasing tau: check the earliest times first.
      for (auto it = roots.rbegin(); it != roots.rend(); ++it) {
        if (-it->hi >= hit.tau) break;
        checkRoot(sd, f, *it, x, hit, true);
      }
    }
    return hit.face >= 0;
  }

  InsideResult query(const Vec& x) const {
    if (!x.allFinite()) throw Error(ErrorCode::NonFinite, "SweptVolume: the query point has a NaN or infinite coordinate");
    InsideResult res;
    if (containsAtStart(x)) {
      res.inside = true;
      res.time = spans.front().t0;
      res.span = 0;
      res.face = -1;
      return res;
    }
    std::vector<int> cand;
    std::vector<ContactRoot> roots;
    for (std::size_t i = 0; i < spans.size(); ++i) {
      const SpanData& sd = spans[i];
      Hit hit;
      if (visit(sd, x, 0, kGrid, at(sd, x, 0), at(sd, x, kGrid), hit, cand, roots)) {
        res.inside = true;
        res.time = sd.t0 + hit.tau * (sd.t1 - sd.t0);
        res.span = i;
        res.face = hit.face;
        return res;
      }
    }
    return res;
  }
};

SweptVolume::SweptVolume(const Body& body, const Motion3& motion, const InsideOptions& options)
    : impl_(std::make_unique<Impl>(body, options)) {
  impl_->spans.reserve(motion.spanCount());
  for (std::size_t i = 0; i < motion.spanCount(); ++i)
    impl_->addSpan(motion.span(i), motion.spanBegin(i), motion.spanEnd(i), options.roots);
}

SweptVolume::SweptVolume(const Body& body, const Span3& span, const InsideOptions& options)
    : impl_(std::make_unique<Impl>(body, options)) {
  impl_->addSpan(span, 0.0, 1.0, options.roots);
}

SweptVolume::~SweptVolume() = default;
SweptVolume::SweptVolume(SweptVolume&&) noexcept = default;
SweptVolume& SweptVolume::operator=(SweptVolume&&) noexcept = default;

bool SweptVolume::contains(const Eigen::Vector3d& x) const { return impl_->query(x).inside; }

InsideResult SweptVolume::query(const Eigen::Vector3d& x) const { return impl_->query(x); }

std::optional<InsideHint> SweptVolume::hint(const Eigen::Vector3d& x) const { return impl_->hint(x); }

bool SweptVolume::contains(const Eigen::Vector3d& y, const InsideHint& hint) const {
  if (!y.allFinite()) throw Error(ErrorCode::NonFinite, "SweptVolume: the query point has a NaN or infinite coordinate");
  if (hint.span < impl_->spans.size() && hint.tau >= 0 && hint.tau <= 1 &&
      impl_->insideAt(impl_->spans[hint.span], hint.tau, y))
    return true;
  return impl_->query(y).inside;
}

bool SweptVolume::containsAtStart(const Eigen::Vector3d& x) const {
  if (!x.allFinite()) throw Error(ErrorCode::NonFinite, "SweptVolume: the query point has a NaN or infinite coordinate");
  return impl_->containsAtStart(x);
}

double SweptVolume::tolerance() const { return impl_->delta; }

std::size_t SweptVolume::spanCount() const { return impl_->spans.size(); }

bool sweptContains(const Body& body, const Motion3& motion, const Eigen::Vector3d& x, const InsideOptions& options) {
  return SweptVolume(body, motion, options).contains(x);
}

bool sweptContains(const Body& body, const Span3& span, const Eigen::Vector3d& x, const InsideOptions& options) {
  return SweptVolume(body, span, options).contains(x);
}

}  // namespace steady::sweep
