// Landings (doc/contacts.md#time-stepping): a body whose only contacts are gaps to the ground
// plane that close within the step is stepped by its own integrator to the instant it touches,
// bounces there, and is stepped through the rest of the step, so its flights stay exact
// parabolas and its bounces leave at e times the exact impact speed.
#pragma once

#include <cstddef>
#include <vector>

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "contact/contact_scratch.h"
#include "contact/contact_solver.h"

namespace cga_rigid_sim {
namespace sim {

/// The first instant in (0, h] at which one of the contacts S.found[first, last) (gaps of one
/// body to the plane) closes faster than `rest_speed`; 0 when none does.
double landingTime(const Model& model, const Data& data, const ContactScratch& S, std::size_t first,
                   std::size_t last, double rest_speed);

/// Steps moving body i to t, solves its plane contacts there with restitution, steps it through
/// the rest of the step and marks it done; appends its contacts to `out`. Returns the kinetic
/// energy the impulses took out.
double land(const Model& model, Data& data, ContactScratch& S, int i, double t,
            const SolverSettings& settings, std::vector<Contact>& out);

}  // namespace sim
}  // namespace cga_rigid_sim
