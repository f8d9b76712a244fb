// A resting tree's island solved by Newton's method (doc/contacts.md#resting-trees): an island
// of one articulated tree and nothing else that moves (its other sides are the ground and
// static bodies), every contact point slower than SolverSettings::resting_tree_speed, no
// impact, no compliant contact, no patch couples. Its contacts' friction is the pyramid with
// the four edges n ± μ t1, n ± μ t2 (Anitescu's convex form: a sticking contact's velocity is
// brought to its target exactly, a sliding one's normal velocity may exceed it by μ |u_t|,
// which the speed bound keeps below μ times that bound), its joints' stops are rows on their
// rates; the whole is the convex cost of contact_tree_newton.h, minimised in the tree's ~30
// coordinates. Gauss–Seidel over the rows leaves a lying robot creeping (doc/decisions.md).
#pragma once

#include <vector>

#include "contact/contact_solver.h"

namespace cga_rigid_sim {
namespace sim {

/// Tries the Newton solve for island I: the rows' targets set, the tree's ν warm-started (its
/// impulses of the last step applied). On success sets the rows' λ_n and λ_t (λ_n = Σ of its
/// edges' impulses, λ_t = μ times their differences), the limit rows' y_lower and y_upper and
/// the tree's ν, and returns the Newton steps taken (≥ 1); −1 when the island is not one for
/// it or the solve failed, and then changes nothing.
int solveRestingTree(const SolverSettings& st, std::vector<SolverTree>& trees,
                     std::vector<ContactRow>& rows, SolverWork& work, const SolverWork::Island& I);

/// The position correction of an island of one tree alone (any speed: it has no friction) by
/// the same method: the pseudo-velocity pν that minimises ½ pνᵀ M pν with every contact's
/// normal pseudo-velocity at least its bias (0 where it overlaps within the slop: not pushed
/// in) and q + h (ν + pν) within the stops. Gauss–Seidel's ten sweeps leave a foot jammed
/// between the floor and its own leg where it is. Sets T.pnu, the rows' λ_p and the stops'
/// p_lower, p_upper; false (pν zero) when the island is not one for it or the solve failed.
bool correctTreePositions(const SolverSettings& st, std::vector<SolverTree>& trees,
                          std::vector<ContactRow>& rows, SolverWork& work,
                          const SolverWork::Island& I);

}  // namespace sim
}  // namespace cga_rigid_sim
