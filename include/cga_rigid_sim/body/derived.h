// Quantities derived from a body's state: pose, world twist, momenta and energies.
// All results are in world axes (suffix _W) unless the name says otherwise.
#pragma once

#include <Eigen/Core>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/body/inertia.h"

namespace cga_rigid_sim {
namespace dynamics {

/// Centre-of-mass position x_c.
inline Eigen::Vector3d comPosition_W(const BodyState& s, double lambda) {
  return s.M_WB.translation(lambda);
}
/// Centre-of-mass velocity R v_B.
inline Eigen::Vector3d comVelocity_W(const BodyState& s, double lambda) {
  return s.M_WB.transformVector(s.omega_B.linear(lambda));
}
/// Angular velocity vector R w_B.
inline Eigen::Vector3d angularVelocity_W(const BodyState& s) {
  return s.M_WB.transformVector(s.omega_B.angular());
}
/// Linear momentum m v.
inline Eigen::Vector3d linearMomentum_W(const Inertia& I, const BodyState& s, double lambda) {
  return I.mass() * comVelocity_W(s, lambda);
}
/// Angular momentum about the centre of mass, R (J w_B) R̃ (the bivector L = R I(Ω_B) R̃ as a
/// vector).
inline Eigen::Vector3d angularMomentumCom_W(const Inertia& I, const BodyState& s) {
  return s.M_WB.transformVector(I.principalMoments().cwiseProduct(s.omega_B.angular()));
}
/// Angular momentum about the world origin, x_c × m v + L_com.
inline Eigen::Vector3d angularMomentumOrigin_W(const Inertia& I, const BodyState& s,
                                               double lambda) {
  return comPosition_W(s, lambda).cross(linearMomentum_W(I, s, lambda)) +
         angularMomentumCom_W(I, s);
}
/// Kinetic energy −½ Ω·I(Ω) = ½ m v² + ½ w·J w.
inline double kineticEnergy(const Inertia& I, const BodyState& s, double lambda) {
  return I.kineticEnergy(s.omega_B, lambda);
}
/// Potential energy in the uniform field g (acceleration, world axes): V = −m g·x_c.
inline double potentialEnergy(const Inertia& I, const BodyState& s, const Eigen::Vector3d& g_W,
                              double lambda) {
  return -I.mass() * g_W.dot(comPosition_W(s, lambda));
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
