#pragma once
/// @file
/// Affinities of the plane and of space, `A(p) = L p + t`, as small value types.

#include <steady/core/error.hpp>

#include <Eigen/Core>
#include <Eigen/LU>  // determinant()
#include <vector>

namespace steady {

/// An affinity `A(p) = L p + t` of R^D (D = 2 or 3) acting on column vectors: the columns of
/// `L` are the images of the basis vectors. Poses in steady map body coordinates to world
/// coordinates. Composition follows function composition: `(A * B)(p) = A(B(p))`.
template <int D>
class Affine {
  static_assert(D == 2 || D == 3, "steady::Affine is defined for D = 2 and D = 3");

 public:
  using Linear = Eigen::Matrix<double, D, D>;          ///< the linear part L
  using Vector = Eigen::Matrix<double, D, 1>;          ///< a point or a vector
  using Matrix = Eigen::Matrix<double, D, D + 1>;      ///< `[L | t]`, D x (D+1)
  using Homogeneous = Eigen::Matrix<double, D + 1, D + 1>;  ///< `[L t; 0 1]`

  /// The identity.
  Affine() : L_(Linear::Identity()), t_(Vector::Zero()) {}
  /// `p -> L p + t`.
  Affine(const Linear& L, const Vector& t) : L_(L), t_(t) {}

  /// From `[L | t]` (D x (D+1)).
  static Affine fromMatrix(const Matrix& m) { return Affine(m.template leftCols<D>(), m.col(D)); }
  /// From a homogeneous matrix. @throws Error(InvalidArgument) when the last row is not
  /// `[0 .. 0 1]` within 1e-12 (a projective map is not an affinity).
  static Affine fromHomogeneous(const Homogeneous& h);

  /// Translation by `v`.
  static Affine translation(const Vector& v) { return Affine(Linear::Identity(), v); }
  /// Uniform scaling by `s` about the origin.
  static Affine scaling(double s) { return Affine(Linear::Identity() * s, Vector::Zero()); }
  /// Axis-aligned scaling by the factors `s` about the origin.
  static Affine scaling(const Vector& s) { return Affine(s.asDiagonal(), Vector::Zero()); }
  /// Shear `p -> p + k (d . p) s`: points move along `s` in proportion to their coordinate
  /// along `d`. @throws Error(DegenerateInput) unless `s` and `d` are nonzero and orthogonal
  /// within 1e-12 (relative), which keeps the shear volume preserving.
  static Affine shear(const Vector& s, const Vector& d, double k);
  /// Rotation about the origin by `angle` radians, counter-clockwise (2D only).
  /// @throws Error(NonFinite) for a non-finite angle.
  static Affine rotation(double angle);
  /// Rotation about the axis through the origin with direction `axis`, right-handed, by
  /// `angle` radians (3D only). About a coordinate axis, that axis's row and column are exactly
  /// those of the identity, so the planes normal to it stay exactly invariant.
  /// @throws Error(DegenerateInput) for a zero or non-finite axis, Error(NonFinite) for a
  /// non-finite angle.
  static Affine rotation(const Vector& axis, double angle);
  /// Rotation by `degrees`, counter-clockwise (2D only). Exact at every multiple of 90 degrees
  /// (a quarter turn is `[[0, -1], [1, 0]]`, not cos(pi/2) = 6e-17 off it): the angle is
  /// reduced exactly to [-45, 45] degrees before its sine and cosine are taken.
  /// @throws Error(NonFinite) for a non-finite angle.
  static Affine rotationDegrees(double degrees);
  /// Rotation about `axis` by `degrees`, right-handed (3D only): as rotation(axis, angle), and
  /// exact at every multiple of 90 degrees about a coordinate axis (a half turn about z is
  /// exactly diag(-1, -1, 1)). Motion files' "angle_deg" use it.
  /// @throws as rotation(axis, angle).
  static Affine rotationDegrees(const Vector& axis, double degrees);

  const Linear& linear() const { return L_; }
  const Vector& translation() const { return t_; }
  Linear& linear() { return L_; }
  Vector& translation() { return t_; }

  /// `[L | t]`.
  Matrix matrix() const;
  /// `[L t; 0 1]`.
  Homogeneous homogeneous() const;

  /// `det L`.
  double determinant() const { return L_.determinant(); }
  /// True when every entry is finite.
  bool isFinite() const { return L_.allFinite() && t_.allFinite(); }

  /// Composition: `(*this * b)(p) = (*this)(b(p))`.
  Affine operator*(const Affine& b) const { return Affine(L_ * b.L_, L_ * b.t_ + t_); }
  /// The inverse map. @throws Error(Singular) when `L` is numerically singular: its Hadamard
  /// ratio `|det L| / prod |column_i|` (1 for orthogonal columns, 0 when singular, independent
  /// of units) is at most 1e-14; Error(NonFinite) for NaN/Inf entries.
  Affine inverse() const;

  /// Image of a point: `L p + t`.
  Vector operator()(const Vector& p) const { return L_ * p + t_; }
  /// Image of a point: `L p + t`.
  Vector applyPoint(const Vector& p) const { return L_ * p + t_; }
  /// Image of a direction (translation ignored): `L v`.
  Vector applyVector(const Vector& v) const { return L_ * v; }
  /// Image of a surface normal: `L^{-T} n`, not normalized (it keeps the orientation of the
  /// surface when det L > 0). @throws Error(Singular) like inverse().
  Vector applyNormal(const Vector& n) const;

  /// Largest absolute entry difference to `b` (L and t together).
  double distance(const Affine& b) const;

 private:
  Linear L_;
  Vector t_;
};

using Affine2 = Affine<2>;
using Affine3 = Affine<3>;

/// The affinity that maps `from[i]` to `to[i]` for every i.
///
/// With exactly D+1 pairs the map is exact; with more it is the least-squares fit (it minimizes
/// the sum of squared distances `|A(from[i]) - to[i]|^2`).
/// @throws Error(InvalidArgument) when the two lists differ in length or hold fewer than D+1
/// points; Error(DegenerateInput) when the `from` points are (numerically) affinely dependent,
/// e.g. collinear in 3D; Error(NonFinite) for NaN/Inf coordinates.
template <int D>
Affine<D> affineFromPoints(const std::vector<typename Affine<D>::Vector>& from,
                           const std::vector<typename Affine<D>::Vector>& to);

/// The frame `[s1 - s0, s2 - s0, s3 - s0 | s0]` of D+1 points (edge vectors as columns, the
/// first point as origin), as used to place a body by a tetrahedron (3D) or triangle (2D).
template <int D>
Affine<D> frameFromPoints(const std::vector<typename Affine<D>::Vector>& points);

extern template class Affine<2>;
extern template class Affine<3>;

}  // namespace steady
