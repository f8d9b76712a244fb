// A tree's island solved by Newton's method: at rest (doc/contacts.md#resting-trees), its
// position correction, and its normals after the sweeps.
//
// A resting tree's island (doc/contacts.md#resting-trees): an island
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

/// A contact's impulses λ_n ≥ 0 and λ_t = (λ_t1, λ_t2) on its friction pyramid's four edges
/// n + μ t1, n − μ t1, n + μ t2, n − μ t2 (μ > 0), as the resting solve's warm start: their sum
/// is λ_n and μ times their differences λ_t, exactly but for rounding. Four edges carry three
/// impulses: `share`, the part of λ_n on the first two (ContactRow::pyramid_share), fixes the
/// fourth number where it fits (|λ_t1| / μ ≤ share ≤ λ_n − |λ_t2| / μ, to rounding), else the
/// slack λ_n − (|λ_t1| + |λ_t2|) / μ is shared equally (NaN: always). An edge below 1e-12 λ_n
/// (rounding) is 0. Friction outside the pyramid is scaled onto its rim.
Eigen::Vector4d pyramidEdges(double lambda_n, const Eigen::Vector2d& lambda_t, double mu,
                             double share);

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

/// After the sweeps of an island of one tree alone
/// (doc/contacts.md#a-trees-normals-after-the-sweeps): when they stopped at their cap with a
/// contact still approaching past its target faster than SolverSettings::tree_sink_speed, its
/// normal and stop impulses are solved again by the same method with the sweeps' friction impulses
/// held, in rounds while keeping that friction within μ λ_n of the new normals cuts it (eight
/// at most). Sets the rows' λ_n and λ_t, the stops' y and the tree's ν from those impulses;
/// false (nothing changed) when the island is not one for it, nothing sinks, a solve failed, or the
/// answer would leave a contact approaching as fast as the sweeps did or raise the kinetic energy
/// above the energy before the impulses.
bool polishTreeNormals(const SolverSettings& st, std::vector<SolverTree>& trees,
                       std::vector<ContactRow>& rows, SolverWork& work,
                       const SolverWork::Island& I);

}  // namespace sim
}  // namespace cga_rigid_sim
