// White-box accuracy of the scalar kernels behind the EAR, against 50-digit references, with
// points placed on both sides of every switch between formulas: this is where a closed form
// that is continuous on paper can still jump in floating point.

#include "kernels.hpp"

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

TEST(Kernels, DepressedCubicRoots) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int i = 0; i < 2000; ++i) {
    // Three real roots summing to zero.
    const double r0 = u(rng), r1 = u(rng), r2 = -r0 - r1;
    const double P = r0 * r1 + r0 * r2 + r1 * r2, Q = -r0 * r1 * r2;
    auto c = steady::detail::depressedCubic(P, Q);
    ASSERT_TRUE(c.real3 || std::abs(c.y[2]) < 1e-6);
    std::vector<double> want = {r0, r1, r2};
    std::sort(want.rbegin(), want.rend());
    if (c.real3) {
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(c.y[k], want[k], 1e-7) << i;  // double roots: sqrt(eps)
    }
    // A real root and a complex pair x +- i w with 2x + r = 0.
    const double x = u(rng), w = std::abs(u(rng)) + 1e-3, r = -2 * x;
    const double Pc = x * x + w * w + 2 * x * r, Qc = -r * (x * x + w * w);
    c = steady::detail::depressedCubic(Pc, Qc);
    ASSERT_FALSE(c.real3) << i;
    EXPECT_NEAR(c.y[0], r, 1e-12 * (1 + std::abs(r)));
    EXPECT_NEAR(c.y[1], x, 1e-12 * (1 + std::abs(x)));
    EXPECT_NEAR(c.y[2], w, 1e-10 * (1 + std::abs(w)) / w);
  }
}
