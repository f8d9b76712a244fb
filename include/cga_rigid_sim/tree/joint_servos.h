// JointServos: position and velocity servos on a tree's joints (doc/articulated.md#servos).
//
// On joint k the servo adds
//   τ_k = kp_k (r_k − q_k) + kd_k (ṙ_k − q̇_k)
// to the joint's effort, and the sum is clamped to the joint's <limit effort>. A position servo
// has kp > 0 (a spring to r, with the damper kd toward ṙ); a velocity servo has kp = 0 and
// kd > 0; a joint with kp = kd = 0 has none. The references r, ṙ hold over one step (the
// controllers set them, sampled at the step's middle).
//
// How each integrator takes the servo: the variational midpoint implicitly — τ at the midpoint
// (q̄ = q + ½h ν̄, ν̄), with ½h kd + ¼h² kp on its iteration matrix's diagonal, so a servo as
// stiff as the user types is stable at any h (the implicit midpoint rule is A-stable: the
// discrete response of a servoed joint is doc/articulated.md (S2)); a contact step's kick
// linearly implicitly (contact/contact_trees.cc); rk4 and euler explicitly, at each stage (the
// baselines: an explicit PD diverges once h √(kp/m) passes their stability bound).
#pragma once

#include <Eigen/Core>
#include <algorithm>

namespace cga_rigid_sim {
namespace dynamics {

struct JointServos {
  /// Per joint (size jointCount(), or all empty: no servo on the tree): the gains, ≥ 0 (N m/rad
  /// and N m s/rad, or N/m and N s/m), and the references r (rad or m) and ṙ (rad/s or m/s).
  Eigen::VectorXd kp, kd, position, velocity;

  bool active() const { return kp.size() > 0; }
  /// Sizes the vectors for n joints, every servo off.
  void resize(Eigen::Index n) {
    kp.setZero(n);
    kd.setZero(n);
    position.setZero(n);
    velocity.setZero(n);
  }
  void clear() {
    kp.resize(0);
    kd.resize(0);
    position.resize(0);
    velocity.resize(0);
  }
  /// The servo's torque on joint k at (q, q̇), before the effort limit.
  double torque(Eigen::Index k, double q, double qdot) const {
    return kp[k] * (position[k] - q) + kd[k] * (velocity[k] - qdot);
  }
};

/// Effort plus servo on joint k, clamped to ±limit (the limit is ≥ 0 or infinite).
inline double servoedEffort(const JointServos& servos, Eigen::Index k, double effort, double q,
                            double qdot, double limit) {
  return std::clamp(effort + servos.torque(k, q, qdot), -limit, limit);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
