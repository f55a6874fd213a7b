#include "kernels.hpp"

#include <algorithm>
#include <cmath>

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
    // x1,2 = a +- h, e^{x1,2} - 1 = c1 +- h s1. When det(e^X - 1) is known, the eigenvalue of
    // e^X nearer 1 comes from it and its log from log1p, since a - h would cancel there.
    double x1 = a + h, x2 = a - h;
    double e1, e2;
    if (std::isnan(detEm1)) {
      e1 = std::expm1(x1);
      e2 = std::expm1(x2);
    } else {
      e1 = c1 + h * s1;
      e2 = c1 - h * s1;
      if (std::abs(e1) >= std::abs(e2)) {
        e2 = detEm1 / e1;
        x2 = std::log1p(e2);
        x1 = 2.0 * a - x2;
      } else {
        e1 = detEm1 / e2;
        x1 = std::log1p(e1);
        x2 = 2.0 * a - x1;
      }
    }
    const double f1 = std::abs(x1) < 1e-8 ? 1.0 + 0.5 * x1 : e1 / x1;
    const double f2 = std::abs(x2) < 1e-8 ? 1.0 + 0.5 * x2 : e2 / x2;
    return {0.5 * (f1 + f2), (f1 - f2) / (x1 - x2)};
  }
  // Complex pair z = a + i h: phi(z) = (e^z - 1)/z with e^z - 1 = c1 + i h s1.
  const double nr = c1, ni = h * s1;
  const double zz = a * a + h * h;
  const double re = (nr * a + ni * h) / zz;
  const double im = (ni * a - nr * h) / zz;
  return {re, im / h};
}

BlockCoefficients phiBlock(double a, double eta) {
  const double em = std::expm1(a);
  const CoshSinhc cs = coshSinhc(eta);
  return phiBlock(a, eta, em * cs.c + cs.cm1, (1.0 + em) * cs.s, std::nan(""));
}

CubicRoots depressedCubic(double P, double Q) {
  CubicRoots out{};
  const double disc = 0.25 * Q * Q + P * P * P / 27.0;
  if (disc > 0) {
    // One real root (Cardano, larger-magnitude cube root first to avoid cancellation).
    const double A = std::cbrt(-0.5 * Q - std::copysign(std::sqrt(disc), Q));
    const double B = A != 0.0 ? -P / (3.0 * A) : 0.0;
    double y = A + B;
    const double f = (y * y + P) * y + Q, df = 3.0 * y * y + P;
    if (df != 0.0) y -= f / df;  // one Newton step
    out.real3 = false;
    out.y[0] = y;
    out.y[1] = -0.5 * y;
    out.y[2] = std::sqrt(std::max(0.0, 0.75 * y * y + P));
    return out;
  }
  // Three real roots (trigonometric form); P <= 0 here.
  out.real3 = true;
  const double m = std::sqrt(std::max(0.0, -P / 3.0));
  if (!(m > 0)) {
    out.y[0] = out.y[1] = out.y[2] = 0.0;
    return out;
  }
  const double arg = std::clamp(-0.5 * Q / (m * m * m), -1.0, 1.0);
  const double th = std::acos(arg) / 3.0;  // in [0, pi/3]
  // cos(th -+ 2pi/3) = -cos(th)/2 +- sin(th) sqrt(3)/2.
  const double c = std::cos(th), s = std::sin(th);
  constexpr double kHalfSqrt3 = 0.86602540378443864676;
  out.y[0] = 2.0 * m * c;
  out.y[1] = m * (-c + 2.0 * kHalfSqrt3 * s);
  out.y[2] = m * (-c - 2.0 * kHalfSqrt3 * s);
  return out;
}

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
