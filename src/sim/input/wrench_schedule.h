// The active wrenches of a World: starting one, ending those whose time is up, dropping all,
// and the bookkeeping that tells updateLoads which bodies' loads to rebuild. Internal to the
// sim layer; none of these allocates (room is made when an input is queued, up to the bounds
// on active wrenches that mayStart enforces).
#pragma once

#include <cstdint>

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/input/input_queue.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

/// Flags moving body i for a rebuild of its applied loads.
void markLoadsDirty(Data& data, int i);

/// Whether wrench or timed effort `in`, due at step k, may start: its body (tree) is below
/// ~max_active_wrenches_per_body and the world below ~max_active_wrenches (wrenches and timed
/// efforts together). If not it is refused: counted and described in data.start_refusals.
/// Never allocates.
bool mayStart(const Model& model, Data& data, const QueuedInput& in, std::uint64_t k);

/// Starts queued wrench `in` at step k. A world-frame wrench's point becomes the material
/// point that is there now, x_B = R̃ (p_W − x_c); a link-frame one is already in B.
void startWrench(const Model& model, Data& data, const QueuedInput& in, std::uint64_t k);

/// Ends the wrenches whose last step was k − 1 (end_step ≤ k), keeping the others in order:
/// O(log n) per ending wrench (a heap on end steps) plus its body's few wrenches, never a pass
/// over every active wrench.
void expireWrenches(Data& data, std::uint64_t k);

/// Ends every active wrench now and drops the applied loads.
void dropActiveWrenches(Data& data);

/// Forgets the active wrenches of moving body i (its data is erased next) and renumbers the
/// bodies after it (i − 1), as when that body is deleted.
void removeActiveWrenchesOf(Data& data, int i);

}  // namespace sim
}  // namespace cga_rigid_sim
