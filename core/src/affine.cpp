#include <steady/core/affine.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <string>
#include <utility>

namespace steady {

namespace {

// Hadamard ratio |det L| / prod |column_i|: 1 for orthogonal columns, 0 for a singular L. It is
// scale invariant, so one threshold serves every unit system.
template <int D>
double hadamardRatio(const Eigen::Matrix<double, D, D>& L) {
  double prod = 1.0;
  for (int j = 0; j < D; ++j) prod *= L.col(j).norm();
  return prod > 0 ? std::abs(L.determinant()) / prod : 0.0;
}

constexpr double kSingularRatio = 1e-14;

void requireFiniteAngle(double angle) {
  if (!std::isfinite(angle)) throw Error(ErrorCode::NonFinite, "rotation angle is NaN or infinite; give a finite angle");
}

// (sin, cos) of an angle in degrees, exact at multiples of 90: the angle is reduced to
// r in [-45, 45] and a quarter-turn count q by IEEE remainders, which are exact, so a multiple
// of 90 leaves r = 0 (sin 0, cos 0 exact), and the quarter turns only swap and negate.
// Continuous across the quadrant borders (r = +-45 from either side: the same values up to
// rounding).
std::pair<double, double> sinCosDegrees(double degrees) {
  const double turn = std::remainder(degrees, 360.0);  // [-180, 180], exact
  const double r = std::remainder(turn, 90.0);          // [-45, 45], exact
  const long q = std::lround((turn - r) / 90.0);       // turn - r is a multiple of 90, exactly
  constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;
  const double s = std::sin(r * kRadiansPerDegree), c = std::cos(r * kRadiansPerDegree);
  switch (((q % 4) + 4) % 4) {
    case 1: return {c, -s};
    case 2: return {-s, -c};
    case 3: return {-c, s};
    default: return {s, c};
  }
}

// R = c 1 + s [a]x + (1 - c) a a^T for a unit axis a, with the diagonal written as
// 1 - (1 - c)(1 - a_i^2): for a = e_k the k-th row and column come out exactly those of the
// identity (Eigen's AngleAxis forms c + (1 - c), which need not round to exactly 1).
Eigen::Matrix3d rotationMatrix(const Eigen::Vector3d& a, double s, double c) {
  const double k = 1.0 - c;
  Eigen::Matrix3d R;
  for (int i = 0; i < 3; ++i) R(i, i) = 1.0 - k * (1.0 - a[i] * a[i]);
  R(0, 1) = k * a[0] * a[1] - s * a[2];
  R(1, 0) = k * a[0] * a[1] + s * a[2];
  R(0, 2) = k * a[0] * a[2] + s * a[1];
  R(2, 0) = k * a[0] * a[2] - s * a[1];
  R(1, 2) = k * a[1] * a[2] - s * a[0];
  R(2, 1) = k * a[1] * a[2] + s * a[0];
  return R;
}

}  // namespace

template <int D>
Affine<D> Affine<D>::fromHomogeneous(const Homogeneous& h) {
  if (!h.allFinite()) throw Error(ErrorCode::NonFinite, "homogeneous matrix has NaN or infinite entries");
  for (int j = 0; j < D; ++j)
    if (std::abs(h(D, j)) > 1e-12)
      throw Error(ErrorCode::InvalidArgument,
                  "homogeneous matrix has a last row other than [0 .. 0 1]: it is projective, not "
                  "affine; divide by the last row or pass the affinity as [L | t]");
  if (std::abs(h(D, D) - 1.0) > 1e-12)
    throw Error(ErrorCode::InvalidArgument,
                "homogeneous matrix has a bottom-right entry other than 1; normalize it first");
  return Affine(h.template topLeftCorner<D, D>(), h.template topRightCorner<D, 1>());
}

template <int D>
Affine<D> Affine<D>::shear(const Vector& s, const Vector& d, double k) {
  const double ns = s.norm(), nd = d.norm();
  if (!(ns > 0) || !(nd > 0) || !std::isfinite(k))
    throw Error(ErrorCode::DegenerateInput, "shear needs nonzero finite direction vectors and factor");
  if (std::abs(s.dot(d)) > 1e-12 * ns * nd)
    throw Error(ErrorCode::DegenerateInput,
                "shear direction s must be orthogonal to the measuring direction d "
                "(otherwise the map is not a shear); orthogonalize s against d");
  return Affine(Linear::Identity() + k * s * d.transpose(), Vector::Zero());
}

namespace {

template <int D>
Affine<D> planeRotation(double s, double c) {
  if constexpr (D == 2) {
    typename Affine<D>::Linear R;
    R << c, -s, s, c;
    return Affine<D>(R, Affine<D>::Vector::Zero());
  } else {
    (void)s;
    (void)c;
    throw Error(ErrorCode::InvalidArgument, "a 3D rotation needs an axis: use rotation(axis, angle)");
  }
}

template <int D>
Affine<D> axisRotation(const typename Affine<D>::Vector& axis, double s, double c) {
  if constexpr (D == 3) {
    const double n = axis.norm();
    if (!(n > 0) || !axis.allFinite())
      throw Error(ErrorCode::DegenerateInput, "rotation axis is zero or not finite; give a direction");
    return Affine<D>(rotationMatrix(axis / n, s, c), Affine<D>::Vector::Zero());
  } else {
    (void)axis;
    (void)s;
    (void)c;
    throw Error(ErrorCode::InvalidArgument, "a 2D rotation has no axis: use rotation(angle)");
  }
}

}  // namespace

template <int D>
Affine<D> Affine<D>::rotation(double angle) {
  requireFiniteAngle(angle);
  return planeRotation<D>(std::sin(angle), std::cos(angle));
}

template <int D>
Affine<D> Affine<D>::rotationDegrees(double degrees) {
  requireFiniteAngle(degrees);
  const auto [s, c] = sinCosDegrees(degrees);
  return planeRotation<D>(s, c);
}

template <int D>
Affine<D> Affine<D>::rotation(const Vector& axis, double angle) {
  requireFiniteAngle(angle);
  return axisRotation<D>(axis, std::sin(angle), std::cos(angle));
}

template <int D>
Affine<D> Affine<D>::rotationDegrees(const Vector& axis, double degrees) {
  requireFiniteAngle(degrees);
  const auto [s, c] = sinCosDegrees(degrees);
  return axisRotation<D>(axis, s, c);
}

template <int D>
typename Affine<D>::Matrix Affine<D>::matrix() const {
  Matrix m;
  m.template leftCols<D>() = L_;
  m.col(D) = t_;
  return m;
}

template <int D>
typename Affine<D>::Homogeneous Affine<D>::homogeneous() const {
  Homogeneous h = Homogeneous::Identity();
  h.template topLeftCorner<D, D>() = L_;
  h.template topRightCorner<D, 1>() = t_;
  return h;
}

template <int D>
Affine<D> Affine<D>::inverse() const {
  if (!isFinite()) throw Error(ErrorCode::NonFinite, "affinity has NaN or infinite entries");
  if (hadamardRatio<D>(L_) <= kSingularRatio)
    throw Error(ErrorCode::Singular,
                "affinity is singular (it flattens space onto a plane, line or point) and has no "
                "inverse; check the pose for a zero or repeated column");
  const Linear Li = L_.inverse();
  return Affine(Li, -(Li * t_));
}

template <int D>
typename Affine<D>::Vector Affine<D>::applyNormal(const Vector& n) const {
  if (hadamardRatio<D>(L_) <= kSingularRatio)
    throw Error(ErrorCode::Singular, "normals cannot be mapped by a singular affinity");
  return L_.inverse().transpose() * n;
}

template <int D>
double Affine<D>::distance(const Affine& b) const {
  return std::max((L_ - b.L_).cwiseAbs().maxCoeff(), (t_ - b.t_).cwiseAbs().maxCoeff());
}

template <int D>
Affine<D> affineFromPoints(const std::vector<typename Affine<D>::Vector>& from,
                           const std::vector<typename Affine<D>::Vector>& to) {
  using Linear = typename Affine<D>::Linear;
  using Vector = typename Affine<D>::Vector;
  if (from.size() != to.size())
    throw Error(ErrorCode::InvalidArgument, "affineFromPoints: the two point lists differ in length (" +
                                                std::to_string(from.size()) + " vs " +
                                                std::to_string(to.size()) + ")");
  const int n = static_cast<int>(from.size());
  if (n < D + 1)
    throw Error(ErrorCode::InvalidArgument, "affineFromPoints: need at least " + std::to_string(D + 1) +
                                                " point pairs, got " + std::to_string(n));
  // Center both sets: the linear part is then the least-squares solution of X L^T = Y.
  Vector cf = Vector::Zero(), ct = Vector::Zero();
  for (int i = 0; i < n; ++i) {
    if (!from[i].allFinite() || !to[i].allFinite())
      throw Error(ErrorCode::NonFinite, "affineFromPoints: point " + std::to_string(i) + " is not finite");
    cf += from[i];
    ct += to[i];
  }
  cf /= n;
  ct /= n;
  Eigen::Matrix<double, Eigen::Dynamic, D> X(n, D), Y(n, D);
  for (int i = 0; i < n; ++i) {
    X.row(i) = (from[i] - cf).transpose();
    Y.row(i) = (to[i] - ct).transpose();
  }
  Eigen::JacobiSVD<Eigen::Matrix<double, Eigen::Dynamic, D>> svd(X, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto sv = svd.singularValues();
  if (!(sv(D - 1) > 1e-12 * sv(0)))
    throw Error(ErrorCode::DegenerateInput,
                "affineFromPoints: the source points are affinely dependent (collinear or coplanar), "
                "so they do not determine an affinity; use points that span the space");
  const Eigen::Matrix<double, D, D> Lt = svd.solve(Y);
  const Linear L = Lt.transpose();
  return Affine<D>(L, ct - L * cf);
}

template <int D>
Affine<D> frameFromPoints(const std::vector<typename Affine<D>::Vector>& points) {
  if (static_cast<int>(points.size()) != D + 1)
    throw Error(ErrorCode::InvalidArgument, "frameFromPoints: need exactly " + std::to_string(D + 1) + " points");
  typename Affine<D>::Linear L;
  for (int j = 0; j < D; ++j) L.col(j) = points[j + 1] - points[0];
  return Affine<D>(L, points[0]);
}

template class Affine<2>;
template class Affine<3>;
template Affine<2> affineFromPoints<2>(const std::vector<Affine<2>::Vector>&, const std::vector<Affine<2>::Vector>&);
template Affine<3> affineFromPoints<3>(const std::vector<Affine<3>::Vector>&, const std::vector<Affine<3>::Vector>&);
template Affine<2> frameFromPoints<2>(const std::vector<Affine<2>::Vector>&);
template Affine<3> frameFromPoints<3>(const std::vector<Affine<3>::Vector>&);

}  // namespace steady
