#include "kernels.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace steady::detail {

namespace {
constexpr double kTiny = 0x1.0p-56;  // series truncation threshold (relative)
}  // namespace

CoshSinhc coshSinhc(double x) {
  if (std::abs(x) < 1e-6) {
    // Taylor: C = 1 + x/2 + x^2/24 + x^3/720, S = 1 + x/6 + x^2/120 + x^3/5040.
    const double cm1 = 0.5 * x * (1.0 + x / 12.0 * (1.0 + x / 30.0));
    return {1.0 + cm1, 1.0 + x / 6.0 * (1.0 + x / 20.0 * (1.0 + x / 42.0)), cm1};
  }
  if (x > 0) {
    const double h = std::sqrt(x);
    const double em = std::expm1(h);  // e^h - 1, accurate for small h
    const double e = em + 1.0;
    const double sinh_h = 0.5 * em * (em + 2.0) / e;
    const double cm1 = 0.5 * em * em / e;  // cosh h - 1
    return {1.0 + cm1, sinh_h / h, cm1};
  }
  const double w = std::sqrt(-x);
  const double sw = std::sin(w), cw = std::cos(w);
  // cos w - 1 without cancellation for small w (and directly where cos w < 0).
  const double cm1 = cw > 0 ? -sw * sw / (1.0 + cw) : cw - 1.0;
  return {cw, sw / w, cm1};
}

double phi(double x) {
  if (std::abs(x) < 1e-8) return 1.0 + 0.5 * x * (1.0 + x / 3.0);
  return std::expm1(x) / x;
}

namespace {

// 1/(n+1)! for n = 0..21.
struct InverseFactorials {
  double v[22];
  InverseFactorials() {
    double f = 1.0;
    for (int n = 0; n < 22; ++n) {
      f *= static_cast<double>(n + 1);
      v[n] = 1.0 / f;
    }
  }
};
const InverseFactorials kInvFact;

// Number of terms K of sum_{n<=K} X^n/(n+1)! for spectral radius r <= 1. The first omitted term,
// X^{K+1}/(K+2)! = (p 1 + q N)/(K+2)!, has |p| <= r^(K+1) and |q| <= (K+1) r^K: the q bound
// decides, kept below 2^-56 (relative to p, q ~ 1 and 1/2). rmax[K] is the largest r for which K
// terms suffice.
struct SeriesRadii {
  double rmax[21];
  SeriesRadii() {
    rmax[0] = 0.0;
    for (int K = 1; K <= 20; ++K)
      rmax[K] = std::pow(kTiny / (static_cast<double>(K + 1) * kInvFact.v[K + 1]), 1.0 / K);
  }
};
const SeriesRadii kSeriesRadii;

int phiSeriesTerms(double r) {
  int K = 1;
  while (K < 20 && r > kSeriesRadii.rmax[K]) ++K;
  return K;
}

}  // namespace

namespace {

// The real eigenvalues x1, x2 of X and e^x1 - 1, e^x2 - 1 (eta > 0): from c1 +- h s1, the one
// nearer 1 through det(e^X - 1) and log1p when that is known (a - h would cancel there), else
// by expm1.
struct RealPair {
  double x1, x2, e1, e2;
};
RealPair realPair(double a, double h, double c1, double s1, double detEm1) {
  RealPair r{a + h, a - h, 0, 0};
  if (std::isnan(detEm1)) {
    r.e1 = std::expm1(r.x1);
    r.e2 = std::expm1(r.x2);
    return r;
  }
  r.e1 = c1 + h * s1;
  r.e2 = c1 - h * s1;
  if (std::abs(r.e1) >= std::abs(r.e2)) {
    r.e2 = detEm1 / r.e1;
    r.x2 = std::log1p(r.e2);
    r.x1 = 2.0 * a - r.x2;
  } else {
    r.e1 = detEm1 / r.e2;
    r.x1 = std::log1p(r.e1);
    r.x2 = 2.0 * a - r.x1;
  }
  return r;
}

}  // namespace

BlockCoefficients phiBlock(double a, double eta, double c1, double s1, double detEm1) {
  const double h = std::sqrt(std::abs(eta));
  const double r = std::abs(a) + h;
  const double det = a * a - eta;
  if (r <= 1.0) {
    // Horner: S_K = c_K, S_n = c_n + X S_{n+1}, (P + QN)(a + N) = (aP + eta Q) + (P + aQ) N.
    const int K = phiSeriesTerms(r);
    double P = kInvFact.v[K], Q = 0.0;
    for (int n = K - 1; n >= 0; --n) {
      const double Pn = kInvFact.v[n] + a * P + eta * Q;
      Q = P + a * Q;
      P = Pn;
    }
    return {P, Q};
  }
  if (h <= std::max(0.25, 0.25 * std::abs(a))) {
    // phi(X) X = e^X - 1 solved in the commutative algebra of X: divide by det X = x1 x2, which
    // is >= 1/4 here (close eigenvalues, both away from 0), so the numerators do not cancel.
    return {(a * c1 - eta * s1) / det, (a * s1 - c1) / det};
  }
  if (eta > 0) {
    // x1,2 = a +- h, e^{x1,2} - 1 = c1 +- h s1 (see realPair).
    const RealPair ev = realPair(a, h, c1, s1, detEm1);
    const double f1 = std::abs(ev.x1) < 1e-8 ? 1.0 + 0.5 * ev.x1 : ev.e1 / ev.x1;
    const double f2 = std::abs(ev.x2) < 1e-8 ? 1.0 + 0.5 * ev.x2 : ev.e2 / ev.x2;
    return {0.5 * (f1 + f2), (f1 - f2) / (ev.x1 - ev.x2)};
  }
  // Complex pair z = a + i h: phi(z) = (e^z - 1)/z with e^z - 1 = c1 + i h s1.
  const double nr = c1, ni = h * s1;
  const double zz = a * a + h * h;
  const double re = (nr * a + ni * h) / zz;
  const double im = (ni * a - nr * h) / zz;
  return {re, im / h};
}

BlockCoefficients phiBlockInverse(double a, double eta, double c1, double s1, double detEm1) {
  const double h = std::sqrt(std::abs(eta));
  if (eta > 0 && h >= 0.25 && std::abs(a) + h > 1.0) {
    const RealPair ev = realPair(a, h, c1, s1, detEm1);
    // x / (e^x - 1) = 1 - x/2 + O(x^2)
    const double g1 = std::abs(ev.x1) < 1e-8 ? 1.0 - 0.5 * ev.x1 : ev.x1 / ev.e1;
    const double g2 = std::abs(ev.x2) < 1e-8 ? 1.0 - 0.5 * ev.x2 : ev.x2 / ev.e2;
    return {0.5 * (g1 + g2), (g1 - g2) / (ev.x1 - ev.x2)};
  }
  const BlockCoefficients pq = phiBlock(a, eta, c1, s1, detEm1);
  const double den = pq.p * pq.p - pq.q * pq.q * eta;
  return {pq.p / den, -pq.q / den};
}

BlockCoefficients phiBlock(double a, double eta) {
  const double em = std::expm1(a);
  const CoshSinhc cs = coshSinhc(eta);
  return phiBlock(a, eta, em * cs.c + cs.cm1, (1.0 + em) * cs.s, std::nan(""));
}

namespace {

// Monomial coefficients, in a variable x in [-1, 1], of degree-19 Chebyshev interpolants of the
// functions below (computed in 60-digit arithmetic; the interpolation error is below 2e-17
// relative, so the double evaluation by poly19 is within about 2 ulp):
//  kRootA: w(k) = 2 cos(acos(k/2)/3), the largest root of w^3 - 3 w = k, for k = x + 1 in
//          [0, 2] (analytic there: the nearest singularity is at k = -2);
//  kRootB: g = w/k for the real root w of w^3 + 3 w = k, as a function of kappa = k^2/4 =
//          (x + 1)/2 in [0, 1] (w is odd in k, so g is analytic in k^2; singular at kappa = -1);
//  kCbrtH: h(m) = (cbrt(m) - 1) / (m - 1) for m = (x + 3)/2 in [1, 2] (so the polynomial only
//          carries the small part of cbrt(m) = 1 + (m - 1) h(m)).
constexpr double kRootA[20] = {
    1.8793852415718169, 0.13164361454489948, -0.01286282797532875, 0.002213309911675948,
    -0.00046729055880895596, 0.00010982883723375936, -2.7582556822720918e-05, 7.2465793809834073e-06,
    -1.9670733878883418e-06, 5.4735236916327455e-07, -1.5529927189289628e-07, 4.4756331794561629e-08,
    -1.3052249997526522e-08, 3.8514385454776357e-09, -1.1658602598046337e-09, 3.5013315451173612e-10,
    -8.9788288278079667e-11, 2.720849860909123e-11, -1.5859366160711338e-11, 4.8900203408114193e-12,
};
constexpr double kRootB[20] = {
    0.31290840947923337, -0.017080218354901096, 0.0026443149446683874, -0.00053564601196441641,
    0.00012324109041983122, -3.0560159303071289e-05, 7.962311297328563e-06, -2.1488155557936236e-06,
    5.9537495221532894e-07, -1.6836993134200499e-07, 4.8401550476559941e-08, -1.4100979364927127e-08,
    4.149692768591094e-09, -1.2340369845068226e-09, 3.7624846020711252e-10, -1.1365403334296865e-10,
    2.9199186466781608e-11, -8.8905979466084841e-12, 5.2350350873299884e-12, -1.6195867269731875e-12,
};
constexpr double kCbrtH[20] = {
    0.28942848510666375, -0.035047542317034427, 0.006782993118187604, -0.0015488173406226166,
    0.00038566716780153332, -0.00010134157002760588, 2.7627526530123285e-05, -7.7364350755648139e-06,
    2.2111294877586576e-06, -6.4221787702540254e-07, 1.8898573406173426e-07, -5.6212017248669017e-08,
    1.6851213876362388e-08, -5.096613388535405e-09, 1.5803462558129839e-09, -4.8418736049917226e-10,
    1.2478216775048745e-10, -3.84748051263273e-11, 2.3356132236110237e-11, -7.3000370029213793e-12,
};
// 2^(r/3), r = 0, 1, 2, as hi + lo.
constexpr double kCbrt2Hi[3] = {1, 1.2599210498948732, 1.5874010519681996};
constexpr double kCbrt2Lo[3] = {0, -2.5899333753005069e-17, -1.0869008194197823e-16};

// Monomial coefficients, in x = (zeta - 3/8) * 8/5 in [-1, 1], of the degree-23 Chebyshev
// interpolant of G(zeta) = (F(zeta) - 1) / zeta on [-1/4, 1], F(zeta) = atan(sqrt zeta) / sqrt zeta
// (analytic there; the nearest singularity is at zeta = -1). F = 1 + zeta G keeps the
// polynomial's rounding in the small part.
constexpr double kAtanG[24] = {
    -0.27392999105930266, 0.078764371587650664, -0.026351393975663565, 0.0094991104581261237,
    -0.0035813851215422054, 0.0013915283649219708, -0.00055250285897619949, 0.00022298407954416476,
    -9.1151771996019447e-05, 3.7646322109550396e-05, -1.5680861000321098e-05, 6.5776628274099128e-06,
    -2.7733166849630864e-06, 1.1763633929204957e-06, -5.0704121365681282e-07, 2.1696153168684756e-07,
    -8.3956076386540069e-08, 3.6083307964925033e-08, -2.5178188606551525e-08, 1.0948499201705764e-08,
    1.6125822417729943e-09, -7.2093488678279762e-10, -2.1094328404104889e-09, 9.2396674683574171e-10,
};

// c[0] + c[1] x + ... + c[23] x^23 by Estrin's scheme (5 dependent steps).
inline double poly23(const double (&c)[24], double x) {
  const double x2 = x * x, x4 = x2 * x2, x8 = x4 * x4, x16 = x8 * x8;
  double a[12];
  for (int i = 0; i < 12; ++i) a[i] = c[2 * i] + c[2 * i + 1] * x;
  const double b0 = a[0] + a[1] * x2, b1 = a[2] + a[3] * x2, b2 = a[4] + a[5] * x2,
               b3 = a[6] + a[7] * x2, b4 = a[8] + a[9] * x2, b5 = a[10] + a[11] * x2;
  const double d0 = b0 + b1 * x4, d1 = b2 + b3 * x4, d2 = b4 + b5 * x4;
  return (d0 + d1 * x8) + d2 * x16;
}

// c[0] + c[1] x + ... + c[19] x^19 by Estrin's scheme: pairs, then pairs of pairs with x^2,
// x^4, x^8, x^16 (5 dependent multiply-add steps instead of Horner's 19).
inline double poly19(const double (&c)[20], double x) {
  const double x2 = x * x, x4 = x2 * x2, x8 = x4 * x4, x16 = x8 * x8;
  double a[10];
  for (int i = 0; i < 10; ++i) a[i] = c[2 * i] + c[2 * i + 1] * x;
  const double b0 = a[0] + a[1] * x2, b1 = a[2] + a[3] * x2, b2 = a[4] + a[5] * x2,
               b3 = a[6] + a[7] * x2, b4 = a[8] + a[9] * x2;
  const double d0 = b0 + b1 * x4, d1 = b2 + b3 * x4;
  return (d0 + d1 * x8) + b4 * x16;
}

// x^(1/3) for a normal positive x (DBL_MIN <= x < inf): with x = m 2^e, m in [1, 2) and
// e = 3 j + r (r = 0, 1, 2), x^(1/3) = 2^j T_r (1 + d), T_r = 2^(r/3) = hi + lo and
// d = (m - 1) h(m) from kCbrtH; T_r (1 + d) = hi + (hi d + lo) up to the tiny lo d. Within
// about 1 ulp.
double cbrtPositive(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const int e = static_cast<int>(bits >> 52) - 1023;
  const int j = (e + 3 * 1024) / 3 - 1024;  // floor(e / 3): the numerator is positive
  const int r = e - 3 * j;
  const std::uint64_t mbits = (bits & ((std::uint64_t{1} << 52) - 1)) | (std::uint64_t{1023} << 52);
  const std::uint64_t sbits = static_cast<std::uint64_t>(j + 1023) << 52;
  double m, scale;
  std::memcpy(&m, &mbits, sizeof m);
  std::memcpy(&scale, &sbits, sizeof scale);
  const double d = (m - 1.0) * poly19(kCbrtH, 2.0 * m - 3.0);
  const double hi = kCbrt2Hi[r];
  const double c = hi + (hi * d + kCbrt2Lo[r]);
  return c * scale;
}

}  // namespace

DominantRoot dominantCubicRoot(double P, double Q) {
  // Write q = |Q| and solve z^3 + P z = q for its positive root z (then y = -sign(Q) z). Its
  // discriminant is h + p3 with h = (q/2)^2 and p3 = (P/3)^3. The regimes below are chosen by
  // inequalities only; each formula is accurate to a few ulp on both sides of every switch, so
  // the root is continuous across them up to rounding.
  const double q = std::abs(Q);
  const double h = 0.25 * q * q;
  const double p3 = P * P * P / 27.0;
  double z;
  if (P < 0 && h + p3 <= 0) {
    // Three real roots. With R = sqrt(-P/3), z = R w where w^3 - 3 w = k = q / R^3 in [0, 2]
    // (rounding can push k just past 2; a NaN from an underflowed R^3 is caught as well).
    const double R = std::sqrt(P / -3.0);
    const double k = q / (R * R * R);
    z = R * poly19(kRootA, (k <= 2.0 ? k : 2.0) - 1.0);
  } else if (P > 0 && h < p3) {
    // One real root and k = q / R^3 < 2 with R = sqrt(P/3): w^3 + 3 w = k, and z = R w =
    // R k g(k^2) = (3 q / P) g with kappa = k^2/4 = h / p3, which needs no square root. (Here
    // Cardano's formula would cancel: its two cube roots tend to opposite values as k -> 0.)
    z = (3.0 * q / P) * poly19(kRootB, 2.0 * (h / p3) - 1.0);
  } else {
    // One real root (or P = Q = 0): Cardano with the larger cube root A = cbrt(q/2 + sqrt(disc))
    // and z = A - P / (3A). For P < 0 both terms are positive (error about that of A). Near the
    // border with three roots (disc -> 0+) z is stationary in A, so the inaccurate sqrt(disc)
    // does not matter there. For P > 0 this regime has k >= 2, so |P / (3A)| <= 0.56 A: the
    // subtraction multiplies the (1 ulp) error of A by at most 3.5, about 3 ulp in z, as in the
    // other regimes (a Newton step would bring it to 1 ulp, at the cost of one more division).
    const double c = 0.5 * q + std::sqrt(h + p3);
    const double A = c >= DBL_MIN ? cbrtPositive(c) : std::cbrt(c);
    z = A > 0 ? A - P / (3.0 * A) : 0.0;
  }
  const double y = Q > 0 ? -z : z;
  return {y, -(0.75 * y * y + P)};
}

double atanRatio(double zeta) { return 1.0 + zeta * poly23(kAtanG, (zeta - 0.375) * 1.6); }

void phiMoments(double a, int nmax, double* out) {
  // I_n = (e^a - n I_{n-1}) / a forward, I_{n-1} = (e^a - a I_n) / n backward. Backward keeps
  // the relative error for every n when a <= 0 (all terms positive) and for n > a when a > 0;
  // forward is stable for n <= a. The backward run starts 60 steps above max(nmax, 2|a|), from
  // the asymptotic value I_n ~ e^a / (n + 1 + a); each step damps the start error by a factor
  // |a| I_n / (n I_{n-1}) <= 1/2 there, so 60 steps damp it below 1e-18.
  nmax = std::clamp(nmax, 0, 64);
  double I[65];
  const double ea = std::exp(a);
  const int split = a > 0 ? static_cast<int>(std::min(std::floor(a), static_cast<double>(nmax + 1))) : -1;
  const int top = std::max(nmax, static_cast<int>(std::ceil(2.0 * std::abs(a)))) + 60;
  double In = ea / (static_cast<double>(top + 1) + a);
  for (int n = top; n > split + 1; --n) {
    In = (ea - a * In) / static_cast<double>(n);  // now I_{n-1}
    if (n - 1 <= nmax) I[n - 1] = In;
  }
  if (split >= 0) {
    I[0] = std::expm1(a) / a;
    for (int n = 1; n <= std::min(split, nmax); ++n) I[n] = (ea - static_cast<double>(n) * I[n - 1]) / a;
  }
  double fact = 1.0;
  for (int n = 0; n <= nmax; ++n) {
    if (n > 0) fact *= static_cast<double>(n);
    out[n] = I[n] / fact;
  }
}

}  // namespace steady::detail
