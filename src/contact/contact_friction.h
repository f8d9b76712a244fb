// The friction and restitution coefficients of a contact in one step under the contact
// model's extensions (doc/contact_model.md).
#pragma once

#include <algorithm>
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

/// Friction in an impact (pressure-dependent friction): μ times impact_friction_ratio. With the
/// ratio 1 (off) it returns μ itself, unchanged to the bit.
inline double impactFriction(const ContactModel& model, double mu) {
  return model.impact_friction_ratio == 1.0 ? mu : model.impact_friction_ratio * mu;
}

/// The restitution of a face landing flat: e times face_restitution_ratio. With the ratio 1
/// (off) it returns e itself, unchanged to the bit.
inline double faceRestitution(const ContactModel& model, double e) {
  return model.face_restitution_ratio == 1.0 ? e : model.face_restitution_ratio * e;
}

/// Johnson's speed-dependent restitution: an impact at normal speed v > 0 bounces with
/// e(v) = min(1, e (v_ref / v)^p). With p = 0 (off) it returns e itself, unchanged to the bit.
inline double restitutionCoefficient(const ContactModel& model, double e, double impact_speed) {
  if (model.restitution_speed_exponent == 0.0 || e == 0.0) return e;
  return std::min(1.0, e * std::pow(model.restitution_reference_speed / impact_speed,
                                    model.restitution_speed_exponent));
}

/// Hunt and Crossley's compliant contact: the normal impulse over a step of h of a contact
/// overlapping by `depth` (m) and approaching at `approach_speed` (m/s, > 0 closing):
/// h max(0, k δ (1 + d δ̇)) for δ > 0, else 0.
inline double compliantImpulse(const ContactModel& model, double depth, double approach_speed,
                               double h) {
  if (depth <= 0.0) return 0.0;
  const double f =
      model.normal_stiffness * depth * (1.0 + model.normal_dissipation * approach_speed);
  return f > 0.0 ? h * f : 0.0;
}

}  // namespace sim
}  // namespace cga_rigid_sim
