// The friction coefficient of a contact in one step under the contact model's extensions
// (doc/contact_model.md#static-and-kinetic-friction).
#pragma once

#include <cmath>

#include "cga_rigid_sim/sim/world_config.h"

namespace cga_rigid_sim {
namespace sim {

/// Stribeck's curve: a contact slipping at speed v (m/s, its tangential relative velocity
/// before the step's impulses) holds with μ(v) = μ (1 + (r − 1) exp(−(v/v_s)²)): the static
/// coefficient r μ at rest, the kinetic one μ once it slides well above v_s. With r = 1 (off)
/// it returns μ itself, so the plain model's numbers are unchanged to the bit.
inline double frictionCoefficient(const ContactModel& model, double mu, double slip_speed) {
  if (model.static_friction_ratio == 1.0) return mu;
  const double x = slip_speed / model.stribeck_speed;
  return mu * (1.0 + (model.static_friction_ratio - 1.0) * std::exp(-x * x));
}

}  // namespace sim
}  // namespace cga_rigid_sim
