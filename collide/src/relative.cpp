// Contact functions of two moving meshes (see relative.hpp for the formulas and bounds).
#include "relative.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <cmath>

namespace steady::detail {

namespace {
constexpr double kUlp = 0x1.0p-52;
// Safety factor on the rounding tolerances of the relative functions: they chain two powers, an
// inverse and a few products, each accurate to a few ulps of the magnitudes summed here.
constexpr double kRelEps = 4.0;
}  // namespace

RelativeRoots::RelativeRoots(const Span3& a, double sa0, double da, double mu_a, const Span3& b, double sb0,
                             double db, double mu_b, const RootOptions& options)
    : a_(a), b_(b), sa0_(sa0), da_(da), sb0_(sb0), db_(db), options_(options) {
  Ma_ = da * a.log().M;
  Mb_ = db * b.log().M;
  ua_ = da * a.log().u;
  ub_ = db * b.log().u;
  dM_ = Ma_ - Mb_;
  mua_ = std::abs(da) * mu_a;
  mub_ = std::abs(db) * mu_b;
  dMn_ = std::min(dM_.norm(), mua_ + mub_);  // Frobenius bounds the spectral norm, so does the sum
}

struct RelPointFn {
  using Vector = Eigen::Vector3d;
  struct Sample {
    double g, gp, eps, epsd;
    double nbn, mbnb, dvn, van;
  };
  const RelativeRoots& R;
  Vector p, n;
  double h, pn, nn, ulps;

  Sample sample(double tau) const {
    const Affine3 PA = R.poseA(tau), PB = R.poseB(tau);
    const Eigen::Matrix3d LBi = PB.linear().inverse();
    const Vector x = PA.applyPoint(p);
    const Vector z = LBi * (x - PB.translation());
    const Vector nb = LBi.transpose() * n;
    const Vector va = R.Ma_ * x + R.ua_, vb = R.Mb_ * x + R.ub_, dv = va - vb;
    Sample s;
    s.g = n.dot(z) - h;
    s.gp = nb.dot(dv);
    s.nbn = nb.norm();
    s.mbnb = (R.Mb_.transpose() * nb).norm();
    s.dvn = dv.norm();
    s.van = va.norm();
    const double xs = x.norm() + pn * PA.linear().norm() + PA.translation().norm();
    const double zs = z.norm() + LBi.norm() * (xs + PB.translation().norm());
    s.eps = kRelEps * ulps * (nn * zs + std::abs(h));
    s.epsd = kRelEps * ulps * s.nbn * (R.dMn_ * xs + s.dvn + R.ua_.norm() + R.ub_.norm());
    return s;
  }
  Bounds bounds(const Sample& c, double r) const {
    const double za = r * R.mua_, zb = r * R.mub_;
    const double K = kBoundSlack * std::exp(zb) *
                     (c.mbnb * (c.dvn + R.dMn_ * c.van * r * phi1(za)) + c.nbn * R.dMn_ * std::exp(za) * c.van);
    Bounds b;
    b.D = K * r;
    b.reach = std::abs(c.gp) * r + 0.5 * K * r * r;
    return b;
  }
};

struct RelEdgeFn {
  using Vector = Eigen::Vector3d;
  struct Sample {
    double g, gp, eps, epsd;
    double beta, ea, va, dv, w, nn;  // |L_b^-1|_F, |ea|, |Va(xa)|, |dV(xa)|, |b0 - z0|, |ez x d|
    double maea, dmea, cea;          // |Ma ea|, |dM ea|, |C ea| with C = dM Ma - Mb dM
  };
  const RelativeRoots& R;
  Vector a0, ea0, b0, d;
  Eigen::Matrix3d C;  // dM Ma - Mb dM
  double a0n, ea0n, dn, c1, ulps;  // c1 = |C|_F

  Sample sample(double tau) const {
    const Affine3 PA = R.poseA(tau), PB = R.poseB(tau);
    const Eigen::Matrix3d Bi = PB.linear().inverse();
    const Vector xa = PA.applyPoint(a0), ea = PA.linear() * ea0;
    const Vector z0 = Bi * (xa - PB.translation()), ez = Bi * ea;
    const Vector va = R.Ma_ * xa + R.ua_, dv = va - (R.Mb_ * xa + R.ub_);
    const Vector w = b0 - z0;
    const Vector n = ez.cross(d);
    const Vector dez = Bi * (R.dM_ * ea), dz = Bi * dv;
    Sample s;
    s.g = n.dot(w);
    s.gp = dez.cross(d).dot(w) - n.dot(dz);
    s.beta = Bi.norm();
    s.ea = ea.norm();
    s.va = va.norm();
    s.dv = dv.norm();
    s.w = w.norm();
    s.nn = n.norm();
    s.maea = (R.Ma_ * ea).norm();
    s.dmea = (R.dM_ * ea).norm();
    s.cea = (C * ea).norm();
    const double xs = xa.norm() + PA.linear().norm() * a0n + PA.translation().norm();
    const double zs = z0.norm() + s.beta * (xs + PB.translation().norm());
    const double es = ez.norm() + s.beta * (s.ea + PA.linear().norm() * ea0n);
    s.eps = kRelEps * ulps * dn * es * (s.w + zs + b0.norm());
    s.epsd = kRelEps * ulps * dn *
             ((dez.norm() + s.beta * R.dMn_ * es) * (s.w + zs + b0.norm()) +
              es * (dz.norm() + s.beta * (R.dMn_ * xs + R.ua_.norm() + R.ub_.norm())));
    return s;
  }
  // Every factor is bounded from its value at c: |L_b^-1(tau)| <= |L_b^-1(c)| e^(r mu_b); a
  // matrix X applied to ea(tau) moves by at most |X| |Ma ea_c| r phi1(r mu_a) (ea' = Ma ea), which
  // keeps the bound zero for edges that stay parallel or move with b.
  Bounds bounds(const Sample& c, double r) const {
    const double za = r * R.mua_, zb = r * R.mub_, GA = std::exp(za), GB = std::exp(zb);
    const double bt = c.beta * GB;                           // |L_b^-1| over the interval
    const double DV = c.dv + R.dMn_ * c.va * r * phi1(za);   // |dV(xa)|
    const double W = c.w + r * bt * DV;                      // |b0 - z0|
    const double step = c.maea * r * phi1(za);               // |ea(tau) - ea_c|
    const double DE = c.dmea + R.dMn_ * step;                // |dM ea|
    const double CE = c.cea + c1 * step;                     // |C ea|
    const double N = c.nn + dn * r * bt * DE;                // |ez x d|
    const double K = kBoundSlack * (dn * (bt * CE * W + 2 * bt * DE * bt * DV) +
                                    N * bt * (R.dMn_ * GA * c.va + R.mub_ * DV));
    Bounds b;
    b.D = K * r;
    b.reach = std::abs(c.gp) * r + 0.5 * K * r * r;
    return b;
  }
};

std::size_t RelativeRoots::pointPlane(const Vector& p, const Vector& n, double h, double t0, double t1,
                                      std::vector<ContactRoot>& out) const {
  const RelPointFn f{*this, p, n, h, p.norm(), n.norm(), options_.value_ulps * kUlp};
  const std::size_t before = out.size();
  isolateRoots(f, t0, t1, options_, [&](const ContactRoot& r) {
    return appendMerged(out, before, r, options_.time_tolerance);
  });
  return out.size() - before;
}

std::size_t RelativeRoots::edgeEdge(const Vector& a0, const Vector& a1, const Vector& b0, const Vector& b1,
                                    double t0, double t1, std::vector<ContactRoot>& out) const {
  const Vector ea0 = a1 - a0, d = b1 - b0;
  const Eigen::Matrix3d C = dM_ * Ma_ - Mb_ * dM_;
  const RelEdgeFn f{*this, a0, ea0, b0, d, C, a0.norm(), ea0.norm(), d.norm(), C.norm(), options_.value_ulps * kUlp};
  const std::size_t before = out.size();
  isolateRoots(f, t0, t1, options_, [&](const ContactRoot& r) {
    return appendMerged(out, before, r, options_.time_tolerance);
  });
  return out.size() - before;
}

}  // namespace steady::detail
