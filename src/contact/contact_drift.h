// The end of a free body's contact step, in the integration stage (stage_integrate.cc): the
// drift of the kick-drift splitting, the position correction and the momentum the body carries
// (doc/contacts.md#drift). Internal to the sim layer.
#pragma once

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

/// Ends the contact step of moving body i (b: its data, contact_step not kNone): a body the
/// contacts stage kicked drifts torque-free over the step (its integrator then reset), its
/// rotor renormalised, the position correction applied and Ω_B read off the momentum it
/// carries; a body its landing stepped through the step is left as it is. Reads only the body's
/// own data and the Model, so the worker threads may call it for their bodies.
void finishBodyContactStep(const Model& model, int i, MovingBodyData& b);

}  // namespace sim
}  // namespace cga_rigid_sim
