// Data: everything of a World that changes as it runs — time, the moving bodies' states, their
// integrators' caches and loads, the queued and active inputs. Made from a Model (makeData);
// the stages of the step (sim/stages.h) read the Model and write the Data.
//
// A per-moving-body datum is one member of MovingBodyData: it is made in one place
// (makeBodyData), reset by remaking it and erased with its body (sim/topology.cc).
//
// Work arrays live here too (Data::tree_scratch, Data::contact_scratch) or in the caches of the
// integrators: the step keeps no state anywhere else, and allocates nothing once they have grown.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/body/integrator.h"
#include "cga_rigid_sim/body/loads.h"
#include "cga_rigid_sim/contact/contact.h"
#include "cga_rigid_sim/curved/curved_integrator.h"
#include "cga_rigid_sim/math/cholesky.h"
#include "cga_rigid_sim/sim/controllers/controllers_data.h"
#include "cga_rigid_sim/sim/input/input_queue.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/tree/tree_integrator.h"
#include "cga_rigid_sim/tree/tree_workspace.h"

namespace cga_rigid_sim {
namespace sim {

/// What the last step did with a body (for the summary).
enum class StepPath : std::uint8_t { kNotStepped, kStepped, kAtRest };

/// A wrench that has started: its load (point in B) and the first step it no longer acts in.
struct ActiveWrench {
  std::uint64_t end_step = kUntilCleared;
  dynamics::AppliedLoad load;
};

/// The changing part of one moving body.
struct MovingBodyData {
  dynamics::BodyState state;                         ///< motor M_WB, bivelocity Ω_B
  std::unique_ptr<dynamics::Integrator> integrator;  ///< one per body (it may cache)
  dynamics::Loads loads;                             ///< gravity + its active wrenches
  bool loads_dirty = false;  ///< its set of active wrenches changed this step
  /// Its started wrenches, in the order they started (its loads sum them in that order).
  std::vector<ActiveWrench> wrenches;
  StepPath last_path = StepPath::kNotStepped;
  /// What the contacts stage did with the body this step (doc/contacts.md#time-stepping).
  enum class ContactStep : std::uint8_t {
    kNone,   ///< nothing: the integrator takes the whole step
    kDrift,  ///< kicked Ω_B by loads and impulses: the integration only drifts, torque-free
    kDone,   ///< landed within the step and stepped through it: the integration skips it
  };
  ContactStep contact_step = ContactStep::kNone;
  /// Added to the centre of mass after that drift: h (v_start − v_end)/2 along the contact
  /// plane when every contact of the body shares one normal, so its sliding is trapezoidal
  /// (doc/contacts.md#time-stepping); zero otherwise.
  Eigen::Vector3d contact_shift_W = Eigen::Vector3d::Zero();
  /// A body in contact carries its momentum from one contact step to the next in world axes
  /// (src/contact/contact_momentum.h, doc/contacts.md#world-momentum): its centre's velocity and
  /// its angular momentum about the centre, each a compensated sum hi + lo. It holds while the
  /// state is the one the last contact drift left (the key); anything else that changes the state
  /// makes the next contact step start again from the state.
  struct ContactMomentum {
    Eigen::Vector3d v_hi = Eigen::Vector3d::Zero(), v_lo = Eigen::Vector3d::Zero();  ///< m/s
    Eigen::Vector3d L_hi = Eigen::Vector3d::Zero(), L_lo = Eigen::Vector3d::Zero();  ///< N m s
    cga::Bivelocity key_omega_B;                      ///< the Ω_B the drift left
    Eigen::Vector4d key_r = Eigen::Vector4d::Zero();  ///< its rotor's coefficients
    bool valid = false;    ///< set by the drift: the key is the state it left
    bool pending = false;  ///< set by the contacts stage: this step's drift reads Ω_B off it
  };
  ContactMomentum contact_momentum;
  /// Coasting (src/sim/coasting.h): while a body's motion is a closed form in the elapsed time
  /// (its integrator coasts() under its loads) and nothing else acts on it, it takes no step;
  /// `state` is then evaluated from `from` and the steps since, when it is read. Whether it
  /// coasts is Data::coasting[i].
  struct Coast {
    std::uint64_t start = 0;   ///< Data::step_count when `from` was the state
    std::uint64_t synced = 0;  ///< `state` is the state at this step count
    dynamics::BodyState from;  ///< the state the coast started at
  };
  Coast coast;
  /// Curved space only: the 1-up state (ψ, Ω_B) and its integrator; `state` then mirrors it in
  /// the chart after every step (sim/curved_bodies.h).
  dynamics::CurvedBodyState curved_state;
  std::unique_ptr<dynamics::CurvedIntegrator> curved_integrator;
};

struct ContactScratch;  // the contacts stage's geometry and arrays (src/contact/contact_scratch.h)

/// A timed effort that has started on one joint of a tree.
struct ActiveEffort {
  int joint = -1;  ///< joint index in the tree
  double effort = 0.0;
  std::uint64_t end_step = kUntilCleared;
};

/// The changing part of one articulated tree (doc/articulated.md).
struct TreeData {
  dynamics::TreeState state;
  std::unique_ptr<dynamics::TreeIntegrator> integrator;
  dynamics::TreeLoads loads;    ///< gravity, the links' applied loads, this step's efforts
  Eigen::VectorXd held_effort;  ///< per joint: the last commanded effort (~joint_efforts)
  /// Per joint: the controllers' feed-forward effort for this step (integral term, velocity
  /// feed-forward, a group effort command), set by the control stage.
  Eigen::VectorXd controller_effort;
  std::vector<ActiveEffort> timed;           ///< started timed efforts (~apply_joint_effort)
  std::vector<std::uint64_t> clamped_steps;  ///< per joint: steps its effort was clamped
  /// The contacts stage kicked the tree and applied its contact impulses this step: the tree
  /// stage then only drifts it, with `drift_loads` (none), and books the step's energy
  /// (doc/contacts.md#trees).
  bool contact_kicked = false;
  dynamics::TreeLoads drift_loads;    ///< no gravity, no applied loads, zero efforts
  Eigen::VectorXd contact_shift;      ///< the position correction's pseudo-velocity pν
  double contact_energy_start = 0.0;  ///< J, kinetic + potential before the kick
  double contact_power_start = 0.0;   ///< W, of the inputs before the kick
  /// J, the inputs' work as the kick added it to the kinetic energy (the energy guard's), and
  /// trapezoidal over the step (the book's: none while a contact holds an effort)
  double contact_kick_work = 0.0, contact_book_work = 0.0;
  /// J: the work the impulses of contacts with other moving bodies did on the tree, P·ū with ū
  /// the mean of its contact point's velocities before and after them: energy handed over, not
  /// created (the energy guard allows it).
  double contact_transfer = 0.0;
  /// J: how far the kick-and-drift's own first-order error may move the energy in this step,
  /// h² (τ + Q)ᵀ M⁻¹ (τ + Q) + (h |ν|∞)² T — the scale of the energy guard's tolerance.
  double contact_energy_slack = 0.0;
  /// The world momentum (about the world origin) the step must end with: the one before the
  /// kick plus the loads' impulse h W and the impulses of contacts with anything but the tree
  /// itself (internal ones cancel). A floating tree's contact step is checked against it.
  cga::Moment contact_momentum_expected;
  /// A floating tree's world momentum after the contact impulses, before the drift.
  cga::Moment contact_momentum_solved;
  /// Its scale, kg m/s: the links' momenta, the loads' and contacts' impulses (the guard's
  /// tolerance is relative to it).
  double contact_momentum_scale = 0.0;
  /// Asleep with its contact island (doc/contacts.md#sleeping): at rest, not stepped, until
  /// something wakes the island; `asleep_effort` holds the efforts it fell asleep under (a new
  /// command wakes it).
  bool asleep = false;
  Eigen::VectorXd asleep_effort;
  Eigen::VectorXd asleep_q;  ///< the pose it fell asleep at (a pose set from outside wakes it)
  /// The state before this step (joint positions and rates, the floating root's motor and
  /// bivelocity), for undoing a step that breaks an invariant (TreeFaults).
  Eigen::VectorXd q_before, v_before;
  cga::Motor M_W0_before;
  cga::Bivelocity omega_0_before;
  /// The energy at the end of its last step that a joint stop limited, and that end state: the
  /// book of a next limited step starting from the very same state takes its energy from here
  /// instead of a kinematics pass (stage_trees.cc). Sized when the tree's data is made.
  struct LimitedEnd {
    bool valid = false;
    double energy = 0.0;  ///< J, kinetic plus potential
    Eigen::VectorXd q, v;
    cga::Motor M_W0;
    cga::Bivelocity omega_0;
  } limited_end;
  /// The generalized velocity ν after the contact impulses (takeTreeImpulses' work array, sized
  /// velocityCount()).
  Eigen::VectorXd contact_nu;
  /// The kinematics of the state its last contact step ended in, and M(q) there when that step
  /// had it: the next contact step's kick takes them when it starts from that very state
  /// (contact_trees.cc) instead of making them again.
  struct ContactEnd {
    bool valid = false, has_mass = false;
    dynamics::TreeKinematics kin;
    Eigen::MatrixXd M;
    dynamics::TreeState state;
  } contact_end;
};

/// Work arrays of the tree stages, kept in the Data so that a step allocates nothing once they
/// have grown to its largest tree (the stages take the trees one at a time). Each member belongs
/// to the function named with it, so no call overwrites what its caller still reads.
struct TreeStageScratch {
  dynamics::TreeWorkspace algorithms;  ///< the tree algorithms' (mass matrix, ABA, …)
  dynamics::TreeKinematics write_kin;  ///< writeTreeBodies: the tree's poses and velocities
  dynamics::TreeKinematics sleep_kin;  ///< putTreeToSleep: the tree's energy
  /// correctAndBook (contact_tree_end.cc): the tree's kinematics, and the tree moved by the
  /// position correction
  dynamics::TreeKinematics end_kin;
  dynamics::TreeState moved;
  Eigen::MatrixXd split_M;   ///< correctTree: the mass matrix at the corrected pose
  Eigen::VectorXd split_Dv;  ///< correctTree: D q̇
  /// limitedStepBook: the kinematics of the state before the step and after it
  dynamics::TreeKinematics book_kin;
  dynamics::TreeState before;
  dynamics::TreeKinematics solved_kin;  ///< takeTreeImpulses: the kinematics after the impulses
  dynamics::TreeKinematics undo_kin;    ///< undoFaultyStep
  /// kickTree (contact_trees.cc): the tree's kinematics and at rest, its state at rest, the
  /// loads' moments, ν̇ and M ν̇, the reduced mass matrix.
  struct Kick {
    dynamics::TreeKinematics kin, still;
    dynamics::TreeState state;
    dynamics::BodyMoments f;
    Eigen::VectorXd nu_dot, M_nu_dot;
    Eigen::MatrixXd M_r;
    // The servos' implicit kick (kickServos): its matrix, reduced with mimic joints, its
    // right-hand side and solution, the servo torques at the kick's start.
    Eigen::MatrixXd servo_A, servo_A_r;
    Eigen::VectorXd servo_rhs, servo_rhs_r, servo_s0;
    math::Cholesky servo_llt;
  } kick;
};

/// Tree steps that broke an invariant of the tree's motion (doc/articulated.md#faults), undone:
/// the tree was set at rest at the pose it had before the step (stage_trees.cc), its kinetic
/// energy booked as dissipated. Counted, and the last one described (without allocating in the
/// step: World::lastTreeFault() writes the message).
struct TreeFaults {
  /// The invariant the step broke.
  enum class Rule {
    kNotFinite,  ///< the state became non-finite
    kNotSolved,  ///< the implicit step did not converge within its attempts
    kLimit,      ///< a joint ended past its position limit (`joint`, `value`, `bound`)
    kEnergy,     ///< a contact step raised the energy beyond the inputs' work (`value`, `bound`)
    kMomentum,   ///< a floating tree's momentum changed by more than the external impulses
  };
  std::uint64_t count = 0;
  int tree = -1;           ///< the last one's tree (the Model's index; past the end once deleted)
  std::uint64_t step = 0;  ///< the step it happened in (1 = the first step)
  Rule rule = Rule::kNotFinite;
  int joint = -1;      ///< kLimit: the joint's index in the tree
  double value = 0.0;  ///< kLimit: its position; kEnergy: the rise, J; kMomentum: the error
  double bound = 0.0;  ///< kLimit: the limit; kEnergy, kMomentum: the tolerance
  int body_a = -1, body_b = -1;  ///< kEnergy, kMomentum: the deepest contact's bodies (b: −1 plane)
};

/// Inputs refused when due to start, past a bound on active wrenches (WorldConfig): counted,
/// and the last one described, without allocating in the step.
struct StartRefusals {
  std::uint64_t count = 0;
  QueuedInput input;       ///< the last one
  std::uint64_t step = 0;  ///< the step it was due at
  bool per_body = false;   ///< the bound per body (per tree) was reached, else the total one
  std::size_t active = 0;  ///< what was active then, counted against that bound
};

struct Data {
  std::uint64_t step_count = 0;  ///< steps done; t = step_count·dt (never goes back)

  /// Per moving body i (the Model's moving index).
  std::vector<MovingBodyData> bodies;
  /// Per moving body i: whether it coasts (MovingBodyData::coast holds the rest). The one
  /// per-body datum kept apart from MovingBodyData, so that a step over 10 000 bodies that all
  /// coast reads 10 kB, not a cache line per body; made, reset and erased with `bodies`
  /// (data.cc, state_edit.cc, topology.cc).
  std::vector<std::uint8_t> coasting;
  /// Moving indices whose loads_dirty is set (capacity: one slot per body, so no allocation).
  std::vector<int> dirty_list;

  InputQueue queue;                 ///< validated inputs waiting for their step
  std::size_t active_wrenches = 0;  ///< started wrenches of every body (MovingBodyData::wrenches)
  /// When the started wrenches of finite duration end: a min-heap on end_step, one entry per
  /// wrench, so that ending them costs O(log n) each (wrench_schedule.cc).
  struct Expiry {
    std::uint64_t end_step;
    int body;  ///< moving index
  };
  std::vector<Expiry> expiries;
  StartRefusals start_refusals;  ///< wrenches and timed efforts refused at start
  TreeFaults tree_faults;        ///< tree steps undone for non-finite results

  /// The contacts of the last step, with their impulses (contact_step.cc).
  std::vector<Contact> contacts;
  /// Gauss–Seidel sweeps the last step's contact solve took (0: no contact), for benchmarks.
  int contact_sweeps = 0;
  /// J taken out by contacts since the start or the last reset (MomentumReport).
  double dissipated_energy = 0.0;
  std::shared_ptr<ContactScratch> contact_scratch;  ///< made by the first contacts stage

  /// Per tree (the Model's tree index).
  std::vector<TreeData> trees;
  /// The joint controllers and their waiting commands (sim/controllers/).
  ControllersData controllers;
  TreeStageScratch tree_scratch;  ///< the tree stages' work arrays
};

/// The data of tree `t` at its initial state, with no effort.
Result<TreeData> makeTreeData(const Model& model, int t);
/// Writes the state of every body of tree `t` (its links, and its floating root) from the
/// tree's state.
void writeTreeBodies(const Model& model, Data& data, int t);

/// The data of a moving body at state `initial`: a fresh integrator, gravity as its only load.
/// Fails only for an unknown integrator name (compileModel has checked it) and, in curved space
/// (which needs the body's moving index), for an initial position outside the chart.
Result<MovingBodyData> makeBodyData(const Model& model, const dynamics::BodyState& initial,
                                    int moving_index = -1);
/// The Data of a new World: every moving body at its initial state, time 0, nothing queued.
Result<Data> makeData(const Model& model);

}  // namespace sim
}  // namespace cga_rigid_sim
