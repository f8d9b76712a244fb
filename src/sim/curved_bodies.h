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
// R < 0); and, once made, state edits and spawning (not built yet). Contacts are not detected.
//
// Wrenches and impulses act 1 up: a force f_B at the body-axes offset x_B from the centre is the
// tangent vector F (f_B carried along the geodesic from the centre to the body point X_B), its
// moment X_B∧F, and a couple τ_B the rotation bivector (τ_B; 0) about the centre; L_B changes by
// the moment (an impulse) or by its rate (a wrench, in kicks K(h/2) around each step: the Strang
// splitting of the integrators). World-axes vectors are turned into the body's axes through the
// chart attitude at the moment they act (the chart is conformal: directions are true there);
// a world point is the chart point, taken into the body's axes like a Euclidean one (exact at
// the centre).
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
/// An impulse on moving body i, in body axes: linear impulse j_B at the offset x_B from the
/// centre and angular impulse a_B: L_B += X_B∧J + (a_B; 0); the pose does not jump. The chart
/// state (b.state) is rewritten.
void applyCurvedImpulse(const Model& model, int i, const Eigen::Vector3d& j_B,
                        const Eigen::Vector3d& x_B, const Eigen::Vector3d& a_B, MovingBodyData& b);
/// "<input>: not available in curved space yet" when the world is curved.
std::optional<Error> refuseInCurvedSpace(const Model& model, const std::string& input);
/// Per moving body, then the total: the 4-d world momentum and the kinetic energy.
std::vector<CurvedMomentumReport> curvedMomentumReports(const Model& model, const Data& data);

}  // namespace sim
}  // namespace cga_rigid_sim
