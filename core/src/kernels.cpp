#include "kernels.hpp"

#include <algorithm>
#include <cmath>

namespace steady::detail {

namespace {
constexpr double kPi = 3.14159265358979323846;
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

BlockCoefficients phiBlock(double a, double eta) {
  const double h = std::sqrt(std::abs(eta));
  const double r = std::abs(a) + h;
  if (r <= 1.0) {
    // sum_{n>=0} X^n/(n+1)!, X^n = p_n 1 + q_n N, X^{n+1} = (a p_n + eta q_n) 1 + (p_n + a q_n) N.
    double pn = 1.0, qn = 0.0, P = 1.0, Q = 0.0;
    double fact = 1.0;  // (n+1)!
    double rn = 1.0;    // r^n
    for (int n = 1; n <= 24; ++n) {
      const double p1 = a * pn + eta * qn;
      const double q1 = pn + a * qn;
      pn = p1;
      qn = q1;
      fact *= static_cast<double>(n + 1);
      P += pn / fact;
      Q += qn / fact;
      rn *= r;
      // Next term: |p_{n+1}| <= r^{n+1}, |q_{n+1}| <= (n+1) r^n, both over (n+2)!.
      if (static_cast<double>(n + 1) * rn / (fact * static_cast<double>(n + 2)) < kTiny) break;
    }
    return {P, Q};
  }
  if (h <= std::max(0.25, 0.25 * std::abs(a))) {
    // phi(X) X = e^X - 1 solved in the commutative algebra of X: divide by det X = x1 x2.
    const CoshSinhc cs = coshSinhc(eta);
    const double ea = std::exp(a), em = std::expm1(a);
    const double det = a * a - eta;
    const double eCm1 = em * cs.c + cs.cm1;  // e^a C - 1
    return {(a * eCm1 - eta * ea * cs.s) / det, (a * ea * cs.s - eCm1) / det};
  }
  if (eta > 0) {
    const double f1 = phi(a + h), f2 = phi(a - h);
    return {0.5 * (f1 + f2), (f1 - f2) / (2.0 * h)};
  }
  // Complex pair z = a + i h: phi(z) = (e^z - 1)/z.
  const double ea = std::exp(a), em = std::expm1(a);
  const double sh = std::sin(h), ch = std::cos(h);
  const double half = std::sin(0.5 * h);
  const double nr = em * ch - 2.0 * half * half;  // Re(e^z - 1) = e^a cos h - 1
  const double ni = ea * sh;                      // Im(e^z - 1)
  const double zz = a * a + h * h;
  const double re = (nr * a + ni * h) / zz;
  const double im = (ni * a - nr * h) / zz;
  return {re, im / h};
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
  const double th = std::acos(arg) / 3.0;
  out.y[0] = 2.0 * m * std::cos(th);
  out.y[1] = 2.0 * m * std::cos(th - 2.0 * kPi / 3.0);
  out.y[2] = 2.0 * m * std::cos(th + 2.0 * kPi / 3.0);
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
