#pragma once
// The hard families of affinities on which the EAR is compared with the high-precision oracle
// (shared by the oracle tests and the accuracy report, so both speak about the same inputs).
//
// Every family is generated from a fixed seed. Where the defining property is delicate (an
// eigenvalue 1 + 1e-14, a turn by pi - 1e-14) the matrix is built in 50-digit arithmetic and
// rounded once to double; the oracle then works on that exact double input, so the reference is
// the logarithm of the matrix actually passed to steady, not of the ideal one.

#include "oracle/hp_oracle.hpp"
#include "support/random_affine.hpp"

#include <steady/core/affine.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <complex>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace steady::oracle {

template <int D>
struct Sample {
  std::string variant;  ///< short description, e.g. "eig 1+1e-7, 2.5"
  double param = 0;     ///< the family parameter (k of 10^-k, or log10 of a condition number)
  Affine<D> A;
  double basis_cond = 0;  ///< 2-norm condition number of the unit-column eigenvector basis
};

namespace fam {

using steady::testing::uniform;

template <int N>
using HMat = Mat<HP, N>;

inline HP hpPi() { return boost::math::constants::pi<HP>(); }

inline HP pow10(int k) {
  HP r = 1;
  for (int i = 0; i < k; ++i) r /= 10;
  return r;
}

template <int D>
Eigen::Matrix<double, D, D> round(const HMat<D>& m) {
  return toEigen<HP, D>(m);
}

/// V Lambda V^-1 in 50 digits.
template <int D>
HMat<D> similar(const HMat<D>& V, const HMat<D>& Lam) {
  return V * (Lam * inverse(V));
}

/// A mild random basis: 1 + entries uniform in [-0.5, 0.5], 2-norm condition number <= 6.
template <int D>
HMat<D> mildBasis(std::mt19937_64& rng) {
  for (;;) {
    Eigen::Matrix<double, D, D> V;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) V(i, j) = (i == j ? 1.0 : 0.0) + uniform(rng, -0.5, 0.5);
    Eigen::JacobiSVD<Eigen::Matrix<double, D, D>> svd(V);
    const auto s = svd.singularValues();
    if (s(D - 1) > 0 && s(0) / s(D - 1) <= 6) return fromEigen<HP, D>(V);
  }
}

template <int D>
typename Affine<D>::Vector randomTranslation(std::mt19937_64& rng, double size = 5) {
  typename Affine<D>::Vector t;
  for (int i = 0; i < D; ++i) t(i) = uniform(rng, -size, size);
  return t;
}

template <int D>
HMat<D> diagonal(std::initializer_list<HP> d) {
  HMat<D> m = HMat<D>::zero();
  int i = 0;
  for (const auto& x : d) {
    m(i, i) = x;
    ++i;
  }
  return m;
}

/// Condition number of a (complex) eigenvector basis after normalizing its columns.
template <int D>
double unitColumnCondition(Eigen::Matrix<std::complex<double>, D, D> V) {
  for (int j = 0; j < D; ++j) V.col(j).normalize();
  Eigen::JacobiSVD<Eigen::Matrix<std::complex<double>, D, D>> svd(V);
  const auto s = svd.singularValues();
  return s(0) / s(D - 1);
}

}  // namespace fam

// ---------------------------------------------------------------------------------------------
/// Eigenvalue 1 +- 1e-k (k = 3..14) in a non-diagonal basis (condition <= 6), with a random
/// translation: the regime where `(1 - L)^-1 t` (the fixed point) cancels catastrophically.
/// 2D: {1 +- e, 2.5}, {1 +- e, 0.4}; 3D: {1 +- e, 0.5, 2.2}, {1 +- e} + complex pair 1.3 e^(+-0.8i).
template <int D>
std::vector<Sample<D>> eigenvalueNearOneFamily(std::uint64_t seed = 101) {
  using namespace fam;
  std::mt19937_64 rng(seed);
  std::vector<Sample<D>> out;
  for (int k = 3; k <= 14; ++k)
    for (int sign : {1, -1})
      for (int variant = 0; variant < 2; ++variant) {
        const HP e1 = HP(1) + HP(sign) * pow10(k);
        HMat<D> Lam;
        std::string name;
        if constexpr (D == 2) {
          Lam = variant == 0 ? diagonal<2>({e1, HP(2.5)}) : diagonal<2>({e1, HP(0.4)});
          name = variant == 0 ? "{1+-e, 2.5}" : "{1+-e, 0.4}";
        } else {
          if (variant == 0) {
            Lam = diagonal<3>({e1, HP(0.5), HP(2.2)});
            name = "{1+-e, 0.5, 2.2}";
          } else {
            const HP rho = HP(1.3), th = HP(0.8);
            Lam = diagonal<3>({e1, rho * cos(th), rho * cos(th)});
            Lam(1, 2) = -rho * sin(th);
            Lam(2, 1) = rho * sin(th);
            name = "{1+-e, 1.3 e^(+-0.8i)}";
          }
        }
        const HMat<D> V = mildBasis<D>(rng);
        Sample<D> s;
        s.variant = name + (sign > 0 ? " +" : " -");
        s.param = k;
        s.A = Affine<D>(round<D>(similar<D>(V, Lam)), randomTranslation<D>(rng));
        out.push_back(s);
      }
  return out;
}

// ---------------------------------------------------------------------------------------------
/// Rotations by pi - 1e-k (k = 3..14) with a random translation.
/// 2D: counter-clockwise and clockwise exact-form rotations [c -s; s c] (c, s rounded once),
/// a rotation scaled by 2, and a rotation in a skewed basis (rounding perturbs it in a generic
/// direction). 3D: about a random axis, and about the z axis.
template <int D>
std::vector<Sample<D>> rotationNearHalfTurnFamily(std::uint64_t seed = 202) {
  using namespace fam;
  std::mt19937_64 rng(seed);
  std::vector<Sample<D>> out;
  for (int k = 3; k <= 14; ++k) {
    const HP theta = hpPi() - pow10(k);
    const HP c = cos(theta), s = sin(theta);
    if constexpr (D == 2) {
      const HMat<2> I = HMat<2>::identity();
      HMat<2> R = HMat<2>::zero();
      R(0, 0) = c;
      R(0, 1) = -s;
      R(1, 0) = s;
      R(1, 1) = c;
      HMat<2> Rcw = R;
      Rcw(0, 1) = s;
      Rcw(1, 0) = -s;
      const HMat<2> V = mildBasis<2>(rng);
      const std::vector<std::pair<std::string, HMat<2>>> vs = {
          {"R(pi-d) ccw", R},
          {"R(pi-d) cw", Rcw},
          {"2 R(pi-d)", HP(2) * R},
          {"V R(pi-d) V^-1", similar<2>(V, R)}};
      (void)I;
      for (const auto& [name, m] : vs) {
        Sample<2> smp;
        smp.variant = name;
        smp.param = k;
        smp.A = Affine<2>(round<2>(m), randomTranslation<2>(rng));
        out.push_back(smp);
      }
    } else {
      for (int variant = 0; variant < 2; ++variant) {
        HP a[3];
        if (variant == 0) {
          Eigen::Vector3d ax;
          do {
            for (int i = 0; i < 3; ++i) ax(i) = uniform(rng, -1, 1);
          } while (ax.norm() < 0.3);
          const HP n = sqrt(HP(ax(0)) * ax(0) + HP(ax(1)) * ax(1) + HP(ax(2)) * ax(2));
          for (int i = 0; i < 3; ++i) a[i] = HP(ax(i)) / n;
        } else {
          a[0] = 0;
          a[1] = 0;
          a[2] = 1;
        }
        // Rodrigues: R = c 1 + s [a]x + (1 - c) a a^T
        HMat<3> R;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) R(i, j) = (HP(1) - c) * a[i] * a[j] + (i == j ? c : HP(0));
        R(0, 1) -= s * a[2];
        R(1, 0) += s * a[2];
        R(0, 2) += s * a[1];
        R(2, 0) -= s * a[1];
        R(1, 2) -= s * a[0];
        R(2, 1) += s * a[0];
        Sample<3> smp;
        smp.variant = variant == 0 ? "random axis" : "z axis";
        smp.param = k;
        smp.A = Affine<3>(round<3>(R), randomTranslation<3>(rng));
        out.push_back(smp);
      }
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
/// Near the identity: A = [1 + e E_L | e E_t] with |[E_L | E_t]|_F = 1 and e = 1e-k, k = 1..14
/// (three random directions per k, and one with E_L skew-symmetric: a small rigid motion).
template <int D>
std::vector<Sample<D>> nearIdentityFamily(std::uint64_t seed = 303) {
  using namespace fam;
  std::mt19937_64 rng(seed);
  std::vector<Sample<D>> out;
  for (int k = 1; k <= 14; ++k) {
    const double e = std::pow(10.0, -k);
    for (int variant = 0; variant < 4; ++variant) {
      Eigen::Matrix<double, D, D + 1> E;
      for (int i = 0; i < D; ++i)
        for (int j = 0; j <= D; ++j) E(i, j) = uniform(rng, -1, 1);
      if (variant == 3) {
        const Eigen::Matrix<double, D, D> S = E.template leftCols<D>();
        E.template leftCols<D>() = 0.5 * (S - S.transpose());
      }
      E /= E.norm();
      Eigen::Matrix<double, D, D + 1> m = e * E;
      m.template leftCols<D>() += Eigen::Matrix<double, D, D>::Identity();
      Sample<D> s;
      s.variant = variant == 3 ? "rigid" : "general";
      s.param = k;
      s.A = Affine<D>::fromMatrix(m);
      out.push_back(s);
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
/// Jordan blocks perturbed by eta = +-1e-k (k = 3..14) in a mild random basis, random translation.
/// 2D: [lam 1; eta lam], lam = 1 (a perturbed shear: eigenvalues 1 +- sqrt(eta)) and lam = 1.6.
/// 3D: [lam 1 0; 0 lam 1; eta 0 lam] (a perturbed triple block) with lam = 1 and 0.8, and
/// [0.7 1 0; eta 0.7 0; 0 0 2.1] (a perturbed double block). eta > 0: close real eigenvalues;
/// eta < 0: a complex pair with a tiny angle.
template <int D>
std::vector<Sample<D>> jordanLikeFamily(std::uint64_t seed = 404) {
  using namespace fam;
  std::mt19937_64 rng(seed);
  std::vector<Sample<D>> out;
  for (int k = 3; k <= 14; ++k)
    for (int sign : {1, -1})
      for (int variant = 0; variant < (D == 2 ? 2 : 3); ++variant) {
        const HP eta = HP(sign) * pow10(k);
        HMat<D> J = HMat<D>::zero();
        std::string name;
        if constexpr (D == 2) {
          const HP lam = variant == 0 ? HP(1) : HP(1.6);
          J(0, 0) = lam;
          J(1, 1) = lam;
          J(0, 1) = 1;
          J(1, 0) = eta;
          name = variant == 0 ? "[1 1; eta 1]" : "[1.6 1; eta 1.6]";
        } else {
          if (variant < 2) {
            const HP lam = variant == 0 ? HP(1) : HP(0.8);
            for (int i = 0; i < 3; ++i) J(i, i) = lam;
            J(0, 1) = 1;
            J(1, 2) = 1;
            J(2, 0) = eta;
            name = variant == 0 ? "triple lam=1" : "triple lam=0.8";
          } else {
            J(0, 0) = HP(0.7);
            J(1, 1) = HP(0.7);
            J(0, 1) = 1;
            J(1, 0) = eta;
            J(2, 2) = HP(2.1);
            name = "double 0.7, 2.1";
          }
        }
        const HMat<D> V = mildBasis<D>(rng);
        Sample<D> s;
        s.variant = name + (sign > 0 ? " eta>0" : " eta<0");
        s.param = k;
        s.A = Affine<D>(round<D>(similar<D>(V, J)), randomTranslation<D>(rng));
        out.push_back(s);
      }
  return out;
}

// ---------------------------------------------------------------------------------------------
/// Eigenvector bases with condition numbers ~1e0 .. 1e12 (k = 0..12), random translation.
/// Real eigenvalues {0.7, 1.9} (3D: and 3.1) with two nearly parallel eigenvectors: the block
/// [0.7 X; 0 1.9] with X = 0.6 * 10^k; a complex pair 0.5 +- 1.2i in the basis diag(1, 1/c):
/// [0.5 -1.2c; 1.2/c 0.5] (3D: with 2.4 as third eigenvalue). In 3D the blocks are conjugated by
/// a fixed mixing of coordinates 1 and 3. The large entries stay in one column, so the linear
/// part is far from singular by steady's Hadamard-ratio test (ratio ~ 1/c > 1e-14).
template <int D>
std::vector<Sample<D>> illConditionedBasisFamily(std::uint64_t seed = 505) {
  using namespace fam;
  using CMat = Eigen::Matrix<std::complex<double>, D, D>;
  std::mt19937_64 rng(seed);
  std::vector<Sample<D>> out;
  for (int k = 0; k <= 12; ++k)
    for (int variant = 0; variant < 2; ++variant) {
      const HP c = 1 / pow10(k);
      HMat<D> B = HMat<D>::zero();
      CMat VB = CMat::Zero();  // eigenvectors of B (columns)
      const std::complex<double> I(0, 1);
      std::string name;
      if (variant == 0) {
        const HP X = HP(0.6) * c;
        B(0, 0) = HP(0.7);
        B(0, 1) = X;
        B(1, 1) = HP(1.9);
        VB(0, 0) = 1;
        VB(0, 1) = static_cast<double>(X);
        VB(1, 1) = 1.2;
        name = "real {0.7, 1.9" + std::string(D == 3 ? ", 3.1}" : "}");
      } else {
        B(0, 0) = HP(0.5);
        B(1, 1) = HP(0.5);
        B(0, 1) = HP(-1.2) * c;
        B(1, 0) = HP(1.2) / c;
        VB(0, 0) = 1;
        VB(0, 1) = 1;
        VB(1, 0) = -I / static_cast<double>(c);
        VB(1, 1) = I / static_cast<double>(c);
        name = "complex 0.5+-1.2i" + std::string(D == 3 ? ", 2.4" : "");
      }
      HMat<D> L = B;
      CMat V = VB;
      if constexpr (D == 3) {
        L(2, 2) = variant == 0 ? HP(3.1) : HP(2.4);
        V(2, 2) = 1;
        // mixing of coordinates 1 and 3 (fixes e2, so the large column stays alone)
        HMat<3> S = HMat<3>::identity();
        S(0, 2) = HP(0.5);
        S(2, 0) = HP(0.3);
        L = similar<3>(S, L);
        Eigen::Matrix3cd Sc = toEigen<HP, 3>(S).template cast<std::complex<double>>();
        V = Sc * V;
      }
      Sample<D> s;
      s.variant = name;
      s.param = k;
      s.basis_cond = unitColumnCondition<D>(V);
      s.A = Affine<D>(round<D>(L), randomTranslation<D>(rng));
      out.push_back(s);
    }
  return out;
}

/// The names of the hard families, in report order.
inline const std::vector<std::string>& familyNames() {
  static const std::vector<std::string> names = {"EigenvalueNearOne", "RotationNearHalfTurn",
                                                 "NearIdentity", "JordanLike",
                                                 "IllConditionedBasis"};
  return names;
}

template <int D>
std::vector<Sample<D>> familyByName(const std::string& name) {
  if (name == "EigenvalueNearOne") return eigenvalueNearOneFamily<D>();
  if (name == "RotationNearHalfTurn") return rotationNearHalfTurnFamily<D>();
  if (name == "NearIdentity") return nearIdentityFamily<D>();
  if (name == "JordanLike") return jordanLikeFamily<D>();
  if (name == "IllConditionedBasis") return illConditionedBasisFamily<D>();
  return {};
}

}  // namespace steady::oracle
