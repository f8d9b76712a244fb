#include "cga_rigid_sim/curved/curved_space.h"

#include <Eigen/LU>
#include <cmath>
#include <sstream>

namespace cga_rigid_sim {
namespace dynamics {

Result<CurvedSpace> CurvedSpace::fromRadius(double R) {
  if (!std::isfinite(R) || R == 0.0) {
    std::ostringstream os;
    os << "must be a finite nonzero radius in m (> 0 spherical, < 0 hyperbolic), got " << R;
    return Error("curvature", "", os.str());
  }
  return CurvedSpace(R);
}

cga::Rotor4 CurvedSpace::translator(const Eigen::Vector3d& d) const {
  return cga::exp(cga::Bivector4(Eigen::Vector3d::Zero(), (-0.5 / rho()) * d), sigma_);
}

Eigen::Vector3d CurvedSpace::toChart(const Eigen::Vector4d& X) const {
  return (2.0 * R_ / (R_ - X[3])) * X.head<3>();
}

double CurvedSpace::chartScale(const Eigen::Vector3d& x) const {
  return 1.0 / (1.0 + 0.25 * curvature() * x.squaredNorm());
}

Eigen::Vector4d CurvedSpace::fromChart(const Eigen::Vector3d& x) const {
  const double k = 0.25 * curvature() * x.squaredNorm();
  Eigen::Vector4d X;
  X.head<3>() = x / (1.0 + k);
  X[3] = -R_ * (1.0 - k) / (1.0 + k);
  return X;
}

double CurvedSpace::chartDistance(const Eigen::Vector3d& x) const {
  const double t = x.norm() / (2.0 * rho());
  return 2.0 * rho() * (sigma_ > 0 ? std::atan(t) : std::atanh(t));
}

cga::Rotor4 CurvedSpace::rotorOfQuaternion(const Eigen::Quaterniond& q) {
  return cga::Rotor4::fromCoefficients({q.w(), -q.x(), -q.y(), -q.z(), 0, 0, 0, 0});
}

Result<cga::Rotor4> CurvedSpace::poseFromChart(const Eigen::Vector3d& x,
                                               const Eigen::Quaterniond& q) const {
  if (!x.allFinite() || !q.coeffs().allFinite())
    return Error("curved_pose", "position", "must be finite");
  if (sigma_ < 0 && x.norm() >= 2.0 * rho()) {
    std::ostringstream os;
    os << "must lie inside the Poincare ball of radius 2|R| = " << 2.0 * rho()
       << " m, |x| = " << x.norm() << " m";
    return Error("curved_pose", "position", os.str());
  }
  const double r = x.norm();
  const Eigen::Vector3d d =
      r > 0.0 ? Eigen::Vector3d((chartDistance(x) / r) * x) : Eigen::Vector3d::Zero();
  return cga::multiply(translator(d), rotorOfQuaternion(q.normalized()), sigma_);
}

void CurvedSpace::chartPose(const cga::Rotor4& psi, Eigen::Vector3d& x,
                            Eigen::Quaterniond& q) const {
  const Eigen::Matrix4d M = cga::toMatrix(psi, sigma_);
  const Eigen::Vector4d X = M * origin();
  x = toChart(X);
  // The differential of x = 2R y/(R − y4) applied to the body's axes f_i = ψ e_i ψ̃:
  //   dx(f) = 2R/(R − y4) · (f_y + y f_4/(R − y4)).
  const double a = 1.0 / (R_ - X[3]);
  Eigen::Matrix3d D;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector4d f = M.col(i);
    D.col(i) = (2.0 * R_ * a) * (f.head<3>() + (a * f[3]) * X.head<3>());
  }
  // D = c Q with Q a rotation (the chart is conformal): divide by c = det(D)^(1/3).
  q = Eigen::Quaterniond(Eigen::Matrix3d(D / std::cbrt(D.determinant())));
  q.normalize();
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
