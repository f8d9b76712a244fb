// The tree stage of the step (sim/stages.h): every articulated tree advances over the step with
// its integrator under gravity, the loads on its links and its joints' efforts; then its bodies'
// states are written from the tree's (doc/articulated.md#in-the-step).
#include <algorithm>
#include <cmath>
#include <limits>

#include "cga_rigid_sim/sim/stages.h"
#include "contact/contact_trees.h"
#include "sim/tree_faults.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// The guards' tolerances (doc/articulated.md#faults).
// A joint may end past its limit by round-off only: every integrator and the contacts stage keep
// it within (the midpoint and the contact solve by impulses, then a clamp of q).
constexpr double kLimitTolerance = 1e-9;  // rad or m
// What a step in which a limit stopped a joint took (the stop's impulse is not a force whose work
// could be summed): the energy before plus the inputs' work (trapezoidal) minus the energy after.
// The energies come from kinematics the step has anyway where it can: the end state's from the
// integrator (lastKinematics), the start's from the last limited step's end when the tree starts
// from that very state (a robot resting on its stops: every step is limited); the start's
// kinematics are made only for applied loads' power or a state changed in between.
double limitedStepBook(const Model& model, Data& data, int t) {
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  TreeData& td = data.trees[t];
  dynamics::TreeKinematics& kin = data.tree_scratch.book_kin;
  const bool applied = std::any_of(td.loads.applied.begin(), td.loads.applied.end(),
                                   [](const dynamics::Loads* l) { return l != nullptr; });
  TreeData::LimitedEnd& last = td.limited_end;
  const bool from_last = last.valid && !applied && last.q == td.q_before && last.v == td.v_before &&
                         last.M_W0.coefficients() == td.M_W0_before.coefficients() &&
                         last.omega_0.rot == td.omega_0_before.rot &&
                         last.omega_0.trans == td.omega_0_before.trans;
  double E0 = 0.0, P0 = 0.0;
  if (from_last) {
    E0 = last.energy;
    P0 = td.loads.effort.dot(td.v_before);  // treeInputPower without applied loads
  } else {
    dynamics::TreeState& before = data.tree_scratch.before;
    before = td.state;
    before.q = td.q_before;
    before.v = td.v_before;
    before.M_W0 = td.M_W0_before;
    before.omega_0 = td.omega_0_before;
    dynamics::treeKinematics(tree, before, kin);
    E0 = treeEnergy(model, t, kin);
    P0 = treeInputPower(model, data, t, kin, before.v);
  }
  const dynamics::TreeKinematics* end = td.integrator->lastKinematics();
  if (!end) {
    dynamics::treeKinematics(tree, td.state, kin);
    end = &kin;
  }
  const double P1 = treeInputPower(model, data, t, *end, td.state.v);
  const double E1 = treeEnergy(model, t, *end);
  last.valid = true;
  last.energy = E1;
  last.q = td.state.q;  // (vectors of the same size: no allocation)
  last.v = td.state.v;
  last.M_W0 = td.state.M_W0;
  last.omega_0 = td.state.omega_0;
  return E0 + 0.5 * model.config.dt * (P0 + P1) - E1;
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
  TreeFaults& f = recordTreeFault(data, t, TreeFaults::Rule::kLimit);
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

// The links' states from the tree's after its step: from `kin`, the kinematics of its state,
// when the step has them, else recomputed (writeTreeBodies).
void writeBodies(const Model& model, Data& data, int t, const dynamics::TreeKinematics* kin) {
  const TreeModel& tm = model.trees[t];
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
    // The actuators: held effort plus the timed ones and the controllers', clamped to
    // <limit effort> (a servo's torque adds in the tree step, clamped again with it).
    td.loads.effort = td.held_effort + td.controller_effort;
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
    // Loads and impulses are in ν already after a contact kick: the step drifts.
    td.integrator->step(tm.body, contact_step ? td.drift_loads : td.loads, model.config.dt,
                        td.state);
    // With servos, the effort the actuators applied (the contacts stage's kick has set it in a
    // contact step): reported, and what a limited step's book counts as their work.
    if (const Eigen::VectorXd* applied = td.integrator->lastEffort(); applied && !contact_step)
      td.loads.effort = *applied;
    // The invariants of the step (doc/articulated.md#faults); a broken one undoes the step.
    bool broken = false;
    if (!td.state.allFinite()) {
      recordTreeFault(data, t, TreeFaults::Rule::kNotFinite);
      broken = true;
    } else if (!td.integrator->lastSolved()) {
      recordTreeFault(data, t, TreeFaults::Rule::kNotSolved);
      broken = true;
    } else if (contact_step) {
      // The limits first: the contact step's correction clamps to them, which would hide a
      // breach as a jump in energy.
      broken = limitBroken(model, data, t) || !finishTreeContactStep(model, data, t);
    } else if (td.integrator->lastLimited()) {
      data.dissipated_energy += limitedStepBook(model, data, t);
    } else {
      data.dissipated_energy += td.integrator->lastDissipated();
    }
    if (!broken && !contact_step) broken = limitBroken(model, data, t);
    if (broken) {
      undoFaultyStep(model, data, t, contact_step);
      writeTreeBodies(model, data, t);
    } else if (contact_step) {  // the kinematics of its end state: finishTreeContactStep's
      writeBodies(model, data, t, &data.tree_scratch.end_kin);
    } else {  // the integrator's, when it has them
      writeBodies(model, data, t, td.integrator->lastKinematics());
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
