// The tree stage of the step (sim/stages.h): every articulated tree advances over the step with
// its integrator under gravity, the loads on its links and its joints' efforts; then its bodies'
// states are written from the tree's (doc/articulated.md#in-the-step).
#include <algorithm>
#include <cmath>

#include "cga_rigid_sim/sim/stages.h"
#include "contact_trees.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// After a contact step's drift: the position correction moves the tree by h pν, paid for from
// its kinetic energy when it lifts the tree (as for free bodies, doc/contacts.md#energy), then
// the step's energy is booked: what the tree had plus the inputs' work (trapezoidal) minus what
// it has now.
void endContactStep(const Model& model, Data& data, int t) {
  const TreeModel& tm = model.trees[t];
  TreeData& td = data.trees[t];
  const dynamics::ArticulatedBody& tree = tm.body;
  const double h = model.config.dt;
  static thread_local dynamics::TreeKinematics kin;
  static thread_local dynamics::TreeState moved;
  if (!td.contact_shift.isZero(0.0)) {
    dynamics::treeKinematics(tree, td.state, kin);
    const double T = dynamics::kineticEnergy(tree, kin);
    const double U0 = treeEnergy(model, t, kin) - T;
    moved = td.state;
    if (tree.floating())
      moved.M_W0 = moved.M_W0 * cga::exp(cga::Bivelocity(td.contact_shift.head<3>(),
                                                         td.contact_shift.segment<3>(3)) *
                                         (-0.5 * h));
    moved.q += h * td.contact_shift.tail(tree.jointCount());
    dynamics::treeKinematics(tree, moved, kin);
    const double dU = treeEnergy(model, t, kin) - T - U0;
    double f = 1.0;
    if (dU > 0) {
      f = std::min(1.0, 0.5 * T / dU);
      if (T > 0) {
        const double scale = std::sqrt(std::max(0.0, 1.0 - f * dU / T));
        td.state.omega_0 = td.state.omega_0 * scale;
        td.state.v *= scale;
      }
    }
    if (tree.floating())
      td.state.M_W0 = td.state.M_W0 * cga::exp(cga::Bivelocity(td.contact_shift.head<3>(),
                                                               td.contact_shift.segment<3>(3)) *
                                               (-0.5 * f * h));
    td.state.q += f * h * td.contact_shift.tail(tree.jointCount());
  }
  dynamics::treeKinematics(tree, td.state, kin);
  const double work =
      0.5 * h * (td.contact_power_start + treeInputPower(model, data, t, kin, td.state.v));
  data.dissipated_energy += td.contact_energy_start + work - treeEnergy(model, t, kin);
  td.contact_kicked = false;
  td.integrator->reset();
}

// A step that left non-finite numbers is undone: the tree is set at rest at the pose it had
// before the step (the contacts stage may have kicked it, which is undone too), and the fault is
// counted (World::lastTreeFault). The integrators fail so only when the tree's mass matrix
// cannot be factored in double precision at some pose of the step: in practice, a link
// implausibly far from its joint (10⁷ m and more in the fuzz findings,
// doc/articulated.md#faults). At rest the tree is tried again in the next step; a tree that
// fails there too stays where it is, and every such step is counted.
void undoFaultyStep(Data& data, int t) {
  TreeData& td = data.trees[t];
  td.state.q = td.q_before;
  td.state.M_W0 = td.M_W0_before;
  td.state.v.setZero();
  td.state.omega_0 = cga::Bivelocity();
  td.contact_kicked = false;  // the kick is undone with the rest
  td.integrator->reset();
  TreeFaults& f = data.tree_faults;
  ++f.count;
  f.tree = t;
  f.step = data.step_count + 1;
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
    // The contacts stage changed only velocities: this is the pose before the step. (Copies
    // between vectors of the same size: no allocation.)
    td.q_before = td.state.q;
    td.M_W0_before = td.state.M_W0;
    // Loads and impulses are in ν already after a contact kick: the step drifts.
    td.integrator->step(tm.body, td.contact_kicked ? td.drift_loads : td.loads, model.config.dt,
                        td.state);
    if (!td.state.allFinite()) {
      undoFaultyStep(data, t);
      writeTreeBodies(model, data, t);
    } else if (td.contact_kicked) {
      endContactStep(model, data, t);
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
