// Making the self-collision table of a World (contact/self_collision.h) and saying what it holds.
#pragma once

#include <string>
#include <vector>

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "contact/contact_detection.h"

namespace cga_rigid_sim {
namespace sim {

/// Fills model.self_collision from the scene's rules and model.config.self_collision (called by
/// compileModel).
void compileSelfCollision(Model& model);
/// Under `auto`, leaves out the allowed pairs that overlap at the poses of `data` (the initial
/// configuration). Called once by World::create.
void leaveOutInitialOverlaps(Model& model, const Data& data, CollisionCache& cache);

/// The start-up summary's lines: per robot, how many pairs of its links collide, which, and
/// which are left out and why (overlaps deepest first, with their depth).
std::vector<std::string> selfCollisionSummary(const Model& model);

}  // namespace sim
}  // namespace cga_rigid_sim
