// Curved space in the World (WorldConfig::curvature, doc/curved_space.md): the free bodies move
// "1 up" with their own state (ψ, Ω_B) and integrator (MovingBodyData::curved_state,
// curved_integrator), and after every step their Euclidean-facing `state` is rewritten as the
// chart pose (position and attitude in the stereographic chart, CurvedSpace::chartPose) with the
// body's true velocities (w, and v = |R| u in body axes), so tf, body states and the Euclidean
// momentum reports read the chart. The conserved 4-d quantities are in curvedMomentum().
//
// What a curved world refuses (each with the rule): gravity ≠ 0, articulated trees, a ground
// plane, an integrator other than auto / curved2 / curved_exact (curved_exact: isotropic bodies
// only), a body too large for the space, an initial position outside the chart (|x| ≥ 2|R| for
// R < 0); and, once made, wrenches, impulses, state edits and spawning (not built yet). Contacts
// are not detected.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/reports.h"

namespace cga_rigid_sim {
namespace sim {

/// The radius and the integrator name of a curved configuration.
std::optional<Error> checkCurvedConfig(const WorldConfig& config);
/// Sets model.curved_space and every moving body's curved inertia; refuses what a curved world
/// cannot simulate (above).
std::optional<Error> compileCurvedBodies(Model& model);
/// The curved state and integrator of a body starting at `initial` (its pose read as a chart
/// pose, its velocities as true velocities).
std::optional<Error> makeCurvedBodyData(const Model& model, int moving_index,
                                        const dynamics::BodyState& initial, MovingBodyData& b);
/// One step of moving body i, then its chart pose written to b.state.
void stepCurvedBody(const Model& model, int i, MovingBodyData& b);
/// "<input>: not available in curved space yet" when the world is curved.
std::optional<Error> refuseInCurvedSpace(const Model& model, const std::string& input);
/// Per moving body, then the total: the 4-d world momentum and the kinetic energy.
std::vector<CurvedMomentumReport> curvedMomentumReports(const Model& model, const Data& data);

}  // namespace sim
}  // namespace cga_rigid_sim
