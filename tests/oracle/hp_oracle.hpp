#pragma once
// An independent high-precision reference for the EAR: the principal logarithm, the exponential
// and real powers of small square matrices, computed by general-purpose iterations that share
// nothing with steady's closed form (no eigenvalues, no case analysis):
//
//   logm: inverse scaling and squaring. Take square roots (coupled Denman-Beavers iteration,
//         with determinantal scaling while far from convergence) until
//         |X - 1|_1 <= 1/4, then sum the Gregory (atanh) series
//             log X = 2 sum_k Y^(2k+1) / (2k+1),  Y = (X - 1)(X + 1)^-1,
//         and multiply by 2^(number of square roots).
//   expm: scaling and squaring with a Taylor series, the terms summed until they drop below the
//         working precision.
//   powm: exp(t log A).
//
// Applied to the homogeneous (D+1)x(D+1) matrix [L t; 0 1], so the translation part of the
// logarithm comes out of the same computation. Every step is a polynomial or rational function
// of the input, so an upper block-triangular input stays upper block-triangular: the last row of
// the log of a homogeneous matrix is [0 .. 0 x] with exact zeros and x = log 1 up to rounding
// (~1e-49); only the first N-1 rows are compared.
//
// Domain: the PRINCIPAL logarithm, i.e. inputs with no eigenvalue on the closed negative real
// axis. Near that axis (a rotation by pi - delta) the log has condition ~pi/delta and the oracle
// loses about log10(1/delta) digits, as any method must; logm throws std::domain_error when the
// iteration does not converge (an eigenvalue on the axis, or a singular matrix).
//
// Scalar: any real type with + - * /, abs, sqrt, pow and std::numeric_limits. The tests use
// boost::multiprecision::cpp_bin_float_50 (50 significant digits, unit roundoff ~1e-50,
// expression templates off by default) and cpp_bin_float_100 for the hard families. Measured
// here (g++ 12 -O2, one 3D affinity: log + 2 exponentials of the 4x4 homogeneous matrix):
// cpp_bin_float_quad 0.6 ms, cpp_bin_float_50 1.1 ms, cpp_bin_float_100 2.9 ms. quad is about
// twice as fast but keeps only ~34 digits: it cannot meet the self-check exp(log X) = X within
// 1e-40, and the hard families cost up to ~21 digits of conditioning (A^t for eigenvector bases
// of condition 1e12, measured 50 vs 100 digits), which would leave quad with ~13 digits, far from
// the >= 30 digits wanted of a reference. 50 digits keep >= 44 digits on the random set and
// >= 28 on every hard family; 100 digits keep >= 78 there.
//
// Written for the steady test suite; deliberately simple (fixed-size row-major arrays), no
// Eigen expression templates with multiprecision scalars.

#include <Eigen/Core>
#include <boost/multiprecision/cpp_bin_float.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace steady::oracle {

/// The working type of the oracle: 50 significant decimal digits.
using HP = boost::multiprecision::cpp_bin_float_50;

/// A fixed-size N x N matrix, row major.
template <class T, int N>
struct Mat {
  std::array<T, N * N> a{};

  T& operator()(int i, int j) { return a[static_cast<std::size_t>(i * N + j)]; }
  const T& operator()(int i, int j) const { return a[static_cast<std::size_t>(i * N + j)]; }

  static Mat zero() {
    Mat m;
    for (auto& x : m.a) x = T(0);
    return m;
  }
  static Mat identity() {
    Mat m = zero();
    for (int i = 0; i < N; ++i) m(i, i) = T(1);
    return m;
  }
};

template <class T, int N>
Mat<T, N> operator+(const Mat<T, N>& x, const Mat<T, N>& y) {
  Mat<T, N> r;
  for (std::size_t k = 0; k < r.a.size(); ++k) r.a[k] = x.a[k] + y.a[k];
  return r;
}
template <class T, int N>
Mat<T, N> operator-(const Mat<T, N>& x, const Mat<T, N>& y) {
  Mat<T, N> r;
  for (std::size_t k = 0; k < r.a.size(); ++k) r.a[k] = x.a[k] - y.a[k];
  return r;
}
template <class T, int N>
Mat<T, N> operator*(const T& s, const Mat<T, N>& x) {
  Mat<T, N> r;
  for (std::size_t k = 0; k < r.a.size(); ++k) r.a[k] = s * x.a[k];
  return r;
}
template <class T, int N>
Mat<T, N> operator*(const Mat<T, N>& x, const Mat<T, N>& y) {
  Mat<T, N> r;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      T s = x(i, 0) * y(0, j);
      for (int k = 1; k < N; ++k) s += x(i, k) * y(k, j);
      r(i, j) = s;
    }
  return r;
}

/// Maximum absolute column sum.
template <class T, int N>
T norm1(const Mat<T, N>& x) {
  using std::abs;
  T best = T(0);
  for (int j = 0; j < N; ++j) {
    T s = T(0);
    for (int i = 0; i < N; ++i) s += abs(x(i, j));
    if (s > best) best = s;
  }
  return best;
}

/// Frobenius norm.
template <class T, int N>
T frobenius(const Mat<T, N>& x) {
  using std::sqrt;
  T s = T(0);
  for (const auto& v : x.a) s += v * v;
  return sqrt(s);
}

/// Inverse by Gauss-Jordan elimination with partial pivoting; also returns the determinant.
/// Throws std::domain_error for an exactly singular matrix. (A zero below the pivot gives a zero
/// multiplier, so a block upper-triangular matrix keeps its exact zero blocks.)
template <class T, int N>
Mat<T, N> inverse(const Mat<T, N>& x, T* det = nullptr) {
  using std::abs;
  Mat<T, N> a = x, inv = Mat<T, N>::identity();
  T d = T(1);
  for (int c = 0; c < N; ++c) {
    int p = c;
    for (int i = c + 1; i < N; ++i)
      if (abs(a(i, c)) > abs(a(p, c))) p = i;
    if (a(p, c) == T(0)) throw std::domain_error("oracle: singular matrix");
    if (p != c) {
      for (int j = 0; j < N; ++j) {
        std::swap(a(p, j), a(c, j));
        std::swap(inv(p, j), inv(c, j));
      }
      d = -d;
    }
    const T piv = a(c, c);
    d *= piv;
    const T rp = T(1) / piv;
    for (int j = 0; j < N; ++j) {
      a(c, j) *= rp;
      inv(c, j) *= rp;
    }
    for (int i = 0; i < N; ++i) {
      if (i == c || a(i, c) == T(0)) continue;
      const T f = a(i, c);
      for (int j = 0; j < N; ++j) {
        a(i, j) -= f * a(c, j);
        inv(i, j) -= f * inv(c, j);
      }
    }
  }
  if (det) *det = d;
  return inv;
}

/// Iteration counts of the last logm call on this thread (for diagnostics and the self-test).
struct LogStats {
  int square_roots = 0;     ///< number of square roots taken
  int db_iterations = 0;    ///< total Denman-Beavers iterations over all square roots
  int series_terms = 0;     ///< terms of the Gregory series
};
inline LogStats& lastLogStats() {
  static thread_local LogStats s;
  return s;
}

/// Principal square root by the (coupled) Denman-Beavers iteration with determinantal scaling
///   Y_{k+1} = (mu Y_k + (mu Z_k)^-1) / 2,   Y_0 = X,   Y_k -> X^(1/2),
///   Z_{k+1} = (mu Z_k + (mu Y_k)^-1) / 2,   Z_0 = 1,   Z_k -> X^(-1/2),
/// mu = |det Y_k det Z_k|^(-1/(2N)) while the relative change of Y exceeds 1/100 (it speeds up
/// the first iterations when the eigenvalues have very different moduli), mu = 1 afterwards.
/// Two inverses per iteration. This coupled form is used rather than the cheaper product form
/// (one inverse; Cheng, Higham, Kenney & Laub 2001) because near a half turn the product form's
/// first iterate M_1 = Y_1 Z_1 has eigenvalues of size delta^2 next to eigenvalues of size 1
/// (delta = pi - rotation angle), and inverting it loses ~2 log10(1/delta) digits (28 at
/// delta = 1e-14, measured against 100 digits), whereas the coupled form inverts matrices of
/// condition ~1/delta, the conditioning of the square root itself.
template <class T, int N>
Mat<T, N> sqrtm(const Mat<T, N>& X, int* iterations = nullptr) {
  using std::abs;
  using std::pow;
  using std::sqrt;
  const T eps = std::numeric_limits<T>::epsilon();
  const T tol = T(16 * N) * eps;
  Mat<T, N> Y = X, Z = Mat<T, N>::identity();
  bool scale = true;
  T prev = std::numeric_limits<T>::max();
  for (int k = 1; k <= 400; ++k) {
    T detY, detZ;
    const Mat<T, N> Yi = inverse(Y, &detY);
    const Mat<T, N> Zi = inverse(Z, &detZ);
    T mu = T(1);
    if (scale) mu = pow(abs(detY * detZ), T(-1) / T(2 * N));
    const T half_mu = mu / 2, half_imu = T(1) / (2 * mu);
    const Mat<T, N> Yn = half_mu * Y + half_imu * Zi;
    Z = half_mu * Z + half_imu * Yi;
    const T change = norm1(Yn - Y) / norm1(Yn);
    Y = Yn;
    if (iterations) *iterations = k;
    if (change <= tol) return Y;
    if (change < T(1e-2)) scale = false;
    // Stagnation at the rounding floor (ill-conditioned input): quadratic convergence has
    // stopped; the last iterate is as good as it gets.
    if (change < sqrt(eps) && change > prev * T(0.25)) return Y;
    prev = change;
  }
  throw std::domain_error("oracle: Denman-Beavers iteration did not converge (eigenvalue on the "
                          "closed negative real axis?)");
}

/// Principal matrix logarithm by inverse scaling and squaring (see the file comment).
template <class T, int N>
Mat<T, N> logm(const Mat<T, N>& A) {
  using std::abs;
  const Mat<T, N> I = Mat<T, N>::identity();
  const T eps = std::numeric_limits<T>::epsilon();
  LogStats& st = lastLogStats();
  st = LogStats{};
  Mat<T, N> X = A;
  int k = 0;
  while (norm1(X - I) > T(0.25)) {
    if (++k > 200) throw std::domain_error("oracle: too many square roots in logm");
    int it = 0;
    X = sqrtm(X, &it);
    st.db_iterations += it;
  }
  st.square_roots = k;
  // Gregory series: log X = 2 atanh(Y), Y = (X - 1)(X + 1)^-1 (the factors commute).
  const Mat<T, N> Y = (X - I) * inverse(X + I);
  const Mat<T, N> Y2 = Y * Y;
  const T q = norm1(Y2);  // |Y^2|_1 <= ~1/60 here, so the tail is geometric
  Mat<T, N> term = Y, sum = Y;
  int j = 0;
  for (j = 1; j < 2000; ++j) {
    term = term * Y2;
    const Mat<T, N> add = (T(1) / T(2 * j + 1)) * term;
    sum = sum + add;
    // remaining terms are bounded by |add| q / (1 - q)
    if (norm1(add) * q <= eps * T(0.01) * norm1(sum) * (T(1) - q)) break;
  }
  st.series_terms = j + 1;
  T scale = T(2);
  for (int i = 0; i < k; ++i) scale *= T(2);
  return scale * sum;
}

/// Matrix exponential by scaling and squaring: exp(X) = (T_m(X / 2^s))^(2^s), with
/// |X / 2^s|_1 <= 1/8 and the Taylor polynomial T_m summed to the working precision.
template <class T, int N>
Mat<T, N> expm(const Mat<T, N>& X) {
  const Mat<T, N> I = Mat<T, N>::identity();
  const T eps = std::numeric_limits<T>::epsilon();
  const T nx = norm1(X);
  int s = 0;
  T scale = T(1);
  while (nx * scale > T(0.125)) {
    scale /= T(2);
    ++s;
  }
  const Mat<T, N> Z = scale * X;
  Mat<T, N> term = I, sum = I;
  for (int j = 1; j < 400; ++j) {
    term = (T(1) / T(j)) * (term * Z);
    sum = sum + term;
    if (norm1(term) <= eps * T(0.01) * norm1(sum)) break;
  }
  for (int i = 0; i < s; ++i) sum = sum * sum;
  return sum;
}

/// Real power A^t = exp(t log A) (principal branch).
template <class T, int N>
Mat<T, N> powm(const Mat<T, N>& A, const T& t) {
  return expm(t * logm(A));
}

// ---- Interoperation with double-precision Eigen matrices (exact conversions to T) ----

/// The N x N homogeneous matrix [m; 0 .. 0 1] of a (N-1) x N double matrix [L | t].
template <class T, int N>
Mat<T, N> homogeneousFrom(const Eigen::Matrix<double, N - 1, N>& m) {
  Mat<T, N> h = Mat<T, N>::zero();
  for (int i = 0; i < N - 1; ++i)
    for (int j = 0; j < N; ++j) h(i, j) = T(m(i, j));
  h(N - 1, N - 1) = T(1);
  return h;
}

/// Any N x N double matrix, exactly.
template <class T, int N>
Mat<T, N> fromEigen(const Eigen::Matrix<double, N, N>& m) {
  Mat<T, N> h;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) h(i, j) = T(m(i, j));
  return h;
}

/// Rounded to double.
template <class T, int N>
Eigen::Matrix<double, N, N> toEigen(const Mat<T, N>& h) {
  Eigen::Matrix<double, N, N> m;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) m(i, j) = static_cast<double>(h(i, j));
  return m;
}

/// Frobenius norm of the first R rows (R = N - 1: the [L | t] or [M | u] part).
template <class T, int N>
T frobeniusRows(const Mat<T, N>& x, int rows) {
  using std::sqrt;
  T s = T(0);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < N; ++j) s += x(i, j) * x(i, j);
  return sqrt(s);
}

/// |approx - ref|_F / |ref|_F over the first `rows` rows and first `cols` columns, computed in
/// T from the exact double values of `approx` (the reference is not rounded first).
template <class T, int N, class Derived>
double relErrorBlock(const Eigen::MatrixBase<Derived>& approx, const Mat<T, N>& ref, int rows,
                     int cols) {
  using std::sqrt;
  T num = T(0), den = T(0);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const T d = T(approx(i, j)) - ref(i, j);
      num += d * d;
      den += ref(i, j) * ref(i, j);
    }
  if (den == T(0)) return static_cast<double>(sqrt(num));
  return static_cast<double>(sqrt(num / den));
}

}  // namespace steady::oracle
