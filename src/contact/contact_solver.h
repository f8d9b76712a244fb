// The contact solver (doc/contacts.md#solver): the impulses of one step's contacts, solved
// together by projected Gauss–Seidel over the contacts, one block (normal, two tangents) per
// contact, as in Kaufman, Edmunds & Pai's Fast Frictional Dynamics: each sweep costs O(number
// of contacts), so a pile scales linearly.
//
// Per contact, with u the relative velocity of a's point against b's after the step:
//   normal     λ_n ≥ 0, u_n ≥ target, λ_n (u_n − target) = 0, where target is 0 for bodies in
//              touch, −gap/h for a gap (it may close, no more), or −e u_n⁻ for an impact
//              faster than the resting threshold (Newton's restitution law);
//   friction   the elliptic (here: circular, μ isotropic) Coulomb cone |λ_t| ≤ μ λ_n: sticking
//              (u_t = 0) inside it, sliding with λ_t opposite u_t on its rim. A diagonal push
//              sees the same cone as a straight one.
// Solved island by island (bodies joined by their contacts), each until its own sweeps
// converge. Warm-started from the impulses of the same contacts in the last step, so a resting
// stack starts at its solution. The corners of a face (consecutive contacts between the same two
// bodies with one normal) take their normal impulses as one block (SolverWork::Group), which
// Gauss–Seidel corner by corner would trade between them for ever. A solve whose restitution
// would raise the kinetic energy (several simultaneous impacts) is redone with e = 0, which
// never raises it (doc/contacts.md proves it).
//
// The solver works on world-axes velocities (v, w) of the bodies' centres of mass; its
// impulses are applied to the states as CGA impulses afterwards (contact_apply.cc), so the
// velocity jump is (I∧n)⁻¹ T_imp as for user impulses. A link of an articulated tree has no
// velocity of its own: the side of a contact on it reads and changes its tree's generalized
// velocity ν through the contact point's Jacobian J (u = J ν) and the response W = M(q)⁻¹ Jᵀ
// (Δν = W P), so contacts on several links of one tree are coupled through M(q)
// (doc/contacts.md#trees).
//
// This header holds what the contact step hands the solver and gets back: bodies, trees, rows,
// settings and the entry points. The working arrays are in contact_solver_work.h; the parts of
// a solve each have a file, listed in contact_solver_internals.h.
#pragma once

#include <Eigen/Dense>
#include <limits>
#include <vector>

#include "cga_rigid_sim/contact/contact.h"
#include "cga_rigid_sim/sim/world_config.h"
#include "contact/contact_solver_work.h"
#include "contact/contact_tree_factor.h"

namespace cga_rigid_sim {
namespace sim {

/// A body as the solver sees it (world axes). Static bodies and the plane have no slot. A link
/// of a tree has a slot too (for its position and its kicked velocity, which the stage reads),
/// with `tree` set and no mass: the solver moves its tree's ν instead.
struct SolverBody {
  int tree = -1;       ///< the solver tree it belongs to, or −1 (a free body)
  int tree_body = -1;  ///< its body index in that tree
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  ///< centre of mass, m
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  ///< centre-of-mass velocity, m/s
  Eigen::Vector3d w = Eigen::Vector3d::Zero();  ///< angular velocity, rad/s
  double inv_mass = 0.0;
  Eigen::Matrix3d inv_inertia = Eigen::Matrix3d::Zero();  ///< world axes
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();      ///< world axes (for the energy)
  double mass = 0.0;
  // Pseudo-velocities of the position correction (they move the pose, not the momentum).
  Eigen::Vector3d pv = Eigen::Vector3d::Zero();
  Eigen::Vector3d pw = Eigen::Vector3d::Zero();
};

/// An articulated tree as the solver sees it: its generalized velocity and mass matrix at the
/// step's start, and per velocity coordinate the world twist (ω, v_o) that a unit rate gives
/// (v_o: the velocity of the point at the world origin), from which contact Jacobians follow.
struct SolverTree {
  /// A joint's position limits as rows on its rate ν_k, solved with the contacts: over the step
  /// the joint may reach its limits, not pass them — lower ≤ q + h ν_k ≤ upper, by impulses
  /// y_lower ≥ 0 and y_upper ≤ 0 on the joint (internal to the tree: they change neither its
  /// momentum nor, being projections in the metric of M, raise its kinetic energy). The
  /// position correction keeps q + h (ν_k + pν_k) within the same limits the same way.
  struct LimitRow {
    int index = 0;                        ///< velocity index
    double q = 0.0;                       ///< the joint's position at the step's start
    double lower = 0.0, upper = 0.0;      ///< its limits (±∞ where it has none)
    double y_lower = 0.0, y_upper = 0.0;  ///< accumulated impulses (velocity solve)
    /// The last step's y_lower, y_upper: the warm start of a resting tree's solve
    /// (contact_resting_tree.h).
    double y_lower_last = 0.0, y_upper_last = 0.0;
    double p_lower = 0.0, p_upper = 0.0;  ///< accumulated pseudo-impulses (position correction)
  };
  Eigen::VectorXd nu;                  ///< ν after the loads' kick and the impulses
  Eigen::VectorXd nu_start, nu_sweep;  ///< before the impulses; before a sweep
  Eigen::VectorXd pnu;                 ///< the position correction's pseudo-velocity
  Eigen::MatrixXd M;                   ///< M(q)
  TreeFactor factor;                   ///< its factor (contact_tree_factor.h)
  /// Per coordinate its parent coordinate (−1: none; the floating base's six a chain, a joint's
  /// the coordinate of its parent link's joint, or the base's last): the sparsity of M that
  /// `factor` keeps. Empty with mimic joints (M on the independent coordinates is factored
  /// densely).
  std::vector<int> coordinate_parent;
  Eigen::Matrix<double, 6, Eigen::Dynamic> twist;  ///< per coordinate: (ω; v_o), world
  std::vector<int> parent;                         ///< per tree body: its parent (−1 for body 0)
  bool floating = false;                           ///< the base's 6 coordinates come first
  std::vector<LimitRow> limits;                    ///< every joint with a position limit
  /// Per joint: the column of ν its rate is (a mimic joint: its leader's) and its multiplier
  /// (1 for an independent joint): ν, M and the solver are on the independent coordinates.
  std::vector<int> column;
  std::vector<double> multiplier;
};

/// One contact in the solver: its bodies' slots (−1: immovable or a tree side), lever arms,
/// basis, the Delassus block K in the basis (n, t1, t2), its target and its accumulated
/// impulses. A side on a tree link has ta/tb set, its Jacobian j (world point velocity = j ν)
/// and the first half of its response, w = L⁻ᵀ jᵀ (M = Lᵀ L); a contact between two links of
/// one tree keeps the difference of their Jacobians on side a alone.
struct ContactRow {
  int a = -1, b = -1;
  int ta = -1, tb = -1;
  Eigen::Matrix<double, 3, Eigen::Dynamic> ja, jb;
  /// The tree sides' Y = L⁻ᵀ jᵀ (TreeFactor::halfSolve), which gave ka, kb = Yᵀ Y and on
  /// which the sweeps work (contact_solver_internals.h, SolverWork::TreeSweeps).
  TreeFactor::Columns wa, wb;
  /// The coordinates from whose paths to the base the tree sides' Jacobians draw (−1: none; a
  /// contact between two links of one tree has two on side a).
  int leaf_a = -1, leaf_a2 = -1, leaf_b = -1;
  /// The tree sides' parts of the Delassus block, j M⁻¹ jᵀ (world axes).
  Eigen::Matrix3d ka = Eigen::Matrix3d::Zero(), kb = Eigen::Matrix3d::Zero();
  Eigen::Vector3d ra, rb, n, t1, t2;
  double k_nn = 0.0;
  /// K n: how the relative velocity at the point changes per unit normal impulse (world axes).
  Eigen::Vector3d k_n = Eigen::Vector3d::Zero();
  /// The tangent block's inverse: a contact that can stick takes the impulse that stops its
  /// slip exactly (fast convergence under a face's four corners).
  Eigen::Matrix2d k_tt_inv = Eigen::Matrix2d::Zero();
  /// The tangent block's largest eigenvalue: a contact that slides steps by −u_t / k_t, along
  /// −u_t, and is projected onto the cone, so its fixed point has λ_t opposite its slip
  /// (maximal dissipation); projecting the exact step would turn it.
  double k_t = 0.0;
  double inv_k_nn = 0.0, inv_k_t = 0.0;  ///< 1/k_nn, 1/k_t (0 where k is infinite)
  double depth = 0.0;                    ///< penetration, m (≤ 0: a gap)
  double target = 0.0;                   ///< the lower bound of u_n after the step, m/s
  double bias = 0.0;                     ///< position correction's target pseudo-velocity, m/s
  double mu = 0.0;          ///< this step's friction coefficient: μ(v) (contact_friction.h)
  double mu_surface = 0.0;  ///< the surfaces' combined μ (the kinetic one)
  double restitution = 0.0;
  double impact = 0.0;  ///< −u_n before the solve when it is an impact, else 0
  double lambda_n = 0.0;
  Eigen::Vector2d lambda_t = Eigen::Vector2d::Zero();
  /// Of lambda_n, the part on the friction pyramid's edges n ± μ t1 (the rest on n ± μ t2) in
  /// a tree's resting solve (contact_resting_tree.cc), as the last one left it on entry (the
  /// sweeps leave it); NaN: unknown.
  double pyramid_share = std::numeric_limits<double>::quiet_NaN();
  double lambda_p = 0.0;  ///< position correction's accumulated pseudo-impulse
  /// The contact model's patch couples (contact_patch.h), 0 when off: about n, about t1 and
  /// t2, and their sum in world axes (the angular impulse on a; b takes its opposite).
  double lambda_spin = 0.0;
  Eigen::Vector2d lambda_roll = Eigen::Vector2d::Zero();
  Eigen::Vector3d couple = Eigen::Vector3d::Zero();
  /// Compliant contact (ContactModel::normal_stiffness): the normal impulse is the spring's,
  /// fixed before the sweeps, not solved.
  bool compliant = false;
  double lambda_fixed = 0.0;
  /// The tangential velocity the friction aims at, (t1, t2): 0, or at an impact with
  /// tangential restitution −e_t u_t⁻.
  Eigen::Vector2d target_t = Eigen::Vector2d::Zero();
  /// One of three or four coplanar corners of a face block (SolverWork::Group).
  bool face = false;
};

struct SolverSettings {
  double h = 0.001;   ///< step, s
  double kick = 0.0;  ///< |g| h, m/s
  /// g h, world axes, m/s: what the step's kick added to every free body's velocity (the
  /// compliant contacts' damping reads the velocity before it).
  Eigen::Vector3d gravity_kick_W = Eigen::Vector3d::Zero();
  double rest_speed = 0.0;  ///< landings slower than this do not bounce, m/s
  /// Approaches slower than this (after the step's kick) do not bounce, m/s: rest_speed plus
  /// what the kick adds, so a landing too slow to bounce does not bounce here either.
  double bounce_speed = 0.0;
  double slop = 5e-5;        ///< overlap left uncorrected, m
  double touching = 1e-9;    ///< gaps below this are contact, m
  double correction = 0.2;   ///< fraction of the overlap beyond slop removed per step
  int max_iterations = 100;  ///< Gauss–Seidel sweeps at most
  /// An island's overlaps are corrected once one of them passes the slop by more than this, m
  /// (then each by its part beyond the slop): a resting contact settles 1e-9–1e-7 m past the
  /// slop, where a correction solved every step would move nothing that matters.
  double correction_onset = 1e-6;
  /// … for an island with an articulated tree: Gauss–Seidel converges slowly where a tree's
  /// contacts and joint stops share its load through M(q), so the cap, not the tolerance, ends
  /// such a solve (a sweep is a projection that never adds energy: a stopped solve leaves
  /// velocities partly corrected, never amplified). Why 30: doc/decisions.md.
  int max_tree_iterations = 30;
  /// An island of one tree whose contact points all move slower than this before the
  /// impulses (m/s) is solved by Newton's method on the tree's coordinates
  /// (contact_resting_tree.h), not by sweeps: a resting robot's contacts and stops share its
  /// load through M(q), where Gauss–Seidel leaves it creeping. Its friction pyramid lets a
  /// contact sliding at s lift at up to μ s, so it is kept to what rests. Why 2 cm/s: twice
  /// the kick g h at 1 ms, doc/decisions.md. 0 turns it off.
  double resting_tree_speed = 0.02;
  /// An island of one tree alone whose sweeps stopped at their cap with a contact approaching
  /// faster than this past its target (m/s) has its normals and stops solved again by Newton's
  /// method, the sweeps' friction held (contact_resting_tree.h). 1 mm/s moves a contact 1 µm in
  /// a 1 ms step, a fiftieth of the slop. Why: doc/decisions.md. Off with
  /// resting_tree_speed = 0 (Newton's solves off).
  double tree_sink_speed = 1e-3;
  int position_iterations = 10;  ///< sweeps of the position correction at most
  /// The position correction moves a tree's coordinate (a joint, rad or m; the floating base's
  /// six, rad and m/λ) by at most this much in one step. It removes a fifth of an overlap per
  /// step, so a few centimetres at a lever of 10 cm need a few hundredths of a radian; more only
  /// where the tree can barely move the contact points apart (J M⁻¹ Jᵀ nearly singular), where
  /// it would fling the joints.
  double max_tree_shift = 0.05;
  /// Stop when a sweep changes no body's velocity at any of its contact points by more, m/s.
  /// The bodies' velocities, not the impulses: four contacts under one face share its load in
  /// any proportion, and Gauss–Seidel keeps shifting it between them long after the motion has
  /// converged.
  double tolerance = 1e-13;
  /// … plus this fraction of the step's kick g h: a column of boxes keeps a slow Gauss–Seidel
  /// mode alive at ~1e-12 m/s (it moves the top box by 1e-11 m in 10 s).
  double tolerance_of_kick = 1e-10;
  /// … plus this fraction of the fastest contact point's speed in the island beyond twice the
  /// kick: 1e-9 relative accuracy while its bodies move fast, nothing added once they rest.
  double tolerance_of_speed = 1e-9;
  /// The contact model's extensions (doc/contact_model.md).
  ContactModel model;
  /// Fill SolveStats' kinetic energies (the landings book theirs; the step's solve does not).
  bool kinetic_energy = false;
};

/// [r]×, the matrix of r × (·).
inline Eigen::Matrix3d crossMatrix(const Eigen::Vector3d& r) {
  Eigen::Matrix3d m;
  m << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return m;
}

struct SolveStats {
  int iterations = 0;  ///< the sweeps of the island that took the most
  double kinetic_before = 0.0, kinetic_after = 0.0;  ///< with SolverSettings::kinetic_energy
};

/// Fills the rows' geometry (arms, basis, K, targets) from the contacts and the bodies.
/// Tree sides take their Jacobians from `trees` (the slot's SolverBody names its tree).
void prepareRows(const std::vector<Contact>& contacts, const std::vector<SolverBody>& bodies,
                 const std::vector<SolverTree>& trees, const std::vector<int>& slot_a,
                 const std::vector<int>& slot_b, std::vector<ContactRow>& rows);
/// Solves the velocity impulses (rows' lambda_n, lambda_t hold the warm start on entry) and
/// leaves the bodies' v, w and the trees' ν at their values after the impulses.
SolveStats solveVelocities(const SolverSettings& settings, std::vector<SolverBody>& bodies,
                           std::vector<SolverTree>& trees, std::vector<ContactRow>& rows,
                           SolverWork& work);
/// Solves the position correction's pseudo-velocities pv, pw and pν (normal only, no friction),
/// island by island: call it after solveVelocities on the same rows (it reuses the islands).
void solvePositions(const SolverSettings& settings, std::vector<SolverBody>& bodies,
                    std::vector<SolverTree>& trees, std::vector<ContactRow>& rows,
                    SolverWork& work);
/// Σ ½ m v² + ½ w·I w over the bodies plus Σ ½ νᵀ M ν over the trees.
double kineticEnergy(const std::vector<SolverBody>& bodies, const std::vector<SolverTree>& trees);

}  // namespace sim
}  // namespace cga_rigid_sim
