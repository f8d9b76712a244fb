// TreeIntegrator: advances an articulated tree's state (base motor and bivelocity, joint
// positions and rates) by one step h under gravity, applied loads and joint efforts, with the
// joints' damping, Coulomb friction and position limits (doc/articulated.md#integrators).
//
// Chosen by the ~integrator names (makeTreeIntegrator):
//   auto, cga2  the variational midpoint: the implicit midpoint rule on positions and momenta
//               (p = M(q) q̇ for the joints, the tree's world momentum for a floating base),
//               second order, symmetric. For a fixed base it is symplectic: the energy of an
//               undamped chain stays bounded without drift. A floating base's world momentum
//               changes only by the external wrench, exactly, so it is conserved to round-off
//               in zero gravity. Damping is implicit (stable at any h); friction and limits are
//               solved with the step (doc/articulated.md#limits-and-friction).
//   cga4        the midpoint composed as Yoshida's triple jump: fourth order, same invariants.
//   rk4         classical Runge–Kutta on (M_W0, Ω_0, q, q̇) with the accelerations of forward
//               dynamics (a fixed base under gravity: CRBA, RNEA bias and Cholesky on scalar
//               frames; otherwise ABA): the baseline (damping and friction explicit, limits by
//               projection after the step).
//   euler       explicit Euler with the same accelerations, the crudest baseline.
//   exact       refused for trees: a tree has no closed-form flow.
// An integrator object belongs to one tree; it caches the momenta of the state it produced and
// recomputes them when the state was changed from outside (reset() drops the cache).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "cga_rigid_sim/body/loads.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/tree/articulated_body.h"
#include "cga_rigid_sim/tree/joint_servos.h"

namespace cga_rigid_sim {
namespace dynamics {

/// What acts on a tree during one step.
struct TreeLoads {
  Eigen::Vector3d gravity_W = Eigen::Vector3d::Zero();
  /// Per body b (size bodyCount(), entries may be null): applied loads in b's frame (their
  /// gravity is ignored: gravity_W is the tree's).
  std::vector<const Loads*> applied;
  /// Actuator effort per joint (size jointCount()), already clamped to the effort limit.
  Eigen::VectorXd effort;
  /// Position and velocity servos (joint_servos.h): their torque adds to `effort`, the sum
  /// clamped to the effort limit. Empty: none.
  JointServos servos;
};

/// The external moments on every body at the poses of `kin`: gravity plus applied loads.
void externalMoments(const ArticulatedBody& tree, const TreeKinematics& kin, const TreeLoads& loads,
                     BodyMoments& out);

class TreeIntegrator {
 public:
  virtual ~TreeIntegrator() = default;
  virtual const char* name() const = 0;
  virtual void step(const ArticulatedBody& tree, const TreeLoads& loads, double h,
                    TreeState& state) = 0;
  /// Drops cached momenta (after an impulse or a state override).
  virtual void reset() {}
  /// reset(), and the kinematics `kin` of `state` and its mass matrix M (null: not at hand),
  /// which the caller has made for the state the next step starts from (a contact step's, after
  /// its impulses): the integrator may take them instead of making its own. They must be what
  /// treeKinematics and massMatrix give for that state, to the bit; they are taken only when the
  /// next step starts from that very state.
  virtual void startFrom(const TreeState& /*state*/, const TreeKinematics& /*kin*/,
                         const Eigen::MatrixXd* /*M*/) {}
  /// Fixed-point iterations of the last step (implicit methods; 0 otherwise), for benchmarks.
  virtual int lastIterations() const { return 0; }
  /// The energy the joints' damping and Coulomb friction took in the last step, J (≥ 0 up to
  /// round-off): the World books it as dissipated (doc/articulated.md#energy).
  virtual double lastDissipated() const { return 0.0; }
  /// Whether a position limit stopped a joint in the last step. The World then books the step's
  /// energy from the states before and after it (what a stop takes is not a force's work).
  virtual bool lastLimited() const { return false; }
  /// Whether the last step was solved: false when the implicit iteration did not converge
  /// within its attempts and the state was left as the last attempt made it (a tree fault).
  virtual bool lastSolved() const { return true; }
  /// Whether a step without loads keeps a floating tree's momentum to round-off (the
  /// variational midpoint and its compositions do; RK4 and Euler only to their truncation):
  /// the World's momentum guard then checks the drift of a contact step too.
  virtual bool conservesMomentum() const { return false; }
  /// The kinematics (poses and velocities of every body) of the state the last step produced,
  /// when the integrator has them at hand, else null: spares the caller a kinematics pass.
  /// Valid until the next call on the integrator; describes that state only while it is
  /// unchanged.
  virtual const TreeKinematics* lastKinematics() const { return nullptr; }
  /// lastKinematics() when they are what treeKinematics gives for that state to the bit (the
  /// midpoint's for a floating base; a fixed base's come from other formulas, equal to
  /// round-off), else null.
  virtual const TreeKinematics* lastExactKinematics() const { return nullptr; }
  /// M(q) at the pose of lastExactKinematics(), as dynamics::massMatrix makes it from those
  /// poses (to the bit), when the integrator made it there; else nullptr. Valid until the next
  /// step.
  virtual const Eigen::MatrixXd* lastMass() const { return nullptr; }
  /// The effort the joints' actuators applied in the last step when servos acted (effort plus
  /// servo, clamped: the midpoint's at the midpoint, rk4's the stages' weighted mean), else
  /// null (the loads' effort was applied as given).
  virtual const Eigen::VectorXd* lastEffort() const { return nullptr; }
};

/// The names makeTreeIntegrator accepts (those of integrator.h that apply to trees).
const std::vector<std::string>& treeIntegratorNames();
/// A new integrator for one tree, or an error naming the integrator and why (unknown, or
/// `exact`, which has no tree form).
Result<std::unique_ptr<TreeIntegrator>> makeTreeIntegrator(const std::string& name);

/// The generalized velocity change Δν = M(q)⁻¹ (J_bᵀ T) of an impulsive moment T (body frame
/// of body b) on a tree at rest in its pose: what an impulse does to the tree (with mimic
/// joints G M_r⁻¹ Gᵀ J_bᵀ T, a change the constraints allow).
Eigen::VectorXd impulseResponse(const ArticulatedBody& tree, const TreeState& state, int body,
                                const cga::Moment& T_b);

}  // namespace dynamics
}  // namespace cga_rigid_sim
