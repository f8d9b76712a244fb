#include "cga_rigid_sim/body/integrator_rk4.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

// The state of the ODE: the rotor as a (not necessarily unit) quaternion, w in body axes, and
// the centre of mass position and velocity in world axes.
struct Y {
  Eigen::Vector4d q;  // (w, x, y, z)
  Eigen::Vector3d w, x, v;
  Y operator+(const Y& o) const { return {q + o.q, w + o.w, x + o.x, v + o.v}; }
  Y operator*(double k) const { return {k * q, k * w, k * x, k * v}; }
};

Eigen::Quaterniond toQuaternion(const Eigen::Vector4d& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}

// ẏ at y. Loads are evaluated at the stage pose with the rotor normalised (the loads rotate
// vectors with it).
Y derivative(const Inertia& inertia, const Loads& loads, double lambda, const Y& y) {
  const Eigen::Quaterniond q = toQuaternion(y.q);
  const Eigen::Vector3d& J = inertia.principalMoments();
  Eigen::Vector3d tau_B = Eigen::Vector3d::Zero(), f_W = Eigen::Vector3d::Zero();
  if (!loads.empty()) {
    const Eigen::Quaterniond qn = q.normalized();
    const cga::Motor M = cga::Motor::fromPose(qn, y.x, lambda);
    cga::Moment T = loads.gravityMoment_B(inertia.mass(), M, lambda);
    if (loads.hasApplied()) T += loads.appliedMoment_B(M, lambda);
    tau_B = T.torque();
    f_W = qn * T.force(lambda);
  }
  const Eigen::Quaterniond qdot = q * Eigen::Quaterniond(0.0, y.w.x(), y.w.y(), y.w.z());
  Y d;
  d.q = 0.5 * Eigen::Vector4d(qdot.w(), qdot.x(), qdot.y(), qdot.z());
  d.w = (tau_B + J.cwiseProduct(y.w).cross(y.w)).cwiseQuotient(J);
  d.x = y.v;
  d.v = f_W / inertia.mass();
  return d;
}

}  // namespace

void Rk4Integrator::step(const Inertia& inertia, const Loads& loads, double lambda, double h,
                         BodyState& state) {
  const Eigen::Quaterniond& q = state.M_WB.rotation();
  const Y y{Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()), state.omega_B.rot,
            state.M_WB.translation(lambda), q * state.omega_B.linear(lambda)};
  const Y k1 = derivative(inertia, loads, lambda, y);
  const Y k2 = derivative(inertia, loads, lambda, y + k1 * (0.5 * h));
  const Y k3 = derivative(inertia, loads, lambda, y + k2 * (0.5 * h));
  const Y k4 = derivative(inertia, loads, lambda, y + k3 * h);
  const Y y1 = y + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);

  const Eigen::Quaterniond q1 = toQuaternion(y1.q).normalized();
  state.M_WB = cga::Motor::fromPose(q1, y1.x, lambda);
  state.omega_B = cga::Bivelocity::fromVelocities(y1.w, q1.conjugate() * y1.v, lambda);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
