// The stages of one step k, over [t_k, t_{k+1}], t_k = k·dt. World::step() runs them in this
// order (doc/architecture.md draws the pipeline):
//
//   applyDueInputs   inputs due at step k, in (step, arrival) order: an impulse makes Ω_B jump
//                    by (I∧n)⁻¹ T_imp, doc/conventions.md (E17) (the pose does not jump; the
//                    body's integrator is reset), a wrench starts (stage_inputs.cc);
//   controlJoints    controller commands due at k take effect; every controller sets its
//                    joints' servos and feed-forward efforts (sim/controllers/stage_control.cc,
//                    declared in sim/controllers/controllers.h);
//   updateLoads      each body's loads become gravity plus its active wrenches, summed in the
//                    order they started — rebuilt only for bodies whose set changed
//                    (stage_loads.cc);
//   loadTrees        each articulated tree's loads for the step: its links' applied loads, its
//                    joints' held and timed efforts clamped to their limits (stage_trees.cc);
//   solveContacts    contacts found at the step's start (broad, then narrow phase); every body
//                    in one, and every tree with a link in one, is kicked by its loads and the
//                    contact impulses, solved together, act on it as user impulses do
//                    (contact_step.cc and its sub-stages in contact_step.h, doc/contacts.md);
//   integrateTrees   every articulated tree over the step with its tree integrator (gravity and
//                    its loads; a tree the contacts stage kicked drifts without them, and its
//                    contact step ends in contact/contact_tree_end.cc); its bodies' states are
//                    then written from the tree's (stage_trees.cc, doc/articulated.md);
//   integrateBodies  every moving body over [t_k, t_{k+1}] with its integrator (a body the
//                    contacts stage kicked drifts torque-free and without gravity, and its
//                    contact step ends in contact/contact_drift.cc); a body with no
//                    load and Ω_B = 0 is at rest under every integrator and is skipped; then the
//                    clock advances, t = (k + 1)·dt (stage_integrate.cc). The bodies are
//                    independent here, so a WorkerPool may split them between threads;
//   expireInputs     wrenches and timed joint efforts whose last step was k end; their loads
//                    drop out at the next updateLoads (stage_expire.cc).
//
// Every stage is a free function over (const Model&, Data&), allocation-free and
// deterministic: the same Model, Data and queued inputs give bit-identical states.
#pragma once

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/worker_pool.h"

namespace cga_rigid_sim {
namespace sim {

void applyDueInputs(const Model& model, Data& data);
void updateLoads(const Model& model, Data& data);
/// `pool` (may be null: one thread) splits the bodies when there are at least
/// kMinBodiesPerThread per thread; the result is the same bit for bit either way.
void integrateBodies(const Model& model, Data& data, WorkerPool* pool = nullptr);
/// Detects the contacts, kicks every body that has one by its loads, solves the contact
/// impulses together and applies them (doc/contacts.md); marks those bodies for a torque-free
/// drift in integrateBodies.
void solveContacts(const Model& model, Data& data);

/// Fewer bodies than this per thread are integrated on the calling thread alone: handing a
/// step to the workers and waiting for them (two wake-ups through a condition variable) costs
/// the time of a few hundred body-steps, so below this it is not worth it
/// (doc/decisions.md#threads).
constexpr std::size_t kMinBodiesPerThread = 256;
void expireInputs(const Model& model, Data& data);
/// Sets every tree's loads for the step (efforts clamped and counted, links' applied loads).
void loadTrees(const Model& model, Data& data);
/// Advances every articulated tree and writes its bodies' states.
void integrateTrees(const Model& model, Data& data);
/// Timed joint efforts whose last step was the one just done end (called by expireInputs).
void expireEfforts(Data& data);

}  // namespace sim
}  // namespace cga_rigid_sim
