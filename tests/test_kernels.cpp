// White-box accuracy of the scalar kernels behind the EAR, against 50-digit references, with
// points placed on both sides of every switch between formulas: this is where a closed form
// that is continuous on paper can still jump in floating point.

#include "kernels.hpp"

#include <boost/math/constants/constants.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

using HP = boost::multiprecision::cpp_bin_float_50;
using steady::detail::coshSinhc;
using steady::detail::phiBlock;
using steady::detail::phiMoments;

constexpr double kEps = 0x1.0p-52;

// phi(a + N) = P + Q N with N^2 = eta, by its power series sum X^n/(n+1)! in 50 digits.
void referencePhiBlock(double a_, double eta_, HP& P, HP& Q) {
  const HP a = a_, eta = eta_;
  HP p = 1, q = 0, fact = 1;
  P = 1;
  Q = 0;
  for (int n = 1; n < 400; ++n) {
    const HP p1 = a * p + eta * q, q1 = p + a * q;
    p = p1;
    q = q1;
    fact *= (n + 1);
    P += p / fact;
    Q += q / fact;
    if (n > 20 && abs(p / fact) < HP(1e-45) && abs(q / fact) < HP(1e-45)) break;
  }
}

double relErr(double got, const HP& want, double floor) {
  const double w = static_cast<double>(want);
  return std::abs(got - w) / std::max(std::abs(w), floor);
}

}  // namespace

TEST(Kernels, PhiBlockAcrossRegimeBorders) {
  // (a, h) pairs on the borders |a| + h = 1 and h = max(1/4, |a|/4), each side, real and
  // complex, plus a grid; eta = +-h^2.
  std::vector<std::pair<double, double>> pts;
  for (double d : {-1e-12, 0.0, 1e-12}) {
    pts.push_back({0.6, 0.4 + d});
    pts.push_back({-0.6, 0.4 + d});
    pts.push_back({0.95, 0.05 + d});
    pts.push_back({-0.95, 0.05 + d});
    pts.push_back({0.9, 0.25 + d});
    pts.push_back({-0.9, 0.25 + d});
    pts.push_back({3.0, 0.75 + d});
    pts.push_back({-3.0, 0.75 + d});
    pts.push_back({8.0, 2.0 + d});
    pts.push_back({-8.0, 2.0 + d});
    pts.push_back({1e-9, 1.0 + d});
  }
  for (double a = -6; a <= 6; a += 0.37)
    for (double h = 0; h <= 5; h += 0.29) pts.push_back({a, h});
  // Small spectral radii r = |a| + h from 1 down to 1e-15, where the series length changes:
  // regression for a term count that ignored the N part (|q_n| <= n r^(n-1)), found on the
  // perturbed shear [1 1; 1e-11 1] (error 4e-13 in q).
  for (int k = 0; k <= 60; ++k) {
    const double r = std::pow(10.0, -k / 4.0);
    for (double frac : {0.0, 1e-6, 0.3, 0.5, 0.9, 1.0}) {
      pts.push_back({r * (1 - frac), r * frac});
      pts.push_back({-r * (1 - frac), r * frac});
    }
  }
  double worstP = 0, worstQ = 0;
  for (auto [a, h] : pts)
    for (int sign : {1, -1}) {
      const double eta = sign * h * h;
      HP P, Q;
      referencePhiBlock(a, eta, P, Q);
      const auto got = phiBlock(a, eta);
      // Errors relative to the size of phi on the spectrum, |phi(x_i)| = sqrt(P^2 + Q^2 |eta|):
      // the block enters A^t as P 1 + Q N with |N| ~ sqrt|eta|. (For the divided difference Q
      // with close eigenvalues, the floor is |phi'| ~ |P| / (1 + |a|).)
      const double scale = std::sqrt(static_cast<double>(P * P + Q * Q * std::abs(eta)));
      const double eP = relErr(got.p, P, scale);
      const double eQ = relErr(got.q, Q, h > 1 ? scale / h : scale / (1 + std::abs(a)));
      worstP = std::max(worstP, eP);
      worstQ = std::max(worstQ, eQ);
      EXPECT_LE(eP, 64 * kEps) << "a=" << a << " eta=" << eta;
      EXPECT_LE(eQ, 64 * kEps) << "a=" << a << " eta=" << eta;
    }
  std::cout << "phiBlock worst relative error: p " << worstP / kEps << " ulp, q " << worstQ / kEps
            << " ulp over " << pts.size() * 2 << " points\n";
}

TEST(Kernels, CoshSinhcAcrossSeriesBorder) {
  double worst = 0;
  for (double x : {-1e-6 * (1 + 1e-12), -1e-6 * (1 - 1e-12), 1e-6 * (1 - 1e-12), 1e-6 * (1 + 1e-12), 1e-12,
                   -1e-12, 0.0, 0.3, -0.3, 2.0, -2.0, 9.0, -9.0, 30.0, -30.0, 100.0, -100.0}) {
    const HP X = x;
    HP C, S;
    if (x > 0) {
      const HP h = sqrt(X);
      C = cosh(h);
      S = sinh(h) / h;
    } else if (x < 0) {
      const HP w = sqrt(-X);
      C = cos(w);
      S = sin(w) / w;
    } else {
      C = 1;
      S = 1;
    }
    const auto got = coshSinhc(x);
    const double e = std::max({relErr(got.c, C, 1e-3), relErr(got.s, S, 1e-3),
                               relErr(got.cm1, C - 1, std::abs(x) * 1e-2)});
    worst = std::max(worst, e);
    EXPECT_LE(e, 16 * kEps) << "x=" << x;
  }
  std::cout << "coshSinhc worst relative error " << worst / kEps << " ulp\n";
}

TEST(Kernels, PhiMomentsBothRecurrenceDirections) {
  const int nmax = 24;
  for (double a : {-300.0, -40.0, -25.0, -24.5, -12.0, -3.0, -0.5, -1e-9, 0.0, 1e-9, 0.5, 3.0, 12.0, 24.5, 25.0, 40.0, 300.0}) {
    double got[65];
    phiMoments(a, nmax, got);
    // Reference in 50 digits: for |a| <= 50 the series I_n(a)/n! = sum_j a^j / (j! (n + j + 1) n!)
    // (cancellation for a < 0 costs at most e^50 ~ 1e22 of the 50 digits); for |a| > 50 the
    // integration-by-parts sum I_n = e^a sum_k (-1)^k n!/((n-k)! a^(k+1)) + (-1)^(n+1) n!/a^(n+1),
    // whose terms shrink like n/|a|.
    HP nf = 1;
    for (int n = 0; n <= nmax; ++n) {
      if (n > 0) nf *= n;
      HP sum = 0;
      if (std::abs(a) <= 50) {
        HP term = 1;  // a^j / j!
        for (int j = 0; j < 2000; ++j) {
          if (j > 0) term *= HP(a) / j;
          sum += term / (n + j + 1);
          if (j > 2 * std::abs(a) + 40 && abs(term) < HP(1e-60)) break;
        }
      } else {
        const HP A = a;
        HP ratio = 1 / A;  // n!/((n-k)! a^(k+1)) for k = 0
        HP acc = 0;
        for (int k = 0; k <= n; ++k) {
          acc += (k % 2 ? -ratio : ratio);
          ratio *= HP(n - k) / A;
        }
        HP last = nf;
        for (int k = 0; k <= n; ++k) last /= A;
        sum = exp(A) * acc + ((n + 1) % 2 ? -last : last);
      }
      EXPECT_LE(relErr(got[n], sum / nf, 0), 64 * kEps) << "a=" << a << " n=" << n;
    }
  }
}

namespace {

// The real roots of y^3 + P y + Q (exact double inputs) in 50 digits: trigonometric form for
// three real roots, Cardano otherwise, each polished by Newton's method.
std::vector<HP> referenceCubicRoots(double P_, double Q_) {
  const HP P = P_, Q = Q_;
  const HP disc = Q * Q / 4 + P * P * P / 27;
  std::vector<HP> ys;
  if (disc > 0) {
    const HP sq = sqrt(disc);
    const HP a = -Q / 2 + sq, b = -Q / 2 - sq;
    auto cbrtHP = [](const HP& x) { return x >= 0 ? HP(pow(x, HP(1) / 3)) : HP(-pow(-x, HP(1) / 3)); };
    ys.push_back(cbrtHP(a) + cbrtHP(b));
  } else {
    const HP m = sqrt(-P / 3);
    const HP arg = -Q / (2 * m * m * m);
    const HP th = acos(arg > 1 ? HP(1) : (arg < -1 ? HP(-1) : arg)) / 3;
    const HP pi = boost::math::constants::pi<HP>();
    for (int k = 0; k < 3; ++k) ys.push_back(2 * m * cos(th - 2 * pi * k / 3));
  }
  for (HP& y : ys)
    for (int i = 0; i < 8; ++i) {
      const HP df = 3 * y * y + P;
      if (df == 0) break;
      y -= ((y * y + P) * y + Q) / df;
    }
  return ys;
}

}  // namespace

TEST(Kernels, DominantCubicRootAcrossRegimeBorders) {
  // Inputs on both sides of every switch of dominantCubicRoot: the discriminant border k = 2
  // for P < 0 (three real roots / Cardano) and for P > 0 (polynomial in k^2 / Cardano), with
  // k = |Q| / (|P|/3)^(3/2); near P = 0 and Q = 0; at several scales. Plus inputs built from
  // random roots (three real summing to 0, or a real root and a complex pair).
  std::vector<std::pair<double, double>> pq;
  for (double scale : {1e-6, 1.0, 3.0, 1e5}) {
    for (double sgnP : {-1.0, 1.0}) {
      const double P = sgnP * scale * scale;
      const double R3 = std::pow(scale * scale / 3.0, 1.5);
      for (double k : {0.0, 1e-9, 0.3, 1.0, 1.9, 2.0 * (1 - 1e-6), 2.0 * (1 - 1e-12), 2.0, 2.0 * (1 + 1e-12),
                       2.0 * (1 + 1e-6), 2.1, 5.0, 1e3, 1e9})
        for (double sgnQ : {-1.0, 1.0}) pq.push_back({P, sgnQ * k * R3});
    }
    pq.push_back({0.0, scale * scale * scale});
    pq.push_back({1e-20 * scale * scale, -scale * scale * scale});
  }
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int i = 0; i < 3000; ++i) {
    const double r0 = u(rng), r1 = u(rng), r2 = -r0 - r1;
    pq.push_back({r0 * r1 + r0 * r2 + r1 * r2, -r0 * r1 * r2});
    const double x = u(rng), w = std::abs(u(rng)) + 1e-3, r = -2 * x;
    pq.push_back({x * x + w * w + 2 * x * r, -r * (x * x + w * w)});
  }
  for (const auto& [P, Q] : pq) {
    const std::vector<HP> ys = referenceCubicRoots(P, Q);
    HP want = ys[0];
    for (const HP& y : ys)
      if (abs(y) > abs(want) || (abs(y) == abs(want) && y > want)) want = y;
    const auto got = steady::detail::dominantCubicRoot(P, Q);
    const double tiny = 1e-300;
    EXPECT_LE(relErr(got.y, want, tiny), 4 * kEps) << "P=" << P << " Q=" << Q;
    // The deflated pair: real (d2 >= 0) exactly when there are three real roots, up to the
    // sqrt(eps) splitting of a double root.
    const double scaleY = std::abs(got.y) + 1e-300;
    if (ys.size() == 3) {
      EXPECT_GE(got.d2, -1e-14 * scaleY * scaleY) << "P=" << P << " Q=" << Q;
    } else {
      EXPECT_LE(got.d2, 1e-14 * scaleY * scaleY) << "P=" << P << " Q=" << Q;
    }
  }
}

TEST(Kernels, AtanRatioAgainstClosedForms) {
  // F(zeta) = atan(sqrt zeta)/sqrt zeta (zeta > 0), atanh(sqrt -zeta)/sqrt -zeta (zeta < 0), on a
  // grid, near 0, and at both ends of its interval [-1/4, 1] (where logBlock2 switches to
  // atan2 / log1p).
  std::vector<double> zs = {0.0, 1e-300, -1e-300, 1e-17, -1e-17, 1e-8, -1e-8, 1e-3, -1e-3};
  for (double end : {steady::detail::kAtanRatioMin, steady::detail::kAtanRatioMax})
    for (double d : {-1e-9, -1e-15, 0.0}) zs.push_back(end + (end > 0 ? d : -d));
  for (int i = 0; i <= 2000; ++i) zs.push_back(-0.25 + 1.25 * i / 2000.0);
  for (double z : zs) {
    HP want = 1;
    if (z > 0) {
      const HP s = sqrt(HP(z));
      want = atan(s) / s;
    } else if (z < 0) {
      const HP s = sqrt(HP(-z));
      want = atanh(s) / s;
    }
    EXPECT_LE(relErr(steady::detail::atanRatio(z), want, 0), 2 * kEps) << "zeta=" << z;
  }
}
