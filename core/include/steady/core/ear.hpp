#pragma once
/// @file
/// The Extraction of Affinity Roots (EAR): the real logarithm of an affinity in closed form,
/// its real powers `A^t = exp(t log A)`, and steady affine morphs (SAMs) between poses.
///
/// Conventions: an affinity `A = [L | t]` maps `p` to `L p + t` (see Affine). The homogeneous
/// logarithm is written `[M | u]`: `M = log L` and `u` such that `exp([M u; 0 0]) = [L t; 0 1]`.
/// The velocity field of the motion `t -> A^t` is `v(p) = M p + u` at every time (it is
/// stationary), and the SAM from pose B to pose C is `S(t) = A^t B` with `A = C B^-1`.
///
/// Numerics: every case is computed by formulas that are continuous across case borders
/// (eigenvalue 1, double and triple eigenvalues, rotations by any angle below a half turn); no
/// branch is selected by exact floating-point equality. The only discontinuity is the
/// mathematical one at an exact half turn (see HalfTurn).

#include <steady/core/affine.hpp>
#include <steady/core/error.hpp>

#include <string>
#include <vector>

namespace steady {

/// Which real logarithm to return for a half turn (case S2: a 2D block equal to `-k 1`).
///
/// A half turn has infinitely many real logarithms; steady returns `ln k 1 + pi J` where `J` is
/// the quarter turn of the block's plane, counter-clockwise (default) or clockwise. In 2D the
/// plane is oriented by the standard frame. In 3D it is oriented by its normal direction `a`
/// (the left eigenvector of the third, positive eigenvalue: for a rotation, the axis), with the
/// sign of `a` chosen so that its largest-magnitude coordinate is positive (the first such
/// coordinate on ties). Example: `diag(-2, -2, 3)^(1/2) = diag(sqrt2 R(+90 deg), sqrt3)`.
enum class HalfTurn {
  CounterClockwise,  ///< `+pi J` (default)
  Clockwise,         ///< `-pi J`
};

/// Options of the EAR functions. The defaults suit poses given in double precision.
struct EarOptions {
  /// The half-turn convention, see HalfTurn.
  HalfTurn half_turn = HalfTurn::CounterClockwise;
  /// Snap radius of the half-turn case: a 2D block `L2` (with `r = tr L2 / 2 < 0`) is treated
  /// as an exact half turn when `|L2 - r 1|_F <= half_turn_tolerance * |r|`. Outside this
  /// radius, a block with complex eigenvalues is a rotation by less than pi and gets its
  /// principal logarithm (accurate up to the snap radius), and a block with two distinct
  /// negative eigenvalues has no real logarithm. Inside it, the result's round trip error is
  /// at most about this tolerance. The default is 64 units in the last place.
  double half_turn_tolerance = 1.4e-14;
  /// Relative tolerance used only to *label* the case (LogCase): eigenvalues this close
  /// (relative to the largest eigenvalue magnitude) count as equal, eigenvalues this close to
  /// 1 count as 1. Rounding alone splits a double eigenvalue by about 1e-8 (the square root of
  /// the unit roundoff), hence the default. Labels never change the numbers returned.
  double case_tolerance = 1e-6;
};

/// Eigen-structure of the linear part `L`, as found by the EAR.
enum class LinearCase {
  ComplexPair,       ///< a complex pair (a rotation part), in 3D with a positive real eigenvalue
  DistinctReal,      ///< distinct positive real eigenvalues
  DoubleEigenvalue,  ///< a double positive eigenvalue (scalar block or Jordan block), the
                     ///< third eigenvalue (3D) different
  HalfTurn,          ///< case S2: a half turn with uniform scaling in a plane (see HalfTurn)
  TripleEigenvalue,  ///< 3D only: the three eigenvalues agree within 2% (scaling, nilpotent
                     ///< shear, or a small motion near the identity), handled by a series
};

/// How the translation interacts with eigenvalue 1 of `L`.
enum class TranslationCase {
  FixedPoint,        ///< 1 is not an eigenvalue: a unique fixed point `q = (1 - L)^-1 t`
  Eigen1Semisimple,  ///< eigenvalue 1, semisimple: screw-like and straight trajectories
  Eigen1Defective,   ///< eigenvalue 1 in a Jordan block: shear with polynomial trajectories
  PureTranslation,   ///< `L = 1`: straight lines
};

/// The case an affinity fell in.
struct LogCase {
  LinearCase linear = LinearCase::DistinctReal;
  TranslationCase translation = TranslationCase::FixedPoint;
};

const char* to_string(LinearCase c) noexcept;
const char* to_string(TranslationCase c) noexcept;
/// `"<linear>/<translation>"`, e.g. `"complex-pair/eigen1-semisimple"` for a screw.
std::string to_string(const LogCase& c);

/// The homogeneous real logarithm `[M | u]` of an affinity, with the case it fell in.
template <int D>
struct AffineLog {
  using Linear = typename Affine<D>::Linear;
  using Vector = typename Affine<D>::Vector;
  using Homogeneous = typename Affine<D>::Homogeneous;

  Linear M = Linear::Zero();  ///< `log L`
  Vector u = Vector::Zero();  ///< translation part of the homogeneous log
  LogCase kase;               ///< what the EAR found

  /// The stationary velocity field `v(p) = M p + u` of the motion `t -> A^t`.
  Vector velocity(const Vector& p) const { return M * p + u; }
  /// `[M u; 0 0]`, with an exactly zero last row.
  Homogeneous homogeneous() const;
};

using AffineLog2 = AffineLog<2>;
using AffineLog3 = AffineLog<3>;

namespace detail {
/// Precomputed spectral form of a homogeneous log; the data behind Span (see ear.cpp).
/// Split form: `M = lam P + m Pi + N`, with `P + Pi = 1`, `P Pi = 0`, `N = Pi N Pi`,
/// `N^2 = eta Pi` (in 2D, `P = 0`); only `Pi`, `N` and `Pu` = `P u` are stored. `Piu`, `Nu` hold
/// `Pi u`, `N u`, or, when `via_inverse`, `Pi w`, `N w` with `w` the block's inverse applied to `u`. Series form (3D, near a triple
/// eigenvalue): `M = ell 1 + Z` with `Z^3 = k2 Z^2 + k1 Z + k0 1`.
template <int D>
struct Spectral {
  using Linear = typename Affine<D>::Linear;
  using Vector = typename Affine<D>::Vector;
  bool series = false, via_inverse = false;
  double lam = 0, inv_lam = 0, m = 0, eta = 0, omega = 0, inv_omega = 0;
  Linear Pi = Linear::Identity(), N = Linear::Zero();
  Vector Pu = Vector::Zero(), Piu = Vector::Zero(), Nu = Vector::Zero();
  double ell = 0, k0 = 0, k1 = 0, k2 = 0, rho = 0;
  Linear Z = Linear::Zero(), Z2 = Linear::Zero();
  Vector u = Vector::Zero(), Zu = Vector::Zero(), Z2u = Vector::Zero();
};
}  // namespace detail

/// The homogeneous real logarithm of `A`, in closed form (no iteration over the data, no
/// complex arithmetic, no heap allocation).
///
/// For a half turn the convention of `options.half_turn` applies; otherwise the result is the
/// principal logarithm (eigenvalues of `M` with imaginary parts in (-pi, pi)).
/// Range: every column of `L`, and `t`, at most 1e30 long, every column of `L` at least
/// 1e-30 long (far beyond any pose in consistent units; the closed forms raise entries to the
/// sixth power, which would overflow beyond it), and eigenvalue moduli of `L` at least 1e-6
/// and within a factor 1e8 of each other. Accuracy degrades towards these limits: a rotation
/// scaled by 1e-3 has its log within 1.4e-13, by 1e-6 within 1.7e-10; diag(1e8, 1) has the
/// translation part within 1.3e-10 relative.
/// @throws Error(NonFinite) for NaN/Inf entries; Error(InvalidArgument) for a column or `t`
/// longer than 1e30, an eigenvalue modulus below 1e-6 or moduli more than 1e8 apart, or a logarithm too
/// large for doubles (`L` within rounding of a negative Jordan block); Error(Singular) when `L` is numerically
/// singular (a column shorter than 1e-30, or Hadamard ratio `|det L| / prod |column_i|` at
/// most 1e-14); Error(NotOrientationPreserving) when
/// `det L < 0`; Error(NoRealLog) when `L`
/// has two distinct negative eigenvalues or a negative Jordan block (no SAM exists: insert an
/// intermediate pose).
template <int D>
AffineLog<D> log(const Affine<D>& A, const EarOptions& options = {});

/// `A^t = exp(t log A)` for any real `t`. Throws like log().
template <int D>
Affine<D> pow(const Affine<D>& A, double t, const EarOptions& options = {});

/// The n-th root `A^(1/n)`, n >= 1: the step of a regular pattern of n steps from the identity
/// to A. Throws like log(), and Error(InvalidArgument) for n < 1.
template <int D>
Affine<D> root(const Affine<D>& A, int n, const EarOptions& options = {});

/// The SAM from pose `B` (at t = 0) to pose `C` (at t = 1): `(C B^-1)^t B`. Throws like log()
/// applied to `C B^-1` (and Error(Singular) when B is not invertible).
template <int D>
Affine<D> sam(const Affine<D>& B, double t, const Affine<D>& C, const EarOptions& options = {});

/// The regular pattern of `n` steps from `B` to `C`: the n+1 poses `(C B^-1)^(i/n) B`,
/// i = 0..n (the first is B, the last C up to rounding). Throws like sam(), and
/// Error(InvalidArgument) for n < 1.
template <int D>
std::vector<Affine<D>> regularPattern(const Affine<D>& B, const Affine<D>& C, int n,
                                      const EarOptions& options = {});

/// Answer of an existence query: whether a real logarithm (a SAM) exists, and if not, why.
struct Existence {
  bool exists = true;
  ErrorCode reason = ErrorCode::InvalidArgument;  ///< meaningful only when !exists
  std::string message;                           ///< empty when exists
  explicit operator bool() const noexcept { return exists; }
};

/// Whether `A` has a real logarithm (Culver's condition: det L > 0 and every negative real
/// eigenvalue in Jordan blocks that come in identical pairs), with the tolerances of log().
/// Never throws.
template <int D>
Existence realLogExists(const Affine<D>& A, const EarOptions& options = {}) noexcept;

/// Whether a SAM from `B` to `C` exists (`realLogExists(C B^-1)`). Never throws.
template <int D>
Existence samExists(const Affine<D>& B, const Affine<D>& C,
                    const EarOptions& options = {}) noexcept;

/// A precomputed SAM span: evaluates `A^t`, the pose `A^t B` and the velocity field at many
/// times `t` cheaply (no allocation, a few exponentials and about 40 multiply-adds).
template <int D>
class Span {
 public:
  using Vector = typename Affine<D>::Vector;

  /// The span of `t -> A^t` (start pose: the identity). Throws like log().
  explicit Span(const Affine<D>& A, const EarOptions& options = {});
  /// The SAM span from pose `B` (t = 0) to pose `C` (t = 1). Throws like sam().
  static Span between(const Affine<D>& B, const Affine<D>& C, const EarOptions& options = {});

  /// `A^t`, for any real t. The error grows at most linearly with |t| (the input's own rounding
  /// is amplified by t); for spans near a triple eigenvalue and |t| large, `A^(t/2^k)` is
  /// squared k times. Entries overflow to infinity when A^t exceeds double range.
  Affine<D> power(double t) const;
  /// The pose at time t: `A^t B` (B is the identity for a span built from A alone).
  Affine<D> pose(double t) const { return power(t) * start_; }
  /// World-space velocity `M p + u` of the body point that is at world position `p`; it is
  /// the same at every time of the span (the field is stationary).
  Vector velocity(const Vector& p) const { return log_.velocity(p); }

  /// `[M | u]` and the case.
  const AffineLog<D>& log() const { return log_; }
  /// The pose at t = 0.
  const Affine<D>& start() const { return start_; }
  /// The relative motion `A` (the pose at t = 1 is `A B`).
  const Affine<D>& relative() const { return relative_; }
  /// The pose at t = 1 as given: `C` for a span built by between(B, C), `A` for a span built
  /// from `A` alone. (The product `relative() * start()` equals it up to rounding only: for
  /// the identity after a pose that keeps z, its z row came out as (0, 0, 1 - 1.1e-16).)
  const Affine<D>& end() const { return end_; }

 private:
  Span() = default;
  Affine<D> relative_;
  Affine<D> end_;
  Affine<D> start_;
  AffineLog<D> log_;
  detail::Spectral<D> spec_;
};

using Span2 = Span<2>;
using Span3 = Span<3>;

}  // namespace steady
