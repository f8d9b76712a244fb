#include "cga_rigid_sim/curved/curved_inertia.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace cga_rigid_sim {
namespace dynamics {

Result<CurvedInertia> CurvedInertia::fromSecondMoments(const std::string& body, double mass,
                                                       const Eigen::Vector4d& J,
                                                       const CurvedSpace& space) {
  if (!std::isfinite(mass) || mass <= 0.0)
    return Error("body '" + body + "'", "mass", "must be finite and > 0 kg");
  if (!J.allFinite() || (J.head<3>().array() < 0.0).any())
    return Error("body '" + body + "'", "second_moments", "must be finite and >= 0 kg m^2");
  if (J[3] <= 0.0) {
    std::ostringstream os;
    os << "body too large for the space: its spread sqrt(tr S / m) = "
       << std::sqrt(J.head<3>().sum() / mass) << " m reaches the radius |R| = " << space.rho()
       << " m (the 4-d moment J4 = m R^2 - tr S = " << J[3] << " kg m^2 must be > 0)";
    return Error("body '" + body + "'", "inertia", os.str());
  }
  CurvedInertia I;
  I.mass_ = mass;
  I.sigma_ = space.sigma();
  I.J_ = J;
  const double s = space.sigma();
  I.k_ = cga::Bivector4({J[1] + J[2], J[2] + J[0], J[0] + J[1]},
                        {J[3] + s * J[0], J[3] + s * J[1], J[3] + s * J[2]});
  static const char* const kPlane[6] = {"e23", "e31", "e12", "e14", "e24", "e34"};
  for (int p = 0; p < 6; ++p) {
    if (!(I.k_[p] > 0.0)) {
      std::ostringstream os;
      os << "the moment of the plane " << kPlane[p] << " must be > 0, got " << I.k_[p]
         << " kg m^2 (a body with no extent in two directions, or too large for the space)";
      return Error("body '" + body + "'", "inertia", os.str());
    }
  }
  const double smax = J.head<3>().maxCoeff(), smin = J.head<3>().minCoeff();
  I.isotropic_ = smax - smin <= kEqualMomentsRelTol * smax;
  return I;
}

Result<CurvedInertia> CurvedInertia::fromEuclidean(const std::string& body,
                                                   const Inertia& euclidean,
                                                   const CurvedSpace& space) {
  const Eigen::Vector3d& Ic = euclidean.principalMoments();
  const double half_trace = 0.5 * Ic.sum();
  // S_i = ½ tr I − I_i ≥ 0 by the triangle inequality (Inertia validated it; clamp round-off).
  const Eigen::Vector3d S = (Eigen::Vector3d::Constant(half_trace) - Ic).cwiseMax(0.0);
  const double m = euclidean.mass();
  Eigen::Vector4d J;
  J.head<3>() = S;
  J[3] = m * space.radius() * space.radius() - space.sigma() * S.sum();
  return fromSecondMoments(body, m, J, space);
}

cga::Bivector4 CurvedInertia::momentum(const cga::Bivector4& omega) const {
  return cga::Bivector4(k_.rot.cwiseProduct(omega.rot),
                        sigma_ * k_.trans.cwiseProduct(omega.trans));
}

cga::Bivector4 CurvedInertia::velocity(const cga::Bivector4& L) const {
  return cga::Bivector4(L.rot.cwiseQuotient(k_.rot), sigma_ * L.trans.cwiseQuotient(k_.trans));
}

double CurvedInertia::kineticEnergy(const cga::Bivector4& omega) const {
  return 0.5 * (k_.rot.dot(omega.rot.cwiseAbs2()) + k_.trans.dot(omega.trans.cwiseAbs2()));
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
