// ArticulatedBody: a kinematic tree of rigid links joined by revolute and prismatic joints, and
// the algorithms over it — forward kinematics, the recursive Newton–Euler algorithm (RNEA),
// the articulated-body algorithm (ABA), the composite-rigid-body mass matrix (CRBA), the
// momentum map and the gradient of the Lagrangian. Derivations: doc/articulated.md.
//
// Everything is written in the algebra's terms (doc/conventions.md): a link's pose is a motor
// M_WL, its velocity the body bivelocity Ω_L = (w, v/λ) in its own frame (origin at its centre
// of mass, principal axes, so its inertia map I(·)∧n is diagonal), a joint's screw axis is a
// unit bivector S, forces and momenta are trivectors (τ, λf) (cga/moment.h). Frames change with
// the motor sandwich M X M̃ (Motor::apply), which the recursions apply through the 3×3 blocks of
// its adjoint matrix (TreeKinematics::R_P, t_P; doc/articulated.md (A1')). The velocity-product
// terms are commutator products (cga::commutator): the acceleration a child gets from its
// joint's rate is q̇ (s × Ω).
//
// Bodies are numbered b = 0…n: body 0 is the base — a free body (floating base, 6 velocity
// coordinates Ω_0) or the world (fixed base: no coordinates, M_W0 = 1, Ω_0 = 0) — and body
// k + 1 is the child of joint k. Joints come parent first. Generalized velocities
// ν = (Ω_0, q̇) for a floating base, ν = q̇ for a fixed one; the power pairing of a trivector T
// with a bivelocity Ω is ⟨T, Ω⟩ = T.rot·Ω.rot + T.trans·Ω.trans (τ·w + f·v).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/moment.h"
#include "cga_rigid_sim/cga/motor.h"
#include "cga_rigid_sim/tree/tree_workspace.h"

namespace cga_rigid_sim {
namespace dynamics {

enum class JointKind { kRevolute, kPrismatic };

/// One joint and the link it moves (its child).
struct TreeJoint {
  JointKind kind = JointKind::kRevolute;
  int parent = 0;   ///< body index of the parent (0: the base), < own body index
  cga::Motor M_PJ;  ///< joint frame J in the parent body's frame (fixed base: in the world)
  cga::Motor M_JC;  ///< the child's frame in J
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();          ///< unit, in J
  Inertia inertia = Inertia::unit();                        ///< the child link's
  double damping = 0.0;                                     ///< viscous, N m s/rad or N s/m
  double friction = 0.0;                                    ///< Coulomb, N m or N
  double lower = -std::numeric_limits<double>::infinity();  ///< position limits
  double upper = std::numeric_limits<double>::infinity();
  double effort_limit = std::numeric_limits<double>::infinity();
  /// A mimic joint (URDF <mimic>) follows joint `mimic` of the same tree exactly:
  /// q = mimic_multiplier · q_mimic + mimic_offset (and q̇, q̈ likewise). −1: an independent
  /// joint. The joint it follows must itself be independent (chains resolved by the loader).
  int mimic = -1;
  double mimic_multiplier = 1.0;
  double mimic_offset = 0.0;
  bool hasLimits() const {
    return lower > -std::numeric_limits<double>::infinity() ||
           upper < std::numeric_limits<double>::infinity();
  }
};

/// One independent joint coordinate of a tree with mimic joints (doc/articulated.md#mimic-joints):
/// the joint that carries it and what the joints that follow it impose on it — the
/// intersection of their position limits mapped to it, their Coulomb friction and their
/// damping (friction Σ |m_k| F_k, damping Σ m_k² c_k: the same power as the joints'). Without
/// mimic joints, each joint's own.
struct JointCoordinate {
  int joint = 0;
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  double friction = 0.0;
  double damping = 0.0;
  bool hasLimits() const {
    return lower > -std::numeric_limits<double>::infinity() ||
           upper < std::numeric_limits<double>::infinity();
  }
};

/// The positions of a leader that keep its follower (q = m q_leader + o) within the follower's
/// limits [lower, upper]: [(lower − o)/m, (upper − o)/m], ordered by the sign of m; the whole
/// line when m = 0 (the follower stays at o) — its limits must then hold o.
inline std::pair<double, double> leaderLimits(double lower, double upper, double m, double o) {
  if (m == 0.0)
    return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  const double a = (lower - o) / m, b = (upper - o) / m;
  return m > 0 ? std::make_pair(a, b) : std::make_pair(b, a);
}

/// The constant part of a tree.
class ArticulatedBody {
 public:
  /// A fixed-base tree (base_inertia empty) or a floating-base one. Joints parent first.
  ArticulatedBody(std::optional<Inertia> base_inertia, std::vector<TreeJoint> joints,
                  double lambda);

  bool floating() const { return base_.has_value(); }
  const std::optional<Inertia>& baseInertia() const { return base_; }
  const std::vector<TreeJoint>& joints() const { return joints_; }
  double lambda() const { return lambda_; }
  int jointCount() const { return static_cast<int>(joints_.size()); }
  int bodyCount() const { return jointCount() + 1; }
  /// Generalized velocity coordinates: 6 + n (floating) or n.
  int velocityCount() const { return (floating() ? 6 : 0) + jointCount(); }
  /// Where joint k's rate sits in ν.
  int velocityIndex(int k) const { return (floating() ? 6 : 0) + k; }

  // Mimic joints make the tree's motion a subspace of ν: ν = G ν_r, with ν_r = (Ω_0, the rates
  // of the independent joints) and G's column of an independent joint holding 1 at that joint
  // and each follower's multiplier at the follower. Every solve of the tree's motion (its
  // integrators, contacts, impulses) works on ν_r with M_r = Gᵀ M G and forces Gᵀ f; this is
  // the one place that says where a joint's rate sits in ν_r. Without mimic joints G = 1.
  bool hasMimic() const { return has_mimic_; }
  /// Reduced velocity coordinates: (6 +) the independent joints.
  int reducedCount() const { return (floating() ? 6 : 0) + static_cast<int>(coordinates_.size()); }
  /// Where the rate that moves joint k (its own, or its leader's) sits in ν_r.
  int reducedIndex(int k) const { return (floating() ? 6 : 0) + coordinate_of_[k]; }
  /// q_k = mimicMultiplier(k) q_leader + mimicOffset(k) (1 and 0 for an independent joint).
  double mimicMultiplier(int k) const {
    return joints_[k].mimic < 0 ? 1.0 : joints_[k].mimic_multiplier;
  }
  double mimicOffset(int k) const { return joints_[k].mimic < 0 ? 0.0 : joints_[k].mimic_offset; }
  /// The independent coordinates, in joint order (coordinate c sits at (6 +) c in ν_r).
  const std::vector<JointCoordinate>& coordinates() const { return coordinates_; }
  /// Joint k's unit screw in J, S = (axis, 0) or (0, axis/λ).
  const cga::Bivelocity& screwInJoint(int k) const { return S_J_[k]; }
  /// Joint k's screw in its child's frame, s = M_JC⁻¹ S M_JC (constant: the joint motion
  /// exp(−½ q S) commutes with S).
  const cga::Bivelocity& screwInChild(int k) const { return s_C_[k]; }
  /// Joint k's child frame in its parent's at q = 0: M_PJ M_JC.
  const cga::Motor& childAtZero(int k) const { return M_PC_[k]; }
  /// Inertia of body b (b ≥ 1, or 0 for a floating base).
  const Inertia& inertiaOf(int b) const { return b == 0 ? *base_ : joints_[b - 1].inertia; }
  /// Parent body of body b ≥ 1.
  int parentOf(int b) const { return joints_[b - 1].parent; }

 private:
  std::optional<Inertia> base_;
  std::vector<TreeJoint> joints_;
  double lambda_ = 1.0;
  std::vector<cga::Bivelocity> S_J_, s_C_;
  std::vector<cga::Motor> M_PC_;
  bool has_mimic_ = false;
  std::vector<int> coordinate_of_;  // per joint: its independent coordinate
  std::vector<JointCoordinate> coordinates_;
};

/// The changing part of a tree: base pose and velocity (a fixed base keeps M_W0 = 1, Ω_0 = 0),
/// joint positions and rates.
struct TreeState {
  cga::Motor M_W0;
  cga::Bivelocity omega_0;
  Eigen::VectorXd q, v;
  bool allFinite() const {
    return M_W0.allFinite() && omega_0.allFinite() && q.allFinite() && v.allFinite();
  }
};

/// Whether two states are the same to the bit (+0 and −0 equal; a NaN equals nothing): what a
/// cache of a state's kinematics or mass matrix is checked against.
bool identical(const TreeState& a, const TreeState& b);

/// Per body b: pose M_Wb, motor to the parent's frame M_pb (b ≥ 1), bivelocity Ω_b; and M_pb
/// as the blocks of its adjoint matrix (doc/articulated.md (A1)) — the rotation matrix R_P and
/// the translation over λ, t_P — with which the recursions change frames.
struct TreeKinematics {
  std::vector<cga::Motor> M_W, M_P;
  std::vector<cga::Bivelocity> omega;
  std::vector<Eigen::Matrix3d> R_P;
  std::vector<Eigen::Vector3d> t_P;
  void resize(int bodies);
};

/// Poses and velocities of every body at `state`.
void treeKinematics(const ArticulatedBody& tree, const TreeState& state, TreeKinematics& kin);
/// The two halves of treeKinematics: the poses (M_W, M_P, R_P, t_P; kin sized), then the
/// velocities (omega) into a `kin` that holds the poses of state's positions — alone, what
/// treeKinematics gives after a change of the rates only.
void treePoses(const ArticulatedBody& tree, const TreeState& state, TreeKinematics& kin);
void treeVelocities(const ArticulatedBody& tree, const TreeState& state, TreeKinematics& kin);

/// Generalized velocity ν of a state, and back.
Eigen::VectorXd velocityVector(const ArticulatedBody& tree, const TreeState& state);
void setVelocityVector(const ArticulatedBody& tree, const Eigen::VectorXd& nu, TreeState& state);

/// Mimic joints (ArticulatedBody::hasMimic): ν = G ν_r. `nu` and `f` have velocityCount()
/// entries, `nu_r`, `f_r` and `M_r` reducedCount(). All are the identity (copies) without mimic
/// joints; none allocates once its output has its size.
/// ν = G ν_r: the followers' rates are their multipliers times their leaders'.
void expandVelocity(const ArticulatedBody& tree, const Eigen::VectorXd& nu_r, Eigen::VectorXd& nu);
/// ν_r of a ν that satisfies the mimic constraints: the base's and the independent joints' entries.
void reduceVelocity(const ArticulatedBody& tree, const Eigen::VectorXd& nu, Eigen::VectorXd& nu_r);
/// f_r = Gᵀ f: generalized forces, impulses or momenta on ν_r (the same power on ν = G ν_r).
void reduceForce(const ArticulatedBody& tree, const Eigen::VectorXd& f, Eigen::VectorXd& f_r);
/// The joints' part alone: `f` per joint (jointCount()), `f_r` per independent coordinate (sized).
void reduceJointForce(const ArticulatedBody& tree, Eigen::Ref<const Eigen::VectorXd> f,
                      Eigen::Ref<Eigen::VectorXd> f_r);
/// M_r = Gᵀ M G: the mass matrix (or any symmetric matrix on ν) on ν_r. Without `work` it
/// allocates its work array (the step passes one: tree_workspace.h).
void reduceMatrix(const ArticulatedBody& tree, const Eigen::MatrixXd& M, Eigen::MatrixXd& M_r);
void reduceMatrix(const ArticulatedBody& tree, const Eigen::MatrixXd& M, Eigen::MatrixXd& M_r,
                  TreeWorkspace& work);
/// Puts every follower where its leader says: q_k = m q_l + o, q̇_k = m q̇_l (bit-exact, so that
/// the constraints hold to the rounding of that one expression), then within its own limits
/// (which the leader's coordinate limits keep it in, up to that rounding).
void applyMimic(const ArticulatedBody& tree, TreeState& state);
/// The positions alone: q_k = m q_l + o for every follower, within its limits.
void applyMimicPositions(const ArticulatedBody& tree, Eigen::VectorXd& q);

/// The external trivector moments on each body (body frame, about its centre of mass): what
/// gravity and applied loads exert; size bodyCount() (entry 0 unused for a fixed base).
using BodyMoments = std::vector<cga::Moment>;

/// Gravity on every body at the poses of `kin`: (0, λ m R̃ g).
void gravityMoments(const ArticulatedBody& tree, const TreeKinematics& kin,
                    const Eigen::Vector3d& g_W, BodyMoments& out);

/// RNEA: the generalized forces (base wrench in body-0 frame, then joint efforts) that give the
/// accelerations ν̇ at the state of `kin` under the external moments: M(q) ν̇ + bias − Jᵀ f_ext.
/// For a floating base the first 6 entries are the wrench the base would need (zero when ν̇
/// is the motion the tree makes on its own).
Eigen::VectorXd inverseDynamics(const ArticulatedBody& tree, const TreeState& state,
                                const TreeKinematics& kin, const Eigen::VectorXd& nu_dot,
                                const BodyMoments& f_ext);

/// The generalized forces that joint efforts `tau` (size n) and external moments exert on a tree
/// at rest, Q = [0; τ] + Jᵀ f_ext (minus the RNEA's forces at ν = 0, ν̇ = 0; the floating base's
/// first, in body 0's frame): M(q) ν̇ = Q is the motion they start. O(n), into `Q`, with its
/// work array in `work` (no allocation once Q and work have their sizes).
void forcesAtRest(const ArticulatedBody& tree, const TreeKinematics& kin,
                  const Eigen::VectorXd& tau, const BodyMoments& f_ext, Eigen::VectorXd& Q,
                  TreeWorkspace& work);

/// ABA: the accelerations ν̇ under joint efforts `tau` (size n) and external moments, O(n).
/// With mimic joints the accelerations the constraints allow, ν̇ = G M_r⁻¹ Gᵀ (τ − b), from the
/// CRBA and the RNEA instead (ABA's recursion cannot hold a constraint between branches).
Eigen::VectorXd forwardDynamics(const ArticulatedBody& tree, const TreeState& state,
                                const TreeKinematics& kin, const Eigen::VectorXd& tau,
                                const BodyMoments& f_ext);
/// The same into `nu_dot`, with its work arrays in `work` (no allocation once nu_dot and work
/// have their sizes); without `work` it allocates them.
void forwardDynamics(const ArticulatedBody& tree, const TreeState& state, const TreeKinematics& kin,
                     const Eigen::VectorXd& tau, const BodyMoments& f_ext, Eigen::VectorXd& nu_dot);
void forwardDynamics(const ArticulatedBody& tree, const TreeState& state, const TreeKinematics& kin,
                     const Eigen::VectorXd& tau, const BodyMoments& f_ext, Eigen::VectorXd& nu_dot,
                     TreeWorkspace& work);

/// CRBA: the mass matrix M(q) (symmetric positive definite), kinetic energy ½ νᵀ M ν.
/// Without `work` it allocates its work array (the step passes one).
void massMatrix(const ArticulatedBody& tree, const TreeKinematics& kin, Eigen::MatrixXd& M);
void massMatrix(const ArticulatedBody& tree, const TreeKinematics& kin, Eigen::MatrixXd& M,
                TreeWorkspace& work);

/// The momentum map ∂L/∂ν = M ν: per joint p_k = ⟨H_k, s_k⟩ with H_k the momentum of the
/// subtree below joint k in the child's frame; for a floating base the first 6 entries are the
/// whole tree's momentum in the base frame. Also returns, through `gradient` (may be null), the
/// gradient of the Lagrangian in q at fixed ν plus the generalized external forces:
///   ∂L/∂q_k + Q_k = ⟨H_k, s_k × Ω_{k+1}⟩ + ⟨F_k, s_k⟩,
/// with F_k the external moments on the subtree in the child's frame (doc/articulated.md).
Eigen::VectorXd momentumAndGradient(const ArticulatedBody& tree, const TreeKinematics& kin,
                                    const BodyMoments& f_ext, Eigen::VectorXd* gradient);
/// The same into `p`, with its work arrays in `work` (no allocation once p, gradient and work
/// have their sizes); without `work` it allocates them.
void momentumAndGradient(const ArticulatedBody& tree, const TreeKinematics& kin,
                         const BodyMoments& f_ext, Eigen::VectorXd& p, Eigen::VectorXd* gradient);
void momentumAndGradient(const ArticulatedBody& tree, const TreeKinematics& kin,
                         const BodyMoments& f_ext, Eigen::VectorXd& p, Eigen::VectorXd* gradient,
                         TreeWorkspace& work);

/// Total momentum of the tree in world axes (the trivector about the world origin) and its
/// kinetic energy.
cga::Moment worldMomentum(const ArticulatedBody& tree, const TreeKinematics& kin);
double kineticEnergy(const ArticulatedBody& tree, const TreeKinematics& kin);

/// 6×6 matrix of the adjoint action B ↦ M B M̃ on bivector coefficients (e23, e31, e12, e1n,
/// e2n, e3n); on trivector coefficients the action is its inverse transpose.
Eigen::Matrix<double, 6, 6> adjointMatrix(const cga::Motor& M, double lambda);

}  // namespace dynamics
}  // namespace cga_rigid_sim
