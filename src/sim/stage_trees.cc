// The tree stage of the step (sim/stages.h): every articulated tree advances over the step with
// its integrator under gravity, the loads on its links and its joints' efforts; then its bodies'
// states are written from the tree's (doc/articulated.md#in-the-step).
#include <algorithm>
#include <cmath>
#include <limits>

#include "cga_rigid_sim/sim/stages.h"
#include "contact/contact_trees.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// The guards' tolerances (doc/articulated.md#faults).
// A joint may end past its limit by round-off only: every integrator and the contacts stage keep
// it within (the midpoint and the contact solve by impulses, then a clamp of q).
constexpr double kLimitTolerance = 1e-9;  // rad or m
// A contact step's energy may rise by the kick-and-drift's own error (symplectic Euler, first
// order: ½ h² (ν̇ᵀ M ν̇ − νᵀ ∂Q/∂q ν) per step, either sign, TreeData::contact_energy_slack
// bounds it), ten times that, plus the drift's and the energies' round-off. A contact solve that
// creates energy (the faults this guards against gained joules in one step) is far above.
constexpr double kEnergySlackFactor = 10.0;
constexpr double kEnergyTolerance = 1e-9;
// A floating tree's momentum after a contact step equals the one before plus the loads' and
// the external contacts' impulses, to round-off of the sums that carry it (the kick's M⁻¹, the
// midpoint's carried momentum, the links' momenta): relative to the momenta involved.
constexpr double kMomentumTolerance = 1e-9;

// Counts a fault of tree t and describes it (TreeFaults); the step then undoes it.
TreeFaults& recordFault(Data& data, int t, TreeFaults::Rule rule) {
  TreeFaults& f = data.tree_faults;
  ++f.count;
  f.tree = t;
  f.step = data.step_count + 1;
  f.rule = rule;
  f.joint = f.body_a = f.body_b = -1;
  f.value = f.bound = 0.0;
  return f;
}

// The deepest contact of tree t in this step (its bodies, for the fault's message).
void deepestContactOf(const Model& model, const Data& data, int t, TreeFaults& f) {
  double deepest = -std::numeric_limits<double>::infinity();
  const auto inTree = [&](int j) {
    const int i = j < 0 ? -1 : model.moving_of_body[j];
    return i >= 0 && model.tree_of_moving[i] == t;
  };
  for (const Contact& c : data.contacts)
    if ((inTree(c.body_a) || inTree(c.body_b)) && c.depth > deepest) {
      deepest = c.depth;
      f.body_a = c.body_a;
      f.body_b = c.body_b;
    }
}

// A floating tree at the pose of `s` (kin: its poses): the base bivelocity that gives it the world
// momentum Pi with the joint rates of s, and its kinetic energy split into the part it would
// have with its joints locked and the joints' motion relative to the base: with
// M = [[B, C], [Cᵀ, D]] over (base, joints) and π the momentum in the base's frame,
// Ω_0 = B⁻¹ (π − C q̇), T = ½ πᵀ B⁻¹ π + ½ q̇ᵀ (D − Cᵀ B⁻¹ C) q̇.
struct MomentumSplit {
  Eigen::Matrix<double, 6, 1> omega_0;
  double T_locked = 0.0, T_internal = 0.0;
};
MomentumSplit splitMomentum(const dynamics::ArticulatedBody& tree,
                            const dynamics::TreeKinematics& kin, const dynamics::TreeState& s,
                            const cga::Moment& Pi, double lambda, TreeStageScratch& scratch) {
  Eigen::MatrixXd& M = scratch.split_M;
  Eigen::VectorXd& Dv = scratch.split_Dv;
  const int n = tree.jointCount();
  dynamics::massMatrix(tree, kin, M, scratch.algorithms);
  Dv.noalias() = M.bottomRightCorner(n, n) * s.v;
  const cga::Moment base = s.M_W0.reverse().apply(Pi, lambda);
  Eigen::Matrix<double, 6, 1> pi;
  pi << base.rot, base.trans;
  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> B(M.topLeftCorner<6, 6>());
  const Eigen::Matrix<double, 6, 1> Cv = M.topRightCorner(6, n) * s.v;
  const Eigen::Matrix<double, 6, 1> B_pi = B.solve(pi), B_Cv = B.solve(Cv);
  MomentumSplit out;
  out.omega_0 = B_pi - B_Cv;
  out.T_locked = 0.5 * pi.dot(B_pi);
  out.T_internal = 0.5 * (s.v.dot(Dv) - Cv.dot(B_Cv));
  return out;
}

// After a contact step's drift: the position correction moves the tree by h pν, paid for from
// its kinetic energy when it raises the tree's energy (as for free bodies,
// doc/contacts.md#energy). A floating tree keeps its world momentum through the move: its
// joints move at their rates, its base's bivelocity is solved from the momentum at the moved
// pose, and what the move costs is paid from the energy of the joints' motion relative to the
// base (T = T_locked + s² T_internal with the rates scaled by s), so that a correction — an
// internal contact's above all — never changes the tree's momentum. Then the step's energy is
// booked: what the tree had plus the inputs' work (trapezoidal) minus what it has now. Returns
// what was booked, J (negative: the step created energy).
double endContactStep(const Model& model, Data& data, int t) {
  const TreeModel& tm = model.trees[t];
  TreeData& td = data.trees[t];
  const dynamics::ArticulatedBody& tree = tm.body;
  const double h = model.config.dt, lambda = model.lambda;
  const int n = tree.jointCount();
  dynamics::TreeKinematics& kin = data.tree_scratch.end_kin;
  dynamics::TreeState& moved = data.tree_scratch.moved;
  if (!td.contact_shift.isZero(0.0)) {
    dynamics::treeKinematics(tree, td.state, kin);
    const double T = dynamics::kineticEnergy(tree, kin);
    const double E0 = treeEnergy(model, t, kin);
    const cga::Moment Pi = dynamics::worldMomentum(tree, kin);
    const auto moveBy = [&](double f, dynamics::TreeState& s) {
      s = td.state;
      if (tree.floating())
        s.M_W0 = s.M_W0 * cga::exp(cga::Bivelocity(td.contact_shift.head<3>(),
                                                   td.contact_shift.segment<3>(3)) *
                                   (-0.5 * f * h));
      s.q += f * h * td.contact_shift.tail(n);
      for (int k = 0; k < n; ++k) {  // within the limits (the solver kept it so, to round-off)
        const dynamics::TreeJoint& j = tree.joints()[k];
        if (j.hasLimits()) s.q[k] = std::clamp(s.q[k], j.lower, j.upper);
      }
      if (tree.hasMimic()) dynamics::applyMimicPositions(tree, s.q);  // followers on leaders
    };
    moveBy(1.0, moved);
    dynamics::treeKinematics(tree, moved, kin);
    if (!tree.floating()) {
      const double dU = treeEnergy(model, t, kin) - E0;
      double f = 1.0, scale = 1.0;
      if (dU > 0) {
        f = std::min(1.0, 0.5 * T / dU);
        if (T > 0) scale = std::sqrt(std::max(0.0, 1.0 - f * dU / T));
      }
      moveBy(f, td.state);
      td.state.v *= scale;
    } else {
      const MomentumSplit full = splitMomentum(tree, kin, moved, Pi, lambda, data.tree_scratch);
      const double U_moved = treeEnergy(model, t, kin) - dynamics::kineticEnergy(tree, kin);
      const double dU = U_moved + full.T_locked + full.T_internal - E0;
      double f = 1.0, s = 1.0;
      if (dU > 0) {
        f = full.T_internal > 0 ? std::min(1.0, 0.5 * full.T_internal / dU) : 0.0;
        if (full.T_internal > 0) s = std::sqrt(std::max(0.0, 1.0 - f * dU / full.T_internal));
      }
      moveBy(f, td.state);
      td.state.v *= s;
      dynamics::treeKinematics(tree, td.state, kin);
      const MomentumSplit end = splitMomentum(tree, kin, td.state, Pi, lambda, data.tree_scratch);
      td.state.omega_0 = cga::Bivelocity(end.omega_0.head<3>(), end.omega_0.tail<3>());
    }
  }
  dynamics::treeKinematics(tree, td.state, kin);
  // The inputs' work, trapezoidal from the rates before the kick to those at the end: for a
  // constant effort ½ h τ·(ν + ν'), exactly what it adds to the kinetic energy when nothing else
  // acts, and none while a contact or a stop holds the effort (the kick's own work, ½ h τ·(ν +
  // ν + h M⁻¹τ), would book a phantom input and its dissipation in every step a gripper holds).
  td.contact_book_work =
      0.5 * h * (td.contact_power_start + treeInputPower(model, data, t, kin, td.state.v));
  const double booked = td.contact_energy_start + td.contact_book_work - treeEnergy(model, t, kin);
  td.contact_kicked = false;
  td.integrator->reset();
  return booked;
}

// What a step in which a limit stopped a joint took (the stop's impulse is not a force whose work
// could be summed): the energy before plus the inputs' work (trapezoidal) minus the energy after.
double limitedStepBook(const Model& model, Data& data, int t) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  const TreeData& td = data.trees[t];
  dynamics::TreeKinematics& kin = data.tree_scratch.book_kin;
  dynamics::TreeState& before = data.tree_scratch.before;
  before = td.state;
  before.q = td.q_before;
  before.v = td.v_before;
  before.M_W0 = td.M_W0_before;
  before.omega_0 = td.omega_0_before;
  dynamics::treeKinematics(tree, before, kin);
  const double E0 = treeEnergy(model, t, kin);
  const double P0 = treeInputPower(model, data, t, kin, before.v);
  dynamics::treeKinematics(tree, td.state, kin);
  const double P1 = treeInputPower(model, data, t, kin, td.state.v);
  return E0 + 0.5 * model.config.dt * (P0 + P1) - treeEnergy(model, t, kin);
}

// A contact step's fault of `rule`: its value and bound, named by the tree's deepest contact.
void contactFault(const Model& model, Data& data, int t, TreeFaults::Rule rule, double value,
                  double bound) {
  TreeFaults& f = recordFault(data, t, rule);
  f.value = value;
  f.bound = bound;
  deepestContactOf(model, data, t, f);
}

// The checks of a contact step (doc/articulated.md#faults): the energy may not rise beyond the
// inputs' work, a floating tree's momentum must be the expected one. Records the fault and
// returns true when one is broken.
bool contactStepBroken(const Model& model, Data& data, int t, double booked) {
  const TreeModel& tm = model.trees[t];
  const TreeData& td = data.trees[t];
  dynamics::TreeKinematics& kin = data.tree_scratch.check_kin;
  dynamics::treeKinematics(tm.body, td.state, kin);
  const double T = dynamics::kineticEnergy(tm.body, kin);
  const double energy_bound = kEnergySlackFactor * td.contact_energy_slack +
                              kEnergyTolerance * (T + std::abs(td.contact_energy_start)) + 1e-12;
  // What the contacts did to the energy the kick left (the kick's work is what it added, and
  // the transfer is what impulses of other moving bodies handed over at the same velocities);
  // the book holds the trapezoidal work instead, which differs by what the contact took of the
  // kick's rates, ½ h τ·(ν_kicked − ν').
  const double rise = -(booked + td.contact_kick_work - td.contact_book_work) - td.contact_transfer;
  if (rise > energy_bound) {
    contactFault(model, data, t, TreeFaults::Rule::kEnergy, rise, energy_bound);
    return true;
  }
  if (!tm.body.floating()) return false;
  const double lambda = model.lambda;
  const cga::Moment Pi = dynamics::worldMomentum(tm.body, kin);
  const cga::Moment& expected = td.contact_momentum_expected;
  double reach = 0.0;  // the links' distance from the world origin: the moments' lever arms
  for (int b = 0; b < tm.body.bodyCount(); ++b)
    reach = std::max(reach, kin.M_W[b].translation(lambda).norm());
  // The impulses keep it (a tree's contacts with itself cancel); the drift keeps it too, to
  // round-off where the integrator conserves momentum, else to its truncation (not checked).
  const auto distance = [&](const cga::Moment& a, const cga::Moment& b) {
    return std::max((a.force(lambda) - b.force(lambda)).norm(),
                    (a.torque() - b.torque()).norm() / std::max(reach, 1.0));
  };
  const cga::Moment& solved = td.contact_momentum_solved;
  double error = distance(solved, expected);
  if (td.integrator->conservesMomentum()) error = std::max(error, distance(Pi, solved));
  const double momentum_bound = kMomentumTolerance * (td.contact_momentum_scale + 1e-9);
  if (error > momentum_bound) {
    contactFault(model, data, t, TreeFaults::Rule::kMomentum, error, momentum_bound);
    return true;
  }
  return false;
}

// A joint past its limit beyond round-off: records the fault (the worst joint).
bool limitBroken(const Model& model, Data& data, int t) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  const Eigen::VectorXd& q = data.trees[t].state.q;
  int worst = -1;
  double past = kLimitTolerance, limit = 0.0;
  for (int k = 0; k < tree.jointCount(); ++k) {
    const dynamics::TreeJoint& j = tree.joints()[k];
    const double below = j.lower - q[k], above = q[k] - j.upper;
    if (below > past) worst = k, past = below, limit = j.lower;
    if (above > past) worst = k, past = above, limit = j.upper;
  }
  if (worst < 0) return false;
  TreeFaults& f = recordFault(data, t, TreeFaults::Rule::kLimit);
  f.joint = worst;
  f.value = q[worst];
  f.bound = limit;
  return true;
}

// A step that broke an invariant is undone: the tree is put back at rest at the pose it had
// before the step (the contacts stage may have kicked it, which is undone too) and its integrator
// reset; the kinetic energy it had is booked as dissipated, so the book still balances. It is
// tried again in the next step. The integrators break an invariant only where the tree's mass
// matrix cannot be factored in double precision (a link implausibly far from its joint: 10⁷ m
// and more in the fuzz findings), or the contact solve would otherwise have created energy or
// momentum; every such step is counted (World::lastTreeFault).
void undoFaultyStep(const Model& model, Data& data, int t, bool contact_step) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  TreeData& td = data.trees[t];
  dynamics::TreeKinematics& kin = data.tree_scratch.undo_kin;
  td.state.q = td.q_before;
  td.state.M_W0 = td.M_W0_before;
  double E_before = td.contact_energy_start;  // before the kick (a contact step)
  if (!contact_step) {
    td.state.v = td.v_before;
    td.state.omega_0 = td.omega_0_before;
    dynamics::treeKinematics(tree, td.state, kin);
    E_before = treeEnergy(model, t, kin);
  }
  td.state.v.setZero();
  td.state.omega_0 = cga::Bivelocity();
  dynamics::treeKinematics(tree, td.state, kin);
  const double booked = E_before - treeEnergy(model, t, kin);
  if (std::isfinite(booked)) data.dissipated_energy += booked;
  td.contact_kicked = false;  // the kick is undone with the rest
  td.integrator->reset();
}

// The links' states from the tree's after its step: from the kinematics the integrator left,
// when it has them, else recomputed (writeTreeBodies).
void writeBodies(const Model& model, Data& data, int t) {
  const TreeModel& tm = model.trees[t];
  const dynamics::TreeKinematics* kin = data.trees[t].integrator->lastKinematics();
  if (!kin) return writeTreeBodies(model, data, t);
  for (int b = tm.body.floating() ? 0 : 1; b < tm.body.bodyCount(); ++b) {
    MovingBodyData& body = data.bodies[tm.movingOf(b)];
    body.state = {kin->M_W[b], kin->omega[b]};
    body.last_path = StepPath::kStepped;
  }
}

}  // namespace

void loadTrees(const Model& model, Data& data) {
  for (int t = 0; t < static_cast<int>(model.trees.size()); ++t) {
    const TreeModel& tm = model.trees[t];
    TreeData& td = data.trees[t];
    // The actuators: held effort plus the timed ones, clamped to <limit effort>.
    td.loads.effort = td.held_effort;
    for (const ActiveEffort& a : td.timed) td.loads.effort[a.joint] += a.effort;
    for (int k = 0; k < tm.body.jointCount(); ++k) {
      const double limit = tm.body.joints()[k].effort_limit;
      double& e = td.loads.effort[k];
      if (std::abs(e) > limit) {
        e = std::clamp(e, -limit, limit);
        ++td.clamped_steps[k];
      }
    }
    for (int b = 0; b < tm.body.bodyCount(); ++b) {
      const int i = tm.movingOf(b);
      td.loads.applied[b] =
          i >= 0 && data.bodies[i].loads.hasApplied() ? &data.bodies[i].loads : nullptr;
    }
  }
}

void integrateTrees(const Model& model, Data& data) {
  for (int t = 0; t < static_cast<int>(model.trees.size()); ++t) {
    const TreeModel& tm = model.trees[t];
    TreeData& td = data.trees[t];
    if (td.asleep) continue;  // at rest with its island (doc/contacts.md#sleeping)
    // The contacts stage changed only velocities: this is the pose before the step. (Copies
    // between vectors of the same size: no allocation.)
    td.q_before = td.state.q;
    td.M_W0_before = td.state.M_W0;
    td.v_before = td.state.v;
    td.omega_0_before = td.state.omega_0;
    const bool contact_step = td.contact_kicked;
    if (contact_step && tm.body.floating()) {  // what the impulses left, for the momentum guard
      dynamics::TreeKinematics& kin = data.tree_scratch.solved_kin;
      dynamics::treeKinematics(tm.body, td.state, kin);
      td.contact_momentum_solved = dynamics::worldMomentum(tm.body, kin);
    }
    // Loads and impulses are in ν already after a contact kick: the step drifts.
    td.integrator->step(tm.body, contact_step ? td.drift_loads : td.loads, model.config.dt,
                        td.state);
    // The invariants of the step (doc/articulated.md#faults); a broken one undoes the step.
    bool broken = false;
    if (!td.state.allFinite()) {
      recordFault(data, t, TreeFaults::Rule::kNotFinite);
      broken = true;
    } else if (!td.integrator->lastSolved()) {
      recordFault(data, t, TreeFaults::Rule::kNotSolved);
      broken = true;
    } else if (contact_step) {
      // The limits first: the correction in endContactStep clamps to them, which would hide a
      // breach as a jump in energy.
      broken = limitBroken(model, data, t);
      if (!broken) {
        const double booked = endContactStep(model, data, t);
        broken = contactStepBroken(model, data, t, booked);
        if (!broken) data.dissipated_energy += booked;
      }
    } else if (td.integrator->lastLimited()) {
      data.dissipated_energy += limitedStepBook(model, data, t);
    } else {
      data.dissipated_energy += td.integrator->lastDissipated();
    }
    if (!broken && !contact_step) broken = limitBroken(model, data, t);
    if (broken) {
      undoFaultyStep(model, data, t, contact_step);
      writeTreeBodies(model, data, t);
    } else if (contact_step) {
      writeTreeBodies(model, data, t);
    } else {
      writeBodies(model, data, t);
    }
  }
}

void expireEfforts(Data& data) {
  for (TreeData& td : data.trees)
    td.timed.erase(
        std::remove_if(td.timed.begin(), td.timed.end(),
                       [&](const ActiveEffort& a) { return a.end_step <= data.step_count; }),
        td.timed.end());
}

}  // namespace sim
}  // namespace cga_rigid_sim
