#pragma once
// Scalar kernels of the EAR (private to steady::core).
//
// A real 2x2 block function is written F(a 1 + N) = p 1 + q N where N is traceless, so that
// N^2 = eta 1 with eta = -det N (eta > 0: two real eigenvalues a +- sqrt(eta); eta < 0: a complex
// pair a +- i sqrt(-eta)). Every kernel below is continuous in (a, eta) across eta = 0 and across
// the switches between its formulas; each switch is placed where both sides are accurate to a
// few units in the last place.

namespace steady::detail {

/// C(x) = cosh(sqrt x), S(x) = sinh(sqrt x)/sqrt x, Cm1 = C - 1 for x >= 0, and the
/// trigonometric continuations cos(sqrt -x), sin(sqrt -x)/sqrt -x for x < 0. For |x| < 1e-6 a
/// Taylor polynomial is used (truncation error below 1e-25).
struct CoshSinhc {
  double c, s, cm1;
};
CoshSinhc coshSinhc(double x);

/// phi(x) = (e^x - 1)/x, phi(0) = 1 (relative error a few ulp for every x).
double phi(double x);

/// The coefficients of phi(a 1 + N) = p 1 + q N, N^2 = eta 1, where phi(X) = (e^X - 1) X^-1 =
/// integral_0^1 e^{sX} ds, for a block whose exponential is known:
/// e^X - 1 = c1 1 + s1 N (c1 = e^a C - 1, s1 = e^a S). No transcendental function is called,
/// except expm1 in the separated-real regime when `detEm1` (= det(e^X - 1), known exactly when
/// e^X is a given matrix) is NaN. Regimes (spectral radius r = |a| + h, h = sqrt|eta|):
///  - r <= 1: power series sum X^n/(n+1)! by Horner (at most 21 terms, fewer for small r);
///  - h <= max(1/4, |a|/4): closed form over det X = a^2 - eta, which is then >= 1/4 and whose
///    numerators do not cancel (close eigenvalues, both away from 0);
///  - eta > 0: (phi(x1) +- phi(x2)) over the well separated real eigenvalues x1,2 = a +- h;
///  - eta < 0: real and imaginary parts of phi(a + i h) with h >= 1/4.
struct BlockCoefficients {
  double p, q;
};
BlockCoefficients phiBlock(double a, double eta, double c1, double s1, double detEm1);

/// phiBlock for a block given by (a, eta) alone (computes its exponential first).
BlockCoefficients phiBlock(double a, double eta);

/// The inverse phi(X)^-1 = P 1 + Q N of phiBlock's phi(X) (same arguments). Real eigenvalues at
/// least 1/2 apart (eta >= 1/16) are inverted one by one, P +- Q h = x_i / (e^x_i - 1), since
/// the determinant p^2 - q^2 eta of phi(X) = p + q N cancels when the eigenvalues of phi(X)
/// differ by orders of magnitude (diag(2.6e24, 1) lost every digit and gave an infinite
/// inverse); otherwise the inverse is (p - q N) / (p^2 - q^2 eta), which does not cancel much
/// there (eigenvalues of phi(X) within a factor e^(1/2) of each other, or e^2 when the spectral
/// radius |a| + h is at most 1; or a complex pair, where p^2 - q^2 eta is a sum of squares).
BlockCoefficients phiBlockInverse(double a, double eta, double c1, double s1, double detEm1);

/// The real root y of y^3 + P y + Q = 0 of largest magnitude (its sign is that of -Q; for Q = 0
/// the positive one), without trigonometric functions or a library cube root: a scaled
/// polynomial in each of two regimes, Cardano's formula with a polynomial cube root in the
/// third (see kernels.cpp). Relative error at most about 3 ulp. The other two roots are the roots of the
/// deflated quadratic, -y/2 +- sqrt(d2): a real pair when d2 >= 0, a complex pair
/// -y/2 +- i sqrt(-d2) otherwise.
struct DominantRoot {
  double y, d2;
};
DominantRoot dominantCubicRoot(double P, double Q);

/// F(zeta) = atan(sqrt zeta) / sqrt zeta for zeta >= 0 and atanh(sqrt -zeta) / sqrt -zeta for
/// zeta < 0 (one analytic function, F(0) = 1), for zeta in [kAtanRatioMin, kAtanRatioMax] =
/// [-1/4, 1], by a polynomial (within about 1 ulp). The log of a 2x2 block with r = tr/2 > 0
/// and N^2 = d 1 has beta = F(-d / r^2) / r: for a complex pair r +- i w, atan(w/r)/w; for real
/// eigenvalues r +- s, atanh(s/r)/s = ln(l1/l2)/(l1 - l2).
constexpr double kAtanRatioMin = -0.25, kAtanRatioMax = 1.0;
double atanRatio(double zeta);

/// I_n(a)/n! for n = 0..nmax (nmax <= 64), with I_n(a) = integral_0^1 s^n e^{a s} ds, computed
/// by the recurrence in its stable direction: forward for n <= a (a > 0), backward otherwise
/// (from 60 steps above max(nmax, 2|a|)).
void phiMoments(double a, int nmax, double* out);

}  // namespace steady::detail
