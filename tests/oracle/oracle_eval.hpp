#pragma once
// Measures steady (and, optionally, Eigen's unsupported MatrixFunctions) against the
// high-precision oracle on one affinity: round trips, the logarithm, and powers A^t.
//
// Error measures (all relative, Frobenius norm over the D x (D+1) part, computed in high
// precision from the exact double results, so the reference is never rounded first):
//   round trip  |exp(log A) - A| / |A|;
//   log         |[M | u] - [M | u]_ref| / |[M | u]_ref|;
//   A^t         |A^t - (A^t)_ref| / |(A^t)_ref|, the maximum over the t grid powerGrid().
// Condition numbers are relative and normwise, kappa_f(A) = |J_f(A)|_F |A|_F / |f(A)|_F, with
// J_f the Jacobian of the map [L | t] -> f(A) (f = the log, or A -> A^t), estimated by forward
// differences in 50 digits. A method whose backward error is c u (u = 2^-53) has a forward error
// of at most about c u kappa_f: kappa_f is the scale of what any double-precision method can
// reach on that input (it can be pessimistic for structured inputs, e.g. near the identity,
// where L - 1 is exact in floating point).

#include "oracle/hp_oracle.hpp"

#include <steady/core/ear.hpp>

#include <Eigen/Dense>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace steady::oracle {

/// 100 significant digits, for references on ill-conditioned inputs (see the hard families).
using HP100 = boost::multiprecision::cpp_bin_float_100;

constexpr double kUnitRoundoff = 0x1.0p-53;  // u, half the machine epsilon

/// The powers t at which A^t is compared: irregular values covering [-2, 2].
inline const std::vector<double>& powerGrid() {
  static const std::vector<double> ts = {-2.0, -1.37, -1.0, -0.5, -0.11, 0.25,
                                         0.5,  0.83,  1.0,  1.5,  2.0};
  return ts;
}

struct EvalOptions {
  bool eigen = false;         ///< also measure Eigen's MatrixFunctions
  bool conditioning = false;  ///< estimate kappa_log and kappa_pow (D(D+1) extra 50-digit logs)
};

struct Eval {
  // steady
  bool steady_ok = true;
  std::string steady_error;
  double rt_pow = 0;    ///< round trip with pow(A, 1)
  double rt_span = 0;   ///< round trip with Span(A).power(1)
  double rt_hp = 0;     ///< round trip of the steady log, exponentiated by the oracle (backward
                        ///< error of the log alone)
  double rt_floor = 0;  ///< round trip of the oracle's log rounded to double, exponentiated by
                        ///< the oracle: what even a correctly rounded log achieves
  double log_err = 0;   ///< [M | u]
  double logM_err = 0;  ///< M only
  double pow_err = 0;   ///< max over the t grid, steady::pow
  double span_err = 0;  ///< max over the t grid, Span::power
  double worst_t = 0;   ///< the t of pow_err
  // Eigen (log(), exp() and pow(t) of the homogeneous matrix)
  double eig_rt = 0, eig_log = 0, eig_pow = 0;
  // conditioning
  double kappa_log = std::numeric_limits<double>::quiet_NaN();
  double kappa_pow = std::numeric_limits<double>::quiet_NaN();  ///< max over the t grid
};

namespace detail_eval {

/// NaN counts as an infinitely large error.
inline double sane(double e) { return std::isnan(e) ? std::numeric_limits<double>::infinity() : e; }

template <class T, int N>
double relHP(const Mat<T, N>& a, const Mat<T, N>& ref, int rows, int cols) {
  T num = 0, den = 0;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const T d = a(i, j) - ref(i, j);
      num += d * d;
      den += ref(i, j) * ref(i, j);
    }
  return sane(static_cast<double>(sqrt(num / den)));
}

template <class Derived, class T, int N>
double relVsRef(const Eigen::MatrixBase<Derived>& approx, const Mat<T, N>& ref, int rows,
                int cols) {
  if (!approx.allFinite()) return std::numeric_limits<double>::infinity();
  return sane(relErrorBlock<T, N>(approx, ref, rows, cols));
}

}  // namespace detail_eval

/// The oracle's homogeneous log and powers of one affinity, in the scalar T.
template <int D, class T = HP>
struct Reference {
  static constexpr int N = D + 1;
  Mat<T, N> H;                  ///< [L t; 0 1], exact
  Mat<T, N> log;                ///< principal log
  std::vector<Mat<T, N>> pows;  ///< A^t on powerGrid()

  explicit Reference(const Affine<D>& A) {
    H = homogeneousFrom<T, N>(A.matrix());
    log = logm(H);
    for (double t : powerGrid()) pows.push_back(expm(T(t) * log));
  }
};

/// Normwise relative condition numbers of A -> log A and A -> A^t (max over the grid), by
/// forward differences in 50 digits with the step h = 1e-40 |A|_F: small enough to stay in the
/// linear regime next to every singularity met here (a half turn 1e-14 away, eigenvector
/// conditions 1e12), large enough that the 1e-50 rounding of the oracle perturbs the difference
/// quotients by ~1e-10 relative at most.
template <int D>
void estimateConditioning(const Affine<D>& A, double& kappa_log, double& kappa_pow) {
  constexpr int N = D + 1;
  const Reference<D, HP> ref(A);
  const auto& ts = powerGrid();
  const HP normA = frobeniusRows(ref.H, D);
  const HP h = HP(1e-40) * normA;
  HP jl = 0;
  std::vector<HP> jp(ts.size(), HP(0));
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < N; ++j) {
      Mat<HP, N> Hp = ref.H;
      Hp(i, j) += h;
      const Mat<HP, N> lp = logm(Hp);
      for (int r = 0; r < D; ++r)
        for (int c = 0; c < N; ++c) {
          const HP d = (lp(r, c) - ref.log(r, c)) / h;
          jl += d * d;
        }
      for (std::size_t q = 0; q < ts.size(); ++q) {
        const Mat<HP, N> pp = expm(HP(ts[q]) * lp);
        for (int r = 0; r < D; ++r)
          for (int c = 0; c < N; ++c) {
            const HP d = (pp(r, c) - ref.pows[q](r, c)) / h;
            jp[q] += d * d;
          }
      }
    }
  kappa_log = static_cast<double>(sqrt(jl) * normA / frobeniusRows(ref.log, D));
  kappa_pow = 0;
  for (std::size_t q = 0; q < ts.size(); ++q)
    kappa_pow = std::max(
        kappa_pow, static_cast<double>(sqrt(jp[q]) * normA / frobeniusRows(ref.pows[q], D)));
}

/// All measurements of one affinity, with references computed in the scalar T.
template <int D, class T = HP>
Eval evaluate(const Affine<D>& A, const EvalOptions& opt = {}) {
  using detail_eval::relHP;
  using detail_eval::relVsRef;
  constexpr int N = D + 1;
  using Hom = Eigen::Matrix<double, N, N>;
  const auto& ts = powerGrid();
  const Reference<D, T> ref(A);
  Eval ev;

  {  // the floor: the oracle's log, correctly rounded to double, then exponentiated exactly
    Mat<T, N> lr = homogeneousFrom<T, N>(toEigen<T, N>(ref.log).template topRows<D>().eval());
    lr(D, D) = 0;
    ev.rt_floor = relHP<T, N>(expm(lr), ref.H, D, N);
  }

  try {
    const AffineLog<D> lg = steady::log(A);
    Eigen::Matrix<double, D, N> lm;
    lm.template leftCols<D>() = lg.M;
    lm.col(D) = lg.u;
    ev.log_err = relVsRef(lm, ref.log, D, N);
    ev.logM_err = relVsRef(lg.M, ref.log, D, D);
    Mat<T, N> lh = homogeneousFrom<T, N>(lm);
    lh(D, D) = 0;
    ev.rt_hp = relHP<T, N>(expm(lh), ref.H, D, N);
    ev.rt_pow = relVsRef(steady::pow(A, 1.0).matrix(), ref.H, D, N);
    const Span<D> span(A);
    ev.rt_span = relVsRef(span.power(1.0).matrix(), ref.H, D, N);
    for (std::size_t q = 0; q < ts.size(); ++q) {
      const double e = relVsRef(steady::pow(A, ts[q]).matrix(), ref.pows[q], D, N);
      if (e > ev.pow_err) {
        ev.pow_err = e;
        ev.worst_t = ts[q];
      }
      ev.span_err = std::max(ev.span_err, relVsRef(span.power(ts[q]).matrix(), ref.pows[q], D, N));
    }
  } catch (const std::exception& e) {
    ev.steady_ok = false;
    ev.steady_error = e.what();
    const double inf = std::numeric_limits<double>::infinity();
    ev.rt_pow = ev.rt_span = ev.rt_hp = ev.log_err = ev.logM_err = ev.pow_err = ev.span_err = inf;
  }

  if (opt.eigen) {
    const Hom Hd = A.homogeneous();
    const Hom Ld = Hd.log();
    ev.eig_log = relVsRef(Ld.template topRows<D>(), ref.log, D, N);
    const Hom Ed = Ld.exp();
    ev.eig_rt = relVsRef(Ed.template topRows<D>(), ref.H, D, N);
    for (std::size_t q = 0; q < ts.size(); ++q) {
      const Hom P = Hd.pow(ts[q]);
      ev.eig_pow = std::max(ev.eig_pow, relVsRef(P.template topRows<D>(), ref.pows[q], D, N));
    }
  }

  if (opt.conditioning) estimateConditioning<D>(A, ev.kappa_log, ev.kappa_pow);
  return ev;
}

// ---- summaries ----

inline double maxOf(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, detail_eval::sane(x));
  return m;
}

inline double medianOf(std::vector<double> v) {
  if (v.empty()) return 0;
  for (double& x : v) x = detail_eval::sane(x);
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

template <class F>
std::vector<double> column(const std::vector<Eval>& evs, F f) {
  std::vector<double> out;
  out.reserve(evs.size());
  for (const auto& e : evs) out.push_back(f(e));
  return out;
}

}  // namespace steady::oracle
