#pragma once
// Time grids and piece counts of swept strips, shared by the candidate surface and the sweep
// cycle. The error bound they guarantee is derived at the top of candidates.cpp:
//   (1) chord of a trajectory over a step h:  h²/8 max_σ |L^σ M v| <= ε/2,
//   (2) twist of a cell of a segment e cut into m pieces:  h max_σ |L^σ M e| / (4m) <= ε/2,
// over σ in [0, h], with X''(τ) = L^(τ-τk) M v(X(τk)) and the twist integrand L^(τ-τk) M e_k
// (M and L^σ commute). `flowFactor` bounds max_σ |L^σ w| / |w| for w = M v and w = M e: by
// e^(hμ) (μ >= |M|_2, |L^σ| <= e^(σμ)), or, where it is less than half of that, by the Taylor
// bound below, which is exact for shears. Both terms vanish for translations and for segments
// in the kernel of M (planar strips need no pieces).
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

// |w|, |M w| and |M² w| for one vector w (or the maxima of each over several vectors).
struct FlowNorms {
  double w = 0, mw = 0, m2w = 0;
  // The norms of w, M w and M² w.
  static FlowNorms of(const Eigen::Matrix3d& M, const Eigen::Vector3d& w) {
    const Eigen::Vector3d mw = M * w;
    return {w.norm(), mw.norm(), (M * mw).norm()};
  }
  // The componentwise maximum with other norms.
  void include(const FlowNorms& o) {
    w = std::max(w, o.w), mw = std::max(mw, o.mw), m2w = std::max(m2w, o.m2w);
  }
};

// A factor G with |L^σ w| = |e^(σM) w| <= G |w| over 0 <= σ <= h (μ >= |M|_2): e^(hμ), or the
// Taylor bound (|w| + h |M w| + h²/2 e^(hμ) |M² w|) / |w| (from e^(σM) w = w + σ M w +
// ∫_0^σ (σ - s) e^(sM) M² w ds) where that is less than half of it. The Taylor bound is exact
// when M² w = 0 (a shear's velocity differences), where e^(hμ) overestimates: 9.5 for a shear
// of 2.25 over one step, and the strips of an L-shaped prism along such a span got 1,487 pieces
// instead of 157, and the sweep took 12 s instead of 0.16 s (a sweep fuzz input). Only where
// it gains 2x or more, and the callers keep their old expressions, so that every other grid
// stays the same to the last bit: the smaller gains (1.0x to 2x, common on rotations with a
// scaling) would change the grids of the recorded campaign cases by which the test suite
// reaches the sweep's rare paths (re-sweeps, kept walls, rims), for little. (A grid that
// differed by 1e-13 relative, from a step guess not inflated like before, gave the bracket
// polySAM of `FaceThroughTheScrewAxisOnAPolySam` 4 self-intersecting face pairs, reported by
// its check: docs/history.md, thirty-third round.)
inline double flowFactor(double h, double mu, const FlowNorms& n) {
  const double grow = std::exp(h * mu);
  if (!(n.w > 0)) return grow;
  const double taylor = 1 + (h * n.mw + 0.5 * h * h * grow * n.m2w) / n.w;
  return taylor < 0.5 * grow ? taylor : grow;
}

// The next grid time after tau (at most 1): the largest step h <= 1 - tau meeting (1), where
// `accel` holds |M v|, |M² v| and |M³ v| (maxima over the points at tau; inflated by 1e-12 for
// their rounding). Returns exactly 1.0 at the end.
inline double nextGridTime(double tau, const FlowNorms& accel, double mu, double eps) {
  const double Ab = accel.w * (1 + 1e-12), rem = 1.0 - tau;
  auto chord = [&](double h) { return h * h / 8.0 * flowFactor(h, mu, accel) * Ab; };
  double h = rem;
  if (chord(h) > 0.5 * eps) {
    h = std::min(rem, std::sqrt(4.0 * eps / Ab));
    while (chord(h) > 0.5 * eps) h *= 0.97;
  }
  return h >= rem ? 1.0 : tau + h;
}

// The twist term of (2) for one cell with m = 1: h max_σ |L^σ M e| / 4, where `me` holds
// |M e|, |M² e| and |M³ e| of the segment e at the cell's start (inflated by 1e-12 for their
// rounding).
inline double cellTwist(double h, double mu, const FlowNorms& me) {
  return h * flowFactor(h, mu, me) * me.w * (1 + 1e-12) / 4.0;
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
