// Resting islands solved directly (doc/contacts.md#resting-islands): an island whose contacts
// are all faces (three or four corners between the same two bodies, one normal), two or more,
// at rest (targets 0, no impact, none sliding in the last step) is tried as welded: every face's
// relative twist brought to zero at once by one linear solve of the faces' 6 × 6 Delassus blocks.
// When the corners' impulses of that solution are all pushing and inside their friction cones it is
// the exact solution of the island's contact problem (every corner active and sticking,
// complementarity holds), which Gauss–Seidel reaches only slowly on a column of boxes (a slow mode
// of the column as a whole).
#pragma once

#include <vector>

#include "contact/contact_solver.h"

namespace cga_rigid_sim {
namespace sim {

/// At most this many faces in a resting island solved directly (a dense 6F × 6F solve).
constexpr int kMaxRestingFaces = SolverWork::Resting::kMax / 6;

/// Tries the direct solve for island I (the velocities in `work.vel` are those before any
/// contact impulse, the rows' targets set). On success sets the rows' λ_n, λ_t and the island's
/// velocities in `work.vel` to the solution and returns true; otherwise changes nothing.
bool solveResting(const std::vector<SolverBody>& bodies, std::vector<ContactRow>& rows,
                  SolverWork& work, const SolverWork::Island& I);

}  // namespace sim
}  // namespace cga_rigid_sim
