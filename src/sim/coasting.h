// Coasting (doc/architecture.md#coasting): a moving body whose motion is a closed form in the
// elapsed time — the exact flow of `exact` and `auto` with no applied load (free, or under
// gravity) — and that nothing else acts on (no tree, no collision shape, flat space) takes no
// step at all. Its state is evaluated from the state the coast started at and the steps since
// (Integrator::coast, body/free_flow.h freeFlowAt) when something reads it: a report, an
// input that acts on it, a state edit. That evaluation is a function of the starting state and
// the step count alone, so what a body does never depends on when, how often, or by how many
// threads it was read: a run observed every step and one never observed are the same run, bit
// for bit. A coast ends (the state is evaluated, then the integrator steps it from there) when an
// input or edit touches the body or its loads change.
#pragma once

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/worker_pool.h"

namespace cga_rigid_sim {
namespace sim {

/// Whether moving body i may coast this step (see above). Reads the Model and its own data only.
bool mayCoast(const Model& model, const MovingBodyData& b, int i);

/// Starts body i's coast from its state now (its integrator's caches are dropped: the coast's
/// are built from that state).
void startCoast(Data& data, int i);

/// Makes body i's `state` the state at data.step_count if it is coasting.
void syncBody(const Model& model, Data& data, int i);

/// Makes every coasting body's `state` current, split between the pool's threads.
void syncBodies(const Model& model, Data& data, WorkerPool* pool);

/// Ends body i's coast, if any: its `state` is made current and its integrator drops the
/// coast's cache, so the next step starts from that state.
void endCoast(const Model& model, Data& data, int i);

}  // namespace sim
}  // namespace cga_rigid_sim
