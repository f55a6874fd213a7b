// The Extraction of Affinity Roots: closed-form real logarithms and powers of 2D and 3D
// affinities. See ../../shared/notes/ear-math.md (§1-§3) for the mathematics.
//
// Outline of log([L | t]):
//  1. Screen non-finite input and det L <= 0.
//  2. 2D: the block kernel logBlock2 gives log L = alpha 1 + beta N (N = L - r 1, N^2 = d 1).
//     3D: eigenvalues of L from the depressed cubic of E = L - 1 (working with E keeps full
//     relative accuracy near the identity); only its root of largest magnitude is solved for
//     (kernels.cpp, dominantCubicRoot). If the three eigenvalues agree within 2%, the log is
//     the series of log(1 + N) around their mean (TripleEigenvalue). Otherwise a simple positive
//     eigenvalue mu is split off with its right/left eigenvectors: L = mu P + W L2 W^T Pi, and
//     the remaining 2D block L2 goes to logBlock2.
//  3. Translation: u = phi(M)^-1 t with phi(X) = (e^X - 1) X^-1, evaluated on the same spectral
//     form. This never divides by det(1 - L), so eigenvalue 1 (screws, shears, translations)
//     needs no special case.
// Powers A^s = exp(s [M | u]) reuse the spectral form (class Span).

#include <steady/core/ear.hpp>

#include "kernels.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace steady {

namespace {

using detail::BlockCoefficients;
using detail::CoshSinhc;

constexpr double kPi = 3.14159265358979323846;
// Relative eigenvalue spread below which the 3D logarithm uses the series about the mean
// eigenvalue (where splitting off an eigenvector would be ill-conditioned).
constexpr double kTripleSpread = 0.02;
// Largest relative spread for which the series form is used on strongly non-normal matrices.
constexpr double kSeriesSpreadMax = 0.25;
// Hadamard ratio at or below which L counts as singular (same threshold as Affine::inverse).
constexpr double kSingularRatio = 1e-14;
// The range of affinities the closed forms take: every column of L, and t, at most kRange long
// (else InvalidArgument), every column of L at least 1 / kRange long (else Singular: the pose
// flattens the body by more than 1e30). The eigenvalue formulas raise
// entries to the sixth power (the cubic's discriminant), which stays inside the double range
// for |entries| <= 1e30 (the squared column norms of the singularity test as well). Beyond it
// an intermediate overflowed or underflowed: diag(6e129, 1, 1) came out as a NaN logarithm
// labelled "triple eigenvalue", and 1e300 I as "singular" (found by tests/fuzz/fuzz_ear.cpp).
constexpr double kRange = 1e30;
// Largest ratio of the moduli of L's eigenvalues the closed forms take. The translation part of
// the log is a sum over the eigenvalues' parts, and loses about log10 of this ratio in digits
// (diag(1e8, 1) with t = (1, 1): u relative error 1.3e-10; 1e12: 5e-7; 1e16: 1e-2). Beyond
// 1e8 the answer would be wrong without saying so, hence an error instead.
constexpr double kMaxStretchRatio = 1e8;
// Smallest modulus of an eigenvalue of L the closed forms take. They work with the offsets
// E = L - 1, whose rounding costs about u / |lambda| relative in a small eigenvalue lambda: a
// rotation scaled by k has its log within 1.4e-13 at k = 1e-3, 1.7e-10 at 1e-6 and 1.7e-8 at
// 1e-8 (3D; 2D about ten times better). Below 1e-6, an error instead.
constexpr double kMinModulus = 1e-6;
constexpr double kSeriesTiny = 0x1.0p-56;
// Largest |t| rho (rho: spectral radius bound of the log's nilpotent-like part Z) for which a
// span in series form sums its series directly (then at most about 30 terms).
constexpr double kSeriesReach = 4.0;
// Largest Frobenius condition number of the log's 2D block for which a span evaluates the
// translation as (e^{tM} - 1) M^-1 u (cheaper; error grows with this condition number).
// 8 keeps the random-set round trip below 2.5e-15 (4: same; 16: 6e-15) and lets about two thirds
// of random spans skip phi at evaluation time.
constexpr double kViaInverseCondition = 8.0;

// Whether the log block X = alpha 1 + N (N^2 = eta 1, |N|_F^2 = nfrob2) has a Frobenius condition
// number below kViaInverseCondition: then phi(X)^-1 = X (e^X - 1)^-1 and (e^{tX} - 1) X^-1 can be
// used directly.
bool wellConditionedBlock(double alpha, double eta, double nfrob2) {
  const double det = alpha * alpha - eta;
  return 2.0 * alpha * alpha + nfrob2 < kViaInverseCondition * std::abs(det) && std::abs(det) > 1e-280;
}

struct Failure {
  ErrorCode code = ErrorCode::InvalidArgument;
  std::string message;
};

std::string fmt(double x) {
  std::ostringstream os;
  os.precision(6);
  os << x;
  return os.str();
}

template <int D>
bool screen(const Affine<D>& A, Failure& fail) {
  // x - x is 0 for a finite x and NaN otherwise, so the sum is NaN exactly when some entry is
  // not finite: one test instead of one per entry (the same answer as Affine::isFinite).
  const double zeros = (A.linear() - A.linear()).sum() + (A.translation() - A.translation()).sum();
  if (std::isnan(zeros)) {
    fail = {ErrorCode::NonFinite,
            "the affinity has NaN or infinite entries; check how the pose was computed or parsed"};
    return false;
  }
  const auto& L = A.linear();
  // Squared lengths of L's columns and of t: the range, then the Hadamard ratio.
  double lo2 = HUGE_VAL, hi2 = A.translation().squaredNorm(), prod2 = 1.0;
  for (int j = 0; j < D; ++j) {
    const double c2 = L.col(j).squaredNorm();
    lo2 = std::min(lo2, c2);
    hi2 = std::max(hi2, c2);
    prod2 *= c2;
  }
  if (!(hi2 <= kRange * kRange)) {
    fail = {ErrorCode::InvalidArgument,
            "the affinity has a column of length " + fmt(std::sqrt(hi2)) +
                ", beyond the 1e30 that steady's logarithm handles: express the poses in other units"};
    return false;
  }
  if (!(lo2 >= 1 / (kRange * kRange))) {
    fail = {ErrorCode::Singular,
            "the linear part is singular (a column of L is " + fmt(std::sqrt(lo2)) +
                " long, below 1e-30): it flattens the body, so no logarithm and no SAM exist; check "
                "the pose for a zero column or for units that make it tiny"};
    return false;
  }
  const double det = L.determinant();
  if (!(prod2 > 0) || det * det <= kSingularRatio * kSingularRatio * prod2) {
    fail = {ErrorCode::Singular,
            "the linear part is singular (det L = " + fmt(det) +
                "): it flattens the body, so no logarithm and no SAM exist; check the pose for a "
                "zero or repeated column"};
    return false;
  }
  if (det < 0) {
    fail = {ErrorCode::NotOrientationPreserving,
            "det L = " + fmt(det) +
                " < 0: the motion would have to mirror the body, which no continuous motion does "
                "(no real logarithm); check the handedness of both poses"};
    return false;
  }
  return true;
}

// Whether the eigenvalues 1 + re_k + i im_k (k < n) of L have moduli of at least kMinModulus
// and within kMaxStretchRatio of each other; fails with InvalidArgument otherwise.
bool eigenvaluesInRange(const double* re, const double* im, int n, Failure& fail) {
  double lo = HUGE_VAL, hi = 0;  // squared moduli (at most about 1e61 within kRange)
  for (int k = 0; k < n; ++k) {
    const double m2 = (1.0 + re[k]) * (1.0 + re[k]) + im[k] * im[k];
    lo = std::min(lo, m2);
    hi = std::max(hi, m2);
  }
  if (lo >= kMinModulus * kMinModulus && hi <= kMaxStretchRatio * kMaxStretchRatio * lo) return true;
  lo = std::sqrt(lo), hi = std::sqrt(hi);
  if (!(lo >= kMinModulus))
    fail = {ErrorCode::InvalidArgument,
            "the linear part shrinks some direction by a factor " + fmt(lo) +
                " (an eigenvalue modulus below 1e-6); the logarithm would lose most of its digits: "
                "use poses that differ less (insert intermediate poses), or other units"};
  else
    fail = {ErrorCode::InvalidArgument,
            "the linear part stretches some direction " + fmt(hi / lo) +
                " times more than another (eigenvalue moduli " + fmt(lo) + " to " + fmt(hi) +
                "); beyond 1e8 the logarithm would lose most of its digits: use poses that differ "
                "less (insert intermediate poses)"};
  return false;
}

// log of a 2x2 block L2 = 1 + E: log L2 = alpha 1 + beta N with N = L2 - r 1 (traceless) and
// N^2 = d 1; in the half-turn case N is the quarter turn +-J and d = -1, beta = pi.
struct Block2Log {
  double alpha = 0, beta = 0, d = 0;
  Eigen::Matrix2d N = Eigen::Matrix2d::Zero();
  LinearCase label = LinearCase::DistinctReal;
  // Data of L2 itself: L2 - 1 = r1 1 + sigma N with sigma = 1 (sigma = 0 for a half turn, whose
  // N is not a part of L2), det(L2 - 1), and the eigenvalue offsets lambda - 1 (re +- i im) for
  // the labels. s1 = sigma / beta is the N coefficient of L2 - 1 in terms of beta N.
  double r1 = 0, detE = 0, sigma = 1, s1 = 0;
  double re[2] = {0, 0}, im[2] = {0, 0};

  double eta() const { return beta * beta * d; }
  /// phi(log L2)^-1 = p 1 + q N (q multiplies N itself, not beta N). For a well-conditioned log
  /// block X (Frobenius condition number below kViaInverseCondition) it is X (L2 - 1)^-1 =
  /// (alpha + beta N)(r1 - sigma N) / det(L2 - 1), using N^2 = d; otherwise phiBlockInverse's
  /// phi(X)^-1 = p' + q' beta N.
  BlockCoefficients phiInverseOfLog() const {
    const double eta_ = eta();
    if (wellConditionedBlock(alpha, eta_, beta * beta * N.squaredNorm()) && std::abs(detE) > 1e-280)
      return {(alpha * r1 - sigma * beta * d) / detE, (beta * r1 - sigma * alpha) / detE};
    const BlockCoefficients inv = detail::phiBlockInverse(alpha, eta_, r1, s1, detE);
    return {inv.p, inv.q * beta};
  }
};

void failNegativePair(double r, double sq, double nnorm, const EarOptions& opt, Failure& fail);

// orient = +-1: the half-turn quarter turn is orient times the counter-clockwise one of the
// block's basis (3D: -1 when that basis is oriented against the canonical normal of the plane).
bool logBlock2(const Eigen::Matrix2d& E, const EarOptions& opt, Block2Log& out, Failure& fail, double orient = 1.0) {
  const double r1 = 0.5 * (E(0, 0) + E(1, 1));
  const double r = 1.0 + r1;
  const double h = 0.5 * (E(0, 0) - E(1, 1));
  Eigen::Matrix2d N;
  N << h, E(0, 1), E(1, 0), -h;
  // d = -det N from the entries of N: no cancellation of r^2 against det L2.
  const double d = h * h + E(0, 1) * E(1, 0);
  // det L2 - 1 from the offsets E (no cancellation near the identity); below det = 1/2 that sum
  // cancels (terms near -1 and 1 for a block that shrinks: error about u / det^2 in det, 6e-11
  // in log L2 for a rotation scaled by 1e-3), and det L2 from its entries 1 + E is accurate to
  // about u / det instead.
  double detm1 = E(0, 0) + E(1, 1) + (E(0, 0) * E(1, 1) - E(0, 1) * E(1, 0));
  double det = 1.0 + detm1;
  const bool shrinks = detm1 < -0.5;
  if (shrinks) {
    det = (1.0 + E(0, 0)) * (1.0 + E(1, 1)) - E(0, 1) * E(1, 0);
    detm1 = det - 1.0;
  }
  if (!(det > 0)) {
    fail = {ErrorCode::Singular, "a 2D block of the linear part is numerically singular"};
    return false;
  }
  out.r1 = r1;
  out.detE = E.determinant();
  const double sq = std::sqrt(std::abs(d));  // |eigenvalue - r|
  if (d >= 0) {
    out.re[0] = r1 + sq;
    out.re[1] = r1 - sq;
  } else {
    out.re[0] = out.re[1] = r1;
    out.im[0] = sq;
    out.im[1] = -sq;
  }
  const double ctol = opt.case_tolerance;
  const double htol = opt.half_turn_tolerance;
  if (r < 0 && N.squaredNorm() <= htol * htol * r * r) {
    // S2: a half turn with uniform scale sqrt(det): log = ln k 1 + pi (+-J).
    Eigen::Matrix2d J;
    J << 0.0, -1.0, 1.0, 0.0;
    out.N = (opt.half_turn == HalfTurn::CounterClockwise ? orient : -orient) * J;
    out.alpha = shrinks ? 0.5 * std::log(det) : 0.5 * std::log1p(detm1);  // ln sqrt(det L2)
    out.beta = kPi;
    out.d = -1.0;
    out.s1 = 0.0;  // e^{pi J} = -1: no N component
    out.sigma = 0.0;
    out.label = LinearCase::HalfTurn;
    return true;
  }
  out.N = N;
  out.d = d;
  // beta is on the longest dependency chain of the log, alpha (log1p) is not: beta first.
  // For r > 0 and zeta = -d / r^2 in [-1/4, 1] (a complex pair r +- i w with w <= r, i.e. at
  // most 45 degrees from the positive axis, or real eigenvalues with l1 <= 3 l2: most blocks,
  // and every block near the identity or near a double eigenvalue) beta = F(zeta) / r with the
  // polynomial atanRatio, which needs no square root and no atan2 or log1p. Outside, the closed
  // forms below; on both sides of these borders both are accurate to a few ulp.
  const double zeta = -d / (r * r);
  if (r > 0 && zeta >= detail::kAtanRatioMin && zeta <= detail::kAtanRatioMax) {
    out.beta = detail::atanRatio(zeta) / r;
    out.label = d < 0 ? (4.0 * sq * sq <= ctol * ctol * det ? LinearCase::DoubleEigenvalue : LinearCase::ComplexPair)
                      : (2.0 * sq <= ctol * (r + sq) ? LinearCase::DoubleEigenvalue : LinearCase::DistinctReal);
  } else if (d < 0) {
    // Complex pair r +- i w: beta = theta / w with theta = atan2(w, r) in (0, pi).
    const double w = sq;
    out.beta = std::atan2(w, r) / w;
    // |lambda| = sqrt(det): a double eigenvalue when 2 w <= ctol sqrt(det).
    out.label = r > 0 && 4.0 * w * w <= ctol * ctol * det ? LinearCase::DoubleEigenvalue : LinearCase::ComplexPair;
  } else if (r > 0) {
    // Two positive eigenvalues l1,2 = r +- s with s > r/2 (z = s/r > 1/2, else atanRatio):
    // beta = ln(l1 / l2) / (l1 - l2) = log1p(2 s / l2) / (2 s). l2 = 1 + (r1 - s) is accurate to
    // an ulp while l2 >= 1/2; below, where that sum would cancel, l2 = det / l1 has no
    // cancellation.
    const double s = sq;
    const double l2 = r1 - s > -0.5 ? 1.0 + (r1 - s) : det / (r + s);
    out.beta = std::log1p(2.0 * s / l2) / (2.0 * s);
    out.label = 2.0 * s <= ctol * (r + s) ? LinearCase::DoubleEigenvalue : LinearCase::DistinctReal;
  } else {
    failNegativePair(r, sq, N.norm(), opt, fail);
    return false;
  }
  out.alpha = shrinks ? 0.5 * std::log(det) : 0.5 * std::log1p(detm1);  // ln sqrt(det L2)
  out.s1 = 1.0 / out.beta;
  return true;
}

// The failure of logBlock2 for a block with negative trace that is not a half turn.
void failNegativePair(double r, double sq, double nnorm, const EarOptions& opt, Failure& fail) {
  const double ctol = opt.case_tolerance;
  const double s = sq;
  if (s > ctol * -r)
    fail = {ErrorCode::NoRealLog,
            "the linear part has two distinct negative eigenvalues (" + fmt(r + s) + ", " +
                fmt(r - s) +
                "), so it has no real logarithm and no SAM connects these poses; insert an "
                "intermediate pose (for example the pose half-way along another interpolation) "
                "and use two SAM spans"};
  else if (nnorm <= ctol * -r)
    fail = {ErrorCode::NoRealLog,
            "the linear part is nearly a half turn but has two slightly different negative "
            "eigenvalues (" + fmt(r + s) + ", " + fmt(r - s) + ", relative deviation " +
                fmt(nnorm / -r) + " above EarOptions::half_turn_tolerance = " +
                fmt(opt.half_turn_tolerance) +
                "), so it has no real logarithm; if an exact half turn is meant, make the two "
                "scalings equal or raise the tolerance, otherwise insert an intermediate pose"};
  else
    fail = {ErrorCode::NoRealLog,
            "the linear part has a negative eigenvalue " + fmt(r) +
                " in a Jordan block (a half turn combined with a shear), so it has no real "
                "logarithm and no SAM connects these poses; insert an intermediate pose and use "
                "two SAM spans"};
}

// Label of the translation part from the eigenvalue offsets lambda_k - 1 (as complex numbers).
template <int D>
TranslationCase translationCase(const double (&re)[3], const double (&im)[3], double lmax,
                                const typename Affine<D>::Linear& E, double ctol) {
  int count = 0;
  const double tol = ctol * std::max(1.0, lmax);
  for (int k = 0; k < D; ++k) count += re[k] * re[k] + im[k] * im[k] <= tol * tol ? 1 : 0;
  if (count == 0) return TranslationCase::FixedPoint;
  if (count == 1) return TranslationCase::Eigen1Semisimple;
  const double emax = E.cwiseAbs().maxCoeff();
  if (count == D) return emax <= tol ? TranslationCase::PureTranslation : TranslationCase::Eigen1Defective;
  // D = 3, double eigenvalue 1: semisimple iff rank E = 1 iff every 2x2 minor of E vanishes.
  Eigen::Matrix3d E3 = Eigen::Matrix3d::Zero();
  E3.template topLeftCorner<D, D>() = E;
  const double minor = E3.row(0).cross(E3.row(1)).cwiseAbs().maxCoeff() +
                       E3.row(0).cross(E3.row(2)).cwiseAbs().maxCoeff() +
                       E3.row(1).cross(E3.row(2)).cwiseAbs().maxCoeff();
  return minor <= tol * std::max(emax * emax, 1e-300) ? TranslationCase::Eigen1Semisimple
                                                      : TranslationCase::Eigen1Defective;
}

// Coefficients (c0, c1, c2) of sum_n w_n Y^n for a 3x3 matrix Y with Y^3 = k2 Y^2 + k1 Y + k0,
// where w_n = weight(n), n = 0..nmax.
template <class Weight>
void cayleyHamiltonSeries(double k0, double k1, double k2, int nmax, Weight weight, double c[3]) {
  double a = 1.0, b = 0.0, cc = 0.0;  // Y^0
  c[0] = c[1] = c[2] = 0.0;
  for (int n = 0; n <= nmax; ++n) {
    const double w = weight(n);
    c[0] += w * a;
    c[1] += w * b;
    c[2] += w * cc;
    const double a1 = cc * k0, b1 = a + cc * k1, c1 = b + cc * k2;
    a = a1;
    b = b1;
    cc = c1;
  }
}

// Number of terms after which a power series with coefficients bounded by 1/n! in a 3x3 matrix
// of spectral radius rho is converged to kSeriesTiny (the Cayley-Hamilton coefficients of Y^n
// are bounded by n^2 rho^(n-2)).
int seriesTerms(double rho) {
  double bound = 1.0;
  for (int n = 1; n <= 60; ++n) {
    bound *= std::max(rho, 1e-300) / n;
    if (n >= 3 && static_cast<double>(n) * n * bound / (rho * rho + 1e-300) < kSeriesTiny) return n;
  }
  return 60;
}

// Right (e: K e = 0) and left (f: f^T K = 0) null vectors of a 3x3 matrix K of rank 2, as the
// largest cross products of two rows, respectively two columns, of K. These six cross products
// are the rows and the columns of the cofactor matrix C of K (row i of C = the cross product of
// the other two rows, in cyclic order; column j likewise for the columns), so the nine cofactors
// give both. Only the directions matter to the caller, not the signs or lengths.
inline void nullVectors(const Eigen::Matrix3d& K, Eigen::Vector3d& e, Eigen::Vector3d& f) {
  const double k00 = K(0, 0), k01 = K(0, 1), k02 = K(0, 2);
  const double k10 = K(1, 0), k11 = K(1, 1), k12 = K(1, 2);
  const double k20 = K(2, 0), k21 = K(2, 1), k22 = K(2, 2);
  const double c00 = k11 * k22 - k12 * k21, c01 = k12 * k20 - k10 * k22, c02 = k10 * k21 - k11 * k20;
  const double c10 = k21 * k02 - k22 * k01, c11 = k22 * k00 - k20 * k02, c12 = k20 * k01 - k21 * k00;
  const double c20 = k01 * k12 - k02 * k11, c21 = k02 * k10 - k00 * k12, c22 = k00 * k11 - k01 * k10;
  const double s00 = c00 * c00, s01 = c01 * c01, s02 = c02 * c02;
  const double s10 = c10 * c10, s11 = c11 * c11, s12 = c12 * c12;
  const double s20 = c20 * c20, s21 = c21 * c21, s22 = c22 * c22;
  const double r0 = s00 + s01 + s02, r1 = s10 + s11 + s12, r2 = s20 + s21 + s22;
  const double q0 = s00 + s10 + s20, q1 = s01 + s11 + s21, q2 = s02 + s12 + s22;
  // The row and the column of largest norm (the last one on ties) are selected with one-hot
  // weights, exactly 0 or 1: which one wins is data-dependent, and a branch on it would be
  // mispredicted about half of the time (an indexed load instead was slower still).
  const bool e2 = r2 >= std::max(r0, r1), e1 = !e2 && r1 >= r0;
  const bool f2 = q2 >= std::max(q0, q1), f1 = !f2 && q1 >= q0;
  const double we1 = e1, we2 = e2, we0 = 1.0 - we1 - we2;
  const double wf1 = f1, wf2 = f2, wf0 = 1.0 - wf1 - wf2;
  e = Eigen::Vector3d(we0 * c00 + we1 * c10 + we2 * c20, we0 * c01 + we1 * c11 + we2 * c21,
                      we0 * c02 + we1 * c12 + we2 * c22);
  f = Eigen::Vector3d(wf0 * c00 + wf1 * c01 + wf2 * c02, wf0 * c10 + wf1 * c11 + wf2 * c12,
                      wf0 * c20 + wf1 * c21 + wf2 * c22);
}

// +1 or -1: the sign of the largest-magnitude coordinate of f (the first such on ties).
inline double leadingSign(const Eigen::Vector3d& f) {
  const double a0 = std::abs(f.x()), a1 = std::abs(f.y()), a2 = std::abs(f.z());
  const double lead01 = a1 > a0 ? f.y() : f.x();
  const double lead = a2 > std::max(a0, a1) ? f.z() : lead01;
  return std::copysign(1.0, lead);
}

// An orthonormal basis (w0, w1) of the plane orthogonal to f != 0 (any length, fn2 = |f|^2),
// with (w0, w1, f/|f|) right-handed. This is the branch-free frame of Duff et al. ("Building an
// orthonormal basis, revisited") for the unit normal n = f/|f|: with s = sign(n_z) and
// a = -1/(s + n_z), b = n_x n_y a,
//   w0 = (1 + s n_x^2 a, s b, -s n_x),  w1 = (b, s + n_y^2 a, -n_y).
// Written in f directly, every term shares the factor g = 1 / (|f| (|f| + |f_z|)), so the
// normalization and the frame cost one square root and one division. Continuous except where
// f_z changes sign.
inline Eigen::Matrix<double, 3, 2> planeBasis(const Eigen::Vector3d& f, double fn2) {
  const double nu = std::sqrt(fn2);
  const double s = std::copysign(1.0, f.z());
  const double den = nu + std::abs(f.z());  // |f| + s f_z, no cancellation
  const double g = 1.0 / (nu * den);
  const double inu = den * g;  // 1 / |f|
  const double xy = f.x() * f.y() * g;
  Eigen::Matrix<double, 3, 2> W;
  W << 1.0 - f.x() * f.x() * g, -s * xy,
       -xy, s * (1.0 - f.y() * f.y() * g),
       -s * f.x() * inu, -f.y() * inu;
  return W;
}

// Fills the split form of a span from the parts of the log: M = lam P + alpha Pi + Nt, with
// Nt^2 = eta Pi. When M's 2D block is well conditioned (wellConditionedBlock) the span stores
// w = (block of M)^-1 u and evaluates the block translation as (e^{tM} - 1) w, which needs no
// phi at evaluation time.
template <int D>
void fillSplit(detail::Spectral<D>& sp, double lam, double alpha, double eta, double nfrob2,
               const typename Affine<D>::Linear& P, const typename Affine<D>::Linear& Pi,
               const typename Affine<D>::Linear& Nt, const typename Affine<D>::Vector& u) {
  sp = detail::Spectral<D>{};
  sp.lam = lam;
  sp.inv_lam = lam != 0.0 ? 1.0 / lam : 0.0;  // used only where |t lam| >= 1e-8
  sp.m = alpha;
  sp.eta = eta;
  sp.omega = std::sqrt(std::abs(eta));
  sp.inv_omega = sp.omega > 0 ? 1.0 / sp.omega : 0.0;  // used only where |t omega| >= 1e-3
  sp.Pi = Pi;
  sp.N = Nt;
  sp.Pu = P * u;
  const typename Affine<D>::Vector Piu = Pi * u, Nu = Nt * u;
  if (wellConditionedBlock(alpha, eta, nfrob2)) {
    const double det = alpha * alpha - eta;  // det of the block
    sp.via_inverse = true;
    sp.Piu = (alpha * Piu - Nu) / det;
    sp.Nu = (alpha * Nu - eta * Piu) / det;
  } else {
    sp.Piu = Piu;
    sp.Nu = Nu;
  }
}

template <int D>
struct LogWork;

template <>
struct LogWork<2> {
  static bool run(const Affine2& A, const EarOptions& opt, AffineLog2& log, detail::Spectral<2>* sp,
                  Failure& fail) {
    if (!screen(A, fail)) return false;
    const Eigen::Matrix2d E = A.linear() - Eigen::Matrix2d::Identity();
    Block2Log b;
    if (!logBlock2(E, opt, b, fail) || !eigenvaluesInRange(b.re, b.im, 2, fail)) return false;
    const Eigen::Matrix2d bN = b.beta * b.N;
    const double eta = b.eta();
    log.M = bN;
    log.M.diagonal().array() += b.alpha;
    // u = phi(M)^-1 t.
    const BlockCoefficients gi = b.phiInverseOfLog();
    const Eigen::Vector2d& t = A.translation();
    log.u = gi.p * t + gi.q * (b.N * t);
    log.kase.linear = b.label;
    const double re[3] = {b.re[0], b.re[1], 0}, im[3] = {b.im[0], b.im[1], 0};
    const double lmax = 1.0 + std::abs(b.r1) + std::sqrt(std::abs(b.d));
    log.kase.translation = translationCase<2>(re, im, lmax, E, opt.case_tolerance);
    if (sp)
      fillSplit<2>(*sp, 0.0, b.alpha, eta, bN.squaredNorm(), Eigen::Matrix2d::Zero(), Eigen::Matrix2d::Identity(),
                   bN, log.u);
    return true;
  }
};

template <>
struct LogWork<3> {
  static bool run(const Affine3& A, const EarOptions& opt, AffineLog3& log, detail::Spectral<3>* sp,
                  Failure& fail) {
    if (!screen(A, fail)) return false;
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d E = A.linear() - I;
    const Eigen::Vector3d& t = A.translation();
    const double s = E.trace() / 3.0;  // mean eigenvalue - 1
    const double lbar = 1.0 + s;
    Eigen::Matrix3d F = E;
    F.diagonal().array() -= s;  // traceless: eigenvalues y_k = lambda_k - lbar
    const double P = -0.5 * (F.cwiseProduct(F.transpose())).sum();
    const double Q = -F.determinant();
    // The eigenvalue offsets y = lambda - lbar are the roots of y^3 + P y + Q. Only the root of
    // largest magnitude is solved for (it is the one split off below, and it is simple and well
    // separated from the others whenever the split is used); the other two follow from the
    // deflated quadratic, for the labels and the spread.
    const detail::DominantRoot root = detail::dominantCubicRoot(P, Q);
    const double y = root.y;
    const bool realPair = root.d2 >= 0;
    const double w2 = std::sqrt(std::abs(root.d2));  // half the gap (or imaginary part) of the pair
    // Largest |y_k|: |y| for three real roots (then P <= 0); for a complex pair of modulus^2 =
    // y^2/4 - d2 = y^2 + P, the larger of |y| and that modulus.
    const double spread = std::sqrt(y * y + std::max(P, 0.0));

    // Labels from the eigenvalue offsets lambda_k - 1.
    double re[3], im[3] = {0, 0, 0};
    re[0] = s + y;
    re[1] = s - 0.5 * y + (realPair ? w2 : 0.0);
    re[2] = s - 0.5 * y - (realPair ? w2 : 0.0);
    im[1] = realPair ? 0.0 : w2;
    im[2] = -im[1];
    if (!eigenvaluesInRange(re, im, 3, fail)) return false;
    log.kase.translation = translationCase<3>(re, im, std::abs(lbar) + spread, E, opt.case_tolerance);

    // Series form near a triple eigenvalue: always within 2%, and up to 25% when L is far from
    // normal there (spread below a tenth of |F|_F, Jordan-like), where the eigenvector split
    // loses about u |F|^2 / spread^2.
    if (lbar > 0 && (spread <= kTripleSpread * lbar ||
                     (spread <= kSeriesSpreadMax * lbar && spread * spread <= 0.01 * F.squaredNorm())))
      return seriesForm(F, s, P, Q, spread, t, log, sp);

    // Choose the simple positive eigenvalue mu to split off: the real one of a complex pair,
    // the only positive one, or the most separated of three positive ones. The root of largest
    // magnitude is all three (of three real roots summing to 0 it is the one farthest from the
    // middle one). Only when it is negative and lbar + y <= 0 (then two eigenvalues are
    // negative and distinct: no real log, reported by logBlock2) the largest root is taken.
    double ymu = y;
    if (y < 0 && !(lbar + y > 0) && realPair) ymu = -0.5 * y + w2;
    const double muE = s + ymu;  // mu - 1
    if (!(1.0 + muE > 0)) {
      fail = {ErrorCode::NoRealLog, "the linear part has no positive real eigenvalue"};
      return false;
    }
    // ln mu does not depend on the eigenvectors: started first, it runs while they are computed.
    const double lam = std::log1p(muE);
    // Right (e) and left (f) eigenvectors of mu from the largest cross products of the rows /
    // columns of K = L - mu 1.
    Eigen::Matrix3d K = F;
    K.diagonal().array() -= ymu;
    Eigen::Vector3d e, f;
    nullVectors(K, e, f);
    const double fn2 = f.squaredNorm();
    if (!(fn2 > 0) || !(e.squaredNorm() > 0))
      return seriesForm(F, s, P, Q, spread, t, log, sp);  // unreachable for a simple mu
    // f keeps its length and sign: every use below but the plane basis W is invariant under
    // scaling f, and W only needs to span the plane. (The canonical orientation of the plane
    // matters for the half-turn convention only; logBlock2 applies it.)
    const Eigen::Matrix<double, 3, 2> W = planeBasis(f, fn2);
    // P1 = e f^T / (f.e) projects on e along the invariant plane f-perp; Pi = 1 - P1 = W Kp with
    // Kp = W^T - (W^T e) f^T / (f.e). The block of L in the plane is L2 = W^T L W.
    const Eigen::Vector3d ef = e / f.dot(e);
    const Eigen::Matrix<double, 2, 3> Kp = W.transpose() - (W.transpose() * ef) * f.transpose();
    const Eigen::Matrix<double, 3, 2> EW = E * W;
    const Eigen::Matrix2d E2 = W.transpose() * EW;
    // Everything that needs the block's traceless part N = E2 - r1 1 but not its logarithm is
    // formed before logBlock2, so that it overlaps with the transcendental functions there:
    // WNK = W N Kp (M's block part is beta WNK), WNK t, and P1 = ef f^T.
    // (N exactly as logBlock2 forms it, h = (E00 - E11)/2 on the diagonal: exactly traceless
    // and consistent with its beta, which near a half turn is large.)
    const double h2 = 0.5 * (E2(0, 0) - E2(1, 1));
    Eigen::Matrix2d N2;
    N2 << h2, E2(0, 1), E2(1, 0), -h2;
    Eigen::Matrix3d WNK;
    WNK.noalias() = (W * N2) * Kp;
    Eigen::Vector3d WNKt = WNK * t;
    Eigen::Matrix3d P1;
    P1.noalias() = ef * f.transpose();
    const double ft = f.dot(t);
    Block2Log b;
    if (!logBlock2(E2, opt, b, fail, leadingSign(f))) return false;
    log.kase.linear = b.label;
    if (b.label == LinearCase::HalfTurn) {
      // Half turn: logBlock2 replaced N by the quarter turn of the plane.
      WNK.noalias() = (W * b.N) * Kp;
      WNKt = WNK * t;
    }
    const double eta = b.eta();
    // M = lam P1 + alpha Pi + beta W N Kp = alpha 1 + (lam - alpha) P1 + beta WNK.
    log.M = b.beta * WNK + (lam - b.alpha) * P1;
    log.M.diagonal().array() += b.alpha;
    // u = phi(M)^-1 t = P1 t / phi(lam) + (p Pi + q W N Kp) t with phi(lam) = (mu - 1) / ln mu
    // and p + q N = phi(X)^-1 for the block X; Pi t = t - ef (f.t).
    const BlockCoefficients gi = b.phiInverseOfLog();
    const double phiLam = std::abs(lam) < 1e-8 ? detail::phi(lam) : muE / lam;
    log.u = (ft / phiLam - gi.p * ft) * ef + gi.p * t + gi.q * WNKt;
    if (sp) {
      const Eigen::Matrix3d Pi = I - P1;  // (= W Kp; this form keeps P1 + Pi = 1 exactly)
      fillSplit<3>(*sp, lam, b.alpha, eta, b.beta * b.beta * b.N.squaredNorm(), P1, Pi, b.beta * WNK, log.u);
    }
    return true;
  }

  // Near a triple eigenvalue: L = lbar (1 + N) with N = F / lbar of spectral radius <= 2%,
  // log L = ln lbar + log(1 + N) summed with Cayley-Hamilton (N^3 = -Pn N - Qn).
  static bool seriesForm(const Eigen::Matrix3d& F, double s, double P, double Q, double spread,
                         const Eigen::Vector3d& t, AffineLog3& log, detail::Spectral<3>* sp) {
    const double lbar = 1.0 + s;
    const Eigen::Matrix3d Nn = F / lbar;
    const double rhoN = spread / lbar;
    const double k0 = -Q / (lbar * lbar * lbar), k1 = -P / (lbar * lbar);
    // log(1 + x) = sum_{n>=1} (-1)^(n+1) x^n / n; term n is bounded by n rho^(n-2) (the
    // Cayley-Hamilton coefficients of N^n are at most n^2 rho^(n-2)).
    int nmax = 3;
    for (double b = rhoN; nmax < 200 && nmax * b > kSeriesTiny; ++nmax) b *= rhoN;
    double z[3];
    cayleyHamiltonSeries(k0, k1, 0.0, nmax,
                         [](int n) { return n == 0 ? 0.0 : ((n % 2) ? 1.0 : -1.0) / n; }, z);
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d Nn2 = Nn * Nn;
    const Eigen::Matrix3d Z = z[0] * I + z[1] * Nn + z[2] * Nn2;
    const double ell = std::log1p(s);
    log.M = ell * I + Z;
    log.kase.linear = LinearCase::TripleEigenvalue;
    // Cayley-Hamilton of Z itself, for exp and phi of multiples of M.
    const double kz2 = Z.trace();
    const double kz1 = -0.5 * (kz2 * kz2 - Z.cwiseProduct(Z.transpose()).sum());  // -c1(Z)
    const double kz0 = Z.determinant();
    const double rhoZ = rhoN / (1.0 - rhoN);
    // u = phi(M)^-1 t, phi(ell + Z) = sum_n I_n(ell)/n! Z^n.
    const int n = seriesTerms(rhoZ);
    double J[65];
    detail::phiMoments(ell, n, J);
    double g[3];
    cayleyHamiltonSeries(kz0, kz1, kz2, n, [&](int k) { return J[k]; }, g);
    const Eigen::Matrix3d Z2 = Z * Z;
    const Eigen::Matrix3d G = g[0] * I + g[1] * Z + g[2] * Z2;
    log.u = G.partialPivLu().solve(t);
    if (sp) {
      *sp = detail::Spectral<3>{};
      sp->series = true;
      sp->ell = ell;
      sp->Z = Z;
      sp->Z2 = Z2;
      sp->k0 = kz0;
      sp->k1 = kz1;
      sp->k2 = kz2;
      sp->rho = rhoZ;
      sp->u = log.u;
      sp->Zu = Z * log.u;
      sp->Z2u = Z2 * log.u;
    }
    return true;
  }
};

// A^t in the series form (3D, near a triple eigenvalue): exp(tM) = e^{t ell} exp(tZ) and
// phi(tM) = sum_n I_n(t ell)/n! (tZ)^n, both summed with Cayley-Hamilton of tZ. Accurate while
// |t| rho <= kSeriesReach (about 30 terms).
Affine3 seriesPower(const detail::Spectral<3>& sp, double t) {
  const double k0 = t * t * t * sp.k0, k1 = t * t * sp.k1, k2 = t * sp.k2;
  const int n = seriesTerms(std::abs(t) * sp.rho);
  double inv[65];
  inv[0] = 1.0;
  for (int k = 1; k <= n; ++k) inv[k] = inv[k - 1] / k;
  double ce[3], cg[3], J[65];
  cayleyHamiltonSeries(k0, k1, k2, n, [&](int k) { return inv[k]; }, ce);
  detail::phiMoments(t * sp.ell, n, J);
  cayleyHamiltonSeries(k0, k1, k2, n, [&](int k) { return J[k]; }, cg);
  const double g = std::exp(t * sp.ell);
  const Eigen::Matrix3d Lt = g * (ce[0] * Eigen::Matrix3d::Identity() + (ce[1] * t) * sp.Z + (ce[2] * t * t) * sp.Z2);
  const Eigen::Vector3d tt = t * (cg[0] * sp.u + (cg[1] * t) * sp.Zu + (cg[2] * t * t) * sp.Z2u);
  return Affine3(Lt, tt);
}

[[noreturn]] void raise(const Failure& f) {
  throw Error(f.code, f.message);
}

}  // namespace

// --- labels ----------------------------------------------------------------------------------

const char* to_string(LinearCase c) noexcept {
  switch (c) {
    case LinearCase::ComplexPair: return "complex-pair";
    case LinearCase::DistinctReal: return "distinct-real";
    case LinearCase::DoubleEigenvalue: return "double-eigenvalue";
    case LinearCase::HalfTurn: return "half-turn";
    case LinearCase::TripleEigenvalue: return "triple-eigenvalue";
  }
  return "unknown";
}

const char* to_string(TranslationCase c) noexcept {
  switch (c) {
    case TranslationCase::FixedPoint: return "fixed-point";
    case TranslationCase::Eigen1Semisimple: return "eigen1-semisimple";
    case TranslationCase::Eigen1Defective: return "eigen1-defective";
    case TranslationCase::PureTranslation: return "pure-translation";
  }
  return "unknown";
}

std::string to_string(const LogCase& c) {
  return std::string(to_string(c.linear)) + "/" + to_string(c.translation);
}

template <int D>
typename AffineLog<D>::Homogeneous AffineLog<D>::homogeneous() const {
  Homogeneous h = Homogeneous::Zero();
  h.template topLeftCorner<D, D>() = M;
  h.template topRightCorner<D, 1>() = u;
  return h;
}

// LogWork<D>::run, and a failure instead of a logarithm that does not fit in doubles. Within
// the range screen() admits, M and u can still overflow where L is within rounding of a case
// without a logarithm: a complex pair r +- i w with r < 0 and w tiny next to a large nilpotent
// part (nearly a negative Jordan block) has |M| about pi |N| / w (fuzzing found |M| = 6e153 and
// u = NaN for w / |r| = 5e-154).
template <int D>
bool computeLog(const Affine<D>& A, const EarOptions& options, AffineLog<D>& log, detail::Spectral<D>* sp,
                Failure& fail) {
  if (!LogWork<D>::run(A, options, log, sp, fail)) return false;
  // (x - x is NaN exactly for a non-finite x, see screen)
  if (!std::isnan((log.M - log.M).sum() + (log.u - log.u).sum())) return true;
  fail = {ErrorCode::InvalidArgument,
          "the logarithm of this affinity overflows the double range: its linear part is within "
          "rounding of one without a real logarithm (such as a negative eigenvalue in a Jordan "
          "block); insert an intermediate pose and use two SAM spans"};
  return false;
}

// --- public functions ------------------------------------------------------------------------

template <int D>
AffineLog<D> log(const Affine<D>& A, const EarOptions& options) {
  AffineLog<D> out;
  Failure f;
  if (!computeLog<D>(A, options, out, nullptr, f)) raise(f);
  return out;
}

template <int D>
Span<D>::Span(const Affine<D>& A, const EarOptions& options) : relative_(A), end_(A) {
  Failure f;
  if (!computeLog<D>(A, options, log_, &spec_, f)) raise(f);
}

template <int D>
Span<D> Span<D>::between(const Affine<D>& B, const Affine<D>& C, const EarOptions& options) {
  Span s(C * B.inverse(), options);
  s.start_ = B;
  s.end_ = C;
  return s;
}

template <int D>
Affine<D> Span<D>::power(double t) const {
  using Linear = typename Affine<D>::Linear;
  using Vec = typename Affine<D>::Vector;
  const detail::Spectral<D>& sp = spec_;
  if constexpr (D == 3) {
    if (sp.series) {
      // The series in tZ is summed while |t| rho <= kSeriesReach; beyond, A^t is the 2^k-th
      // power of A^(t/2^k) (k squarings, each adding about one rounding error).
      if (std::abs(t) * sp.rho > kSeriesReach) {
        const int k = static_cast<int>(std::ceil(std::log2(std::abs(t) * sp.rho / kSeriesReach)));
        Affine<D> B = seriesPower(sp, std::ldexp(t, -k));
        for (int i = 0; i < k; ++i) B = B * B;
        return B;
      }
      return seriesPower(sp, t);
    }
  }
  // Split form: exp(tM) = e^{t lam} P + e^{t m} (C Pi + t S N), C, S at t^2 eta, written as
  // 1 + (e^{t lam} - 1) P + (e^{tm} C - 1) Pi + e^{tm} t S N (exactly 1 at t = 0, and accurate
  // relative to A^t - 1 for small t). Translation: t phi(t lam) P u plus, for the block, either
  // (e^{tM} - 1) w with the stored w = M^-1 u (well-conditioned block), or
  // t [p Pi u + t q N u] with (p, q) = phiBlock(t m, t^2 eta).
  // Block exponential e^{t m} (C + t S N) with C = cosh or cos of w = t sqrt|eta| and
  // t S = sinh(w)/sqrt|eta| or sin(w)/sqrt|eta| (1/sqrt|eta| stored); Taylor terms for small w.
  const double a = t * sp.m;
  const double em = std::expm1(a), ea = 1.0 + em;
  const double w = t * sp.omega;
  double c, cm1, tS;  // C, C - 1, t S
  if (std::abs(w) < 1e-3) {
    const CoshSinhc cs = detail::coshSinhc(t * t * sp.eta);
    c = cs.c;
    cm1 = cs.cm1;
    tS = t * cs.s;
  } else if (sp.eta < 0) {
    const double sw = std::sin(w), cw = std::cos(w);
    c = cw;
    cm1 = cw > 0 ? -sw * sw / (1.0 + cw) : cw - 1.0;
    tS = sw * sp.inv_omega;
  } else {
    const double ex = std::expm1(std::abs(w)), e = ex + 1.0;
    cm1 = 0.5 * ex * ex / e;
    c = 1.0 + cm1;
    tS = std::copysign(0.5 * ex * (ex + 2.0) / e, t) * sp.inv_omega;
  }
  const double c1 = em * c + cm1, s1t = ea * tS;
  double emx = 0.0;
  if constexpr (D == 3) emx = std::expm1(t * sp.lam);
  // With P = 1 - Pi: 1 + emx P + c1 Pi = (1 + emx) 1 + (c1 - emx) Pi.
  Linear Lt = (c1 - emx) * sp.Pi + s1t * sp.N;
  Lt.diagonal().array() += 1.0 + emx;
  Vec tt;
  if (sp.via_inverse) {
    tt = c1 * sp.Piu + s1t * sp.Nu;
  } else {
    // (t = 0 falls in phiBlock's series branch, which does not read s1.)
    const BlockCoefficients pq = detail::phiBlock(a, t * t * sp.eta, c1, t != 0.0 ? s1t / t : ea, std::nan(""));
    tt = t * (pq.p * sp.Piu + (t * pq.q) * sp.Nu);
  }
  if constexpr (D == 3) {
    const double x = t * sp.lam;
    tt += (std::abs(x) < 1e-8 ? t * (1.0 + 0.5 * x) : emx * sp.inv_lam) * sp.Pu;
  }
  return Affine<D>(Lt, tt);
}

template <int D>
Affine<D> pow(const Affine<D>& A, double t, const EarOptions& options) {
  if (!std::isfinite(t)) throw Error(ErrorCode::NonFinite, "the exponent t is not finite");
  return Span<D>(A, options).power(t);
}

template <int D>
Affine<D> root(const Affine<D>& A, int n, const EarOptions& options) {
  if (n < 1) throw Error(ErrorCode::InvalidArgument, "root: n must be at least 1, got " + std::to_string(n));
  return Span<D>(A, options).power(1.0 / n);
}

template <int D>
Affine<D> sam(const Affine<D>& B, double t, const Affine<D>& C, const EarOptions& options) {
  if (!std::isfinite(t)) throw Error(ErrorCode::NonFinite, "the time t is not finite");
  return Span<D>::between(B, C, options).pose(t);
}

template <int D>
std::vector<Affine<D>> regularPattern(const Affine<D>& B, const Affine<D>& C, int n,
                                      const EarOptions& options) {
  if (n < 1)
    throw Error(ErrorCode::InvalidArgument, "regularPattern: n must be at least 1, got " + std::to_string(n));
  const Span<D> span = Span<D>::between(B, C, options);
  std::vector<Affine<D>> out;
  out.reserve(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) out.push_back(span.pose(static_cast<double>(i) / n));
  return out;
}

template <int D>
Existence realLogExists(const Affine<D>& A, const EarOptions& options) noexcept {
  try {
    AffineLog<D> lg;
    Failure f;
    if (computeLog<D>(A, options, lg, nullptr, f)) return {};
    return {false, f.code, f.message};
  } catch (const std::exception& e) {  // only std::bad_alloc from message building
    return {false, ErrorCode::InvalidArgument, e.what()};
  }
}

template <int D>
Existence samExists(const Affine<D>& B, const Affine<D>& C, const EarOptions& options) noexcept {
  try {
    return realLogExists<D>(C * B.inverse(), options);
  } catch (const Error& e) {
    return {false, e.code(), std::string("the start pose: ") + e.what()};
  } catch (const std::exception& e) {
    return {false, ErrorCode::InvalidArgument, e.what()};
  }
}

// --- instantiations --------------------------------------------------------------------------

#define STEADY_EAR_INSTANTIATE(D)                                                                  \
  template struct AffineLog<D>;                                                                    \
  template class Span<D>;                                                                          \
  template AffineLog<D> log<D>(const Affine<D>&, const EarOptions&);                                \
  template Affine<D> pow<D>(const Affine<D>&, double, const EarOptions&);                           \
  template Affine<D> root<D>(const Affine<D>&, int, const EarOptions&);                             \
  template Affine<D> sam<D>(const Affine<D>&, double, const Affine<D>&, const EarOptions&);         \
  template std::vector<Affine<D>> regularPattern<D>(const Affine<D>&, const Affine<D>&, int,        \
                                                    const EarOptions&);                             \
  template Existence realLogExists<D>(const Affine<D>&, const EarOptions&) noexcept;               \
  template Existence samExists<D>(const Affine<D>&, const Affine<D>&, const EarOptions&) noexcept;

STEADY_EAR_INSTANTIATE(2)
STEADY_EAR_INSTANTIATE(3)

#undef STEADY_EAR_INSTANTIATE

}  // namespace steady
