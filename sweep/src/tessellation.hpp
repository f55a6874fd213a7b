#pragma once
// Time grids and piece counts of swept strips, shared by the candidate surface and the sweep
// cycle. The error bound they guarantee is derived at the top of candidates.cpp:
//   (1) chord of a trajectory over a step h:  h²/8 μ e^(hμ) V <= ε/2,
//   (2) twist of a cell of a segment of length |e| cut into m pieces:  h μ e^(hμ) |e| / (4m) <= ε/2,
// with μ >= |M|_2 and V the largest speed of the points at the step's start. Both hold with the
// sharper factors |M v| for μ V and |M e| for μ |e|: X''(τ) = L^(τ-τk) M v(X(τk)) and the twist
// integrand is L^(τ-τk) M e_k, since M and L^σ commute (|L^σ| <= e^(|σ|μ)). These vanish for
// translations and for segments in the kernel of M (planar strips need no pieces).
#include <steady/core/error.hpp>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>

namespace steady::sweep::detail {

// An upper bound of the spectral norm |M|_2: the square root of the largest eigenvalue of
// MᵀM, inflated to cover its rounding, and never above the Frobenius norm.
inline double spectralBound(const Eigen::Matrix3d& M) {
  const double frob = M.norm();
  if (frob == 0) return 0.0;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M.transpose() * M, Eigen::EigenvaluesOnly);
  const double lmax = es.eigenvalues().maxCoeff();
  return std::min(frob, std::sqrt(std::max(lmax, 0.0)) * (1 + 1e-10) + 1e-12 * frob);
}

// The next grid time after tau (at most 1): the largest step h <= 1 - tau meeting (1), where
// `accel` >= |M v| over the points at tau (μ V, or the sharper max |M v|; inflated by 1e-12 for
// its rounding). Returns exactly 1.0 at the end.
inline double nextGridTime(double tau, double accel, double mu, double eps) {
  const double Ab = accel * (1 + 1e-12), rem = 1.0 - tau;
  auto chord = [&](double h) { return h * h / 8.0 * std::exp(h * mu) * Ab; };
  double h = rem;
  if (chord(h) > 0.5 * eps) {
    h = std::min(rem, std::sqrt(4.0 * eps / Ab));
    while (chord(h) > 0.5 * eps) h *= 0.97;
  }
  return h >= rem ? 1.0 : tau + h;
}

// The twist term of (2) for one cell with m = 1: h e^(hμ) |M e| / 4, where `me` >= |M e_k|
// (μ |e_k|, or the sharper |M e_k|; inflated for rounding).
inline double cellTwist(double h, double mu, double me) {
  return h * std::exp(h * mu) * me * (1 + 1e-12) / 4.0;
}

// The number of pieces m meeting (2) for the largest cell twist of a segment; throws
// Error(InvalidArgument) beyond max_steps. `what` names the segment in the message.
inline int piecesFor(double twist, double eps, int max_steps, const std::string& what) {
  const double m_real = std::ceil(twist / (0.5 * eps));
  if (!(m_real <= max_steps))
    throw Error(ErrorCode::InvalidArgument, what + " needs more than " + std::to_string(max_steps) +
                                                " pieces for tolerance " + std::to_string(eps) +
                                                "; raise the tolerance (or max_steps)");
  return std::max(1, static_cast<int>(m_real));
}

}  // namespace steady::sweep::detail
