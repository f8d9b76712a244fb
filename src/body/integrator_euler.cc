#include "cga_rigid_sim/body/integrator_euler.h"

namespace cga_rigid_sim {
namespace dynamics {

void EulerIntegrator::step(const Inertia& inertia, const Loads& loads, double lambda, double h,
                           BodyState& state) {
  const Eigen::Quaterniond& q = state.M_WB.rotation();
  const Eigen::Vector3d x = state.M_WB.translation(lambda);
  const Eigen::Vector3d& w = state.omega_B.rot;
  const Eigen::Vector3d& J = inertia.principalMoments();
  const Eigen::Vector3d v_W = q * state.omega_B.linear(lambda);

  // Loads at the old pose: torque in body axes, force in world axes.
  Eigen::Vector3d tau_B = Eigen::Vector3d::Zero(), f_W = Eigen::Vector3d::Zero();
  if (!loads.empty()) {
    cga::Moment T = loads.gravityMoment_B(inertia.mass(), state.M_WB, lambda);
    if (loads.hasApplied()) T += loads.appliedMoment_B(state.M_WB, lambda);
    tau_B = T.torque();
    f_W = q * T.force(lambda);
  }

  // q ← q + h ½ q ⊗ (0, w), then normalised.
  Eigen::Quaterniond qdot = q * Eigen::Quaterniond(0.0, w.x(), w.y(), w.z());
  Eigen::Quaterniond q_new(q.coeffs() + (0.5 * h) * qdot.coeffs());
  q_new.normalize();
  const Eigen::Vector3d w_new = w + h * (tau_B + J.cwiseProduct(w).cross(w)).cwiseQuotient(J);
  const Eigen::Vector3d v_new = v_W + (h / inertia.mass()) * f_W;
  const Eigen::Vector3d x_new = x + h * v_W;

  state.M_WB = cga::Motor::fromPose(q_new, x_new, lambda);
  state.omega_B = cga::Bivelocity::fromVelocities(w_new, q_new.conjugate() * v_new, lambda);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
