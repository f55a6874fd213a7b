#pragma once
// Contact functions of two meshes that both move, over a time interval on which each follows one
// SAM span. With local time tau in [0, 1] on the interval, mesh a's span parameter is
// sa(tau) = sa0 + da tau and b's is sb(tau) = sb0 + db tau; world positions are P_a(tau) p and
// P_b(tau) q for points p, q given at their span's start (P = the span's A^s). The relative motion
// P_b^-1 P_a is not a SAM, but its velocity is again bounded from its values at the middle of an
// interval (see the bounds below), so the isolation of isolate.hpp applies unchanged.
//
// Point/plane (a vertex of a against a face of b, in b's span-start frame):
//   g(tau) = n . (P_b^-1 P_a p) - h,   g' = (L_b^-T n) . dV(x),   x = P_a p (world),
//   dV(x) = Va(x) - Vb(x) with the interval-scaled fields Va = da (M_a x + u_a), Vb likewise;
//   g'' = -(Mb^T nb) . dV(x) + nb . (dM Va(x)),  nb = L_b^-T n, dM = da M_a - db M_b.
// Edge/edge (in b's span-start frame, where b's edge (b0, d) is still): with N = L_b^-1 L_a,
//   g(tau) = (N ea0 x d) . (b0 - P_b^-1 P_a a0),
//   g'  = (L_b^-1 dM ea x d) . w - (ez x d) . L_b^-1 dV(xa),   ez = N ea0, w = b0 - z0,
//   g'' = (L_b^-1 (dM Ma - Mb dM) ea x d) . w - 2 (L_b^-1 dM ea x d) . L_b^-1 dV
//         - (ez x d) . L_b^-1 (dM Va - Mb dV),
// every term carrying dM or dV, so bodies carried together (dM = 0, dV = 0) give g' = g'' = 0.
#include "isolate.hpp"

#include <steady/core/ear.hpp>

#include <Eigen/Core>

#include <vector>

namespace steady::detail {

class RelativeRoots {
 public:
  using Vector = Eigen::Vector3d;

  // Spans of a and b with their parameter maps over the interval; norms of M are spectral
  // upper bounds (SpanRoots::logNorm()).
  RelativeRoots(const Span3& a, double sa0, double da, double mu_a, const Span3& b, double sb0, double db,
                double mu_b, const RootOptions& options);

  // Roots in tau in [t0, t1] of the vertex p of a (at a's span start) against the plane n.x = h
  // of b (in b's span-start frame).
  std::size_t pointPlane(const Vector& p, const Vector& n, double h, double t0, double t1,
                         std::vector<ContactRoot>& out) const;
  // Roots of the coplanarity of edge (a0, a1) of a and edge (b0, b1) of b (span-start frames).
  std::size_t edgeEdge(const Vector& a0, const Vector& a1, const Vector& b0, const Vector& b1, double t0,
                       double t1, std::vector<ContactRoot>& out) const;

  // Poses at local time tau.
  Affine3 poseA(double tau) const { return a_.power(sa0_ + da_ * tau); }
  Affine3 poseB(double tau) const { return b_.power(sb0_ + db_ * tau); }

 private:
  friend struct RelPointFn;
  friend struct RelEdgeFn;
  const Span3& a_;
  const Span3& b_;
  double sa0_, da_, sb0_, db_;
  Eigen::Matrix3d Ma_, Mb_, dM_;  // interval-scaled logs and their difference
  Vector ua_, ub_;
  double mua_, mub_, dMn_;  // spectral bounds of the scaled Ma, Mb and of dM
  RootOptions options_;
};

}  // namespace steady::detail
