// MidpointResidual: the residual of the variational midpoint's equations (tree_integrator_
// midpoint.cc) in one outward and one inward pass, for the common case of a fixed-base tree
// under gravity and joint efforts alone (no loads applied to its links), and for a floating
// base without gravity or loads (a contact step's drift, doc/contacts.md#trees); on the same
// constants also the explicit integrators' stage for a fixed base (accelerations()). Internal.
// Defined in tree_integrator_residual.cc (the residual passes), tree_residual_pose.cc (the tree's
// constants, the end pose and its velocities) and tree_residual_dynamics.cc (the mass matrix and
// the explicit stage), with the joint frames of tree_residual_frames.h.
//
// At the midpoint q̄ = q + ½h q̄̇ with rates q̄̇ it yields what treeKinematics, gravityMoments and
// momentumAndGradient together yield there — the joint momenta p = M(q̄) q̄̇ and the gradient
// ∂L/∂q + Q — to round-off, with less work:
// - each joint's frame change in the blocks of its adjoint (R_P, t_P; doc/articulated.md (A1'))
//   straight from the joint angle: a revolute joint turns its child about the line s = (u, m),
//   so with M_PC = T(a0) R0 and c the point of the line nearest the child's origin,
//     R_P = R0 R_u(q) = R0 + sin q R0[u]× + (1 − cos q) R0[u]×²,   t_P = (a0 + R0 c − R_P c)/λ,
//   (Rodrigues; the three matrices and a0 + R0 c are constants of the tree); a prismatic joint
//   slides it: R_P = R0, t_P = (a0 + λ q R0 m)/λ. No motors (poses in the world are not needed;
//   endPose() gives them at the step's end, for the mass matrix and the World).
// - sin and cos of ½q̄ by the addition theorem from those of ½q at the step's start, which the
//   iteration does not move: ½q̄ = ½q + ¼h q̄̇, the increment's sine and cosine from their
//   Taylor polynomials (exact to round-off while |¼h q̄̇| ≤ 1/16, else from std::sin/cos).
// - gravity in each body's axes carried outward with the frames (g_b = R_Pᵀ g_p), so that the
//   external moments (0, λ m g_b) need no world pose either.
// - the outward pass also sets each body's bivelocity and momentum I(Ω_b); the inward pass then
//   accumulates the subtree momenta H and external moments F as momentumAndGradient does.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "cga_rigid_sim/tree/articulated_body.h"
#include "cga_rigid_sim/tree/tree_integrator.h"
#include "tree/tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

class MidpointResidual {
 public:
  /// Whether these passes apply to a step of `tree` under `loads`: no loads applied to its
  /// links, and for a floating base no gravity either (a contact step's drift); the general
  /// path handles the rest.
  static bool applies(const ArticulatedBody& tree, const TreeLoads& loads);
  /// The tree's constants (recomputed when called with another tree than the last).
  void prepare(const ArticulatedBody& tree);
  /// sin and cos of ½q at the step's start.
  void startAt(const Eigen::VectorXd& q);
  /// The poses of treePoses() at positions q (M_W, M_P, R_P, t_P; kin sized), to round-off,
  /// from the same constants: M_pb = M_PC exp(−½ q s) is linear in (cos ½q, sin ½q), R_P and
  /// t_P come by Rodrigues as in evaluate(). Also does startAt(q): the next step starts there.
  void endPose(const Eigen::VectorXd& q, TreeKinematics& kin);
  /// The mass matrix M(q) at the positions of the last endPose() (or accelerations()):
  /// massMatrix() (CRBA on composite inertias) to round-off, on the frames endPose() kept, with
  /// composites and screws in one frame per subtree of the base (tree_residual_dynamics.cc).
  void massMatrix(Eigen::MatrixXd& M);
  /// The bivelocities kin.omega at the pose of the last endPose() and joint rates v:
  /// treeVelocities() to round-off.
  void velocities(const Eigen::VectorXd& v, TreeKinematics& kin) const;
  /// At the midpoint of a step of h from the positions q of startAt() with midpoint rates
  /// q̄̇ = nu_bar: the joint momenta p and the gradient ∂L/∂q + Q, under gravity g (world
  /// axes: a fixed base's). A floating base has no gravity here (applies()): g is not read, its
  /// midpoint bivelocity is nu_bar's first six entries, and p's first six are the tree's
  /// momentum in the base's axes (the base's subtree momentum H_0, what momentumAndGradient
  /// gives there). Sizes are kept: no allocation once sized.
  void evaluate(const Eigen::VectorXd& q, const Eigen::Vector3d& g, double h,
                const Eigen::VectorXd& nu_bar, Eigen::VectorXd& p, Eigen::VectorXd& gradient);
  /// The power of gravity at the last evaluate()'s midpoint, Σ ⟨F_b, Ω_b⟩ (needed once a
  /// step, not in every pass).
  double gravityPower() const;
  /// The explicit integrators' stage (rk4, euler): the accelerations q̈ = M(q)⁻¹ (τ − b(q, q̇))
  /// at positions q and rates v under gravity g_W and joint forces tau — forwardDynamics() to
  /// round-off, with the frames by Rodrigues as above, M by massMatrix() on them and the bias b
  /// by one RNEA pass with q̈ = 0 and the base accelerating at −g (so that gravity needs no
  /// frame of its own). For 7 joints this is about half the operations of ABA's 6×6
  /// articulated inertias (doc/articulated.md#integrators). Leaves the frames of q for
  /// massMatrix(); no allocation once sized.
  void accelerations(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::Vector3d& g_W,
                     const Eigen::VectorXd& tau, Eigen::VectorXd& qdd);

 private:
  template <bool Floating>
  void passes(const Eigen::VectorXd& q, const Eigen::Vector3d& g_0, double h,
              const Eigen::VectorXd& nu_bar, Eigen::VectorXd& p, Eigen::VectorXd& gradient);

  struct Joint {
    bool revolute = true;
    int parent = 0;
    double A[9];  // R0 (row-major)
    // R_P = R0 + sin q R0[u]× + (1 − cos q) R0[u]×² differs from R0 only where R0[u]× or
    // R0[u]×² has a nonzero entry: four of the nine for an axis along a coordinate axis of
    // R0's frame (the usual URDF joint). Those entries, as (index, R0[u]×, R0[u]×²); none for a
    // prismatic joint.
    struct Term {
      int index;
      double b, c;
    };
    Term terms[9];
    int term_count;
    double c[3];      // revolute: c/λ; prismatic: R0 m
    double d[3];      // revolute: (a0 + R0 c)/λ; prismatic: a0/λ
    double s[6];      // screw in the child's frame (rot, trans)
    double J[3], m2;  // principal moments, m λ²
    double lm;        // λ m (gravity moment per unit acceleration)
    // M_pb = cos ½q P0 + sin ½q P1 (revolute) or P0 + q P1 (prismatic), as the rotor's and the
    // dual quaternion's (w, x, y, z): P0 = M_PC, P1 = M_PC (u, −m) or M_PC (0, −½m).
    double P0[8], P1[8];
  };
  struct Body {  // per body, scratch of one evaluation (a: accelerations())
    double R[9], t[3], g[3], w[3], u[3], H[6], F[6], a[6];
  };
  struct Frame {  // per body, its frame in its parent's at the last endPose()
    double R[9], t[3];
  };
  struct Screw {  // per joint, massMatrix()'s screw in its subtree root's frame
    double s[6];
  };
  // A composite rigid-body inertia about a body's origin (lengths over λ, m' = m λ²): I_o
  // (xx, yy, zz, xy, xz, yz), h = m' c, m' (tree_momentum.cc).
  using Composite = tree_math::Composite;
  const ArticulatedBody* tree_ = nullptr;
  int joints_ = -1;
  bool floating_ = false;
  double base_J_[3] = {0.0, 0.0, 0.0}, base_m2_ = 0.0, base_lm_ = 0.0;  // a floating base's
  std::vector<Joint> joint_;
  std::vector<Body> body_;
  std::vector<Frame> frame_;
  std::vector<Frame> root_frame_;  // massMatrix(): each body's frame in its subtree root's
  std::vector<Screw> root_screw_;
  std::vector<Composite> composite_;
  std::vector<double> sin_half_, cos_half_;
  Eigen::MatrixXd mass_;  // accelerations(): M(q), its factor
  tree_math::Cholesky llt_;
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
