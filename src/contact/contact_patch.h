// Rolling and torsional resistance of a contact patch (doc/contact_model.md#rolling-and-torsional-
// resistance): one block of the contact solver's sweep, after the contact's friction.
//
// Two surfaces touching over a patch rather than at a point resist turning against each other:
// the pressure over the patch can shift its centre by up to the patch's half-width ρ_r, so it
// resists rolling about a tangent by a couple |M_r| ≤ ρ_r λ_n (the rolling-resistance law,
// Coulomb's for rolling, with a "coefficient of rolling friction" that is a length), and
// friction over the patch resists spinning about the normal by |M_s| ≤ ρ_s λ_n (for a disc of
// radius a under uniform pressure ρ_s = (2/3) μ a). Both are solved as the contact's friction
// is: a step that would stop the relative rotation, projected onto its bound (a disc for the
// two rolling components, an interval for the spin), so a rolling or spinning contact takes the
// full couple against its motion and a resting one only what holds it. These are MuJoCo's
// condim 6 rows with its torsional and rolling coefficients.
//
// Free bodies only: a side on an articulated tree's link takes no couple (its angular Jacobian
// is not formed), and the contact keeps its point friction alone.
#pragma once

#include <algorithm>
#include <cmath>

#include "cga_rigid_sim/sim/world_config.h"
#include "contact/contact_solver.h"

namespace cga_rigid_sim {
namespace sim {

/// Whether the model has a patch resistance at all (then every contact's sweep runs patchStep).
inline bool patchResistance(const ContactModel& m) {
  return m.rolling_resistance > 0.0 || m.torsional_resistance > 0.0;
}

/// One sweep's update of contact c's patch couples, between body slots A and B (the dummy for
/// an immovable side): updates c.lambda_spin, c.lambda_roll and c.couple (world axes, on a; b
/// takes its opposite) and the two angular velocities.
inline void patchStep(const ContactModel& m, ContactRow& c, SolverWork::Twist& A,
                      SolverWork::Twist& B, const SolverWork::Response& ra,
                      const SolverWork::Response& rb) {
  const Eigen::Matrix3d K = ra.inv_inertia + rb.inv_inertia;  // rotation per unit couple
  const Eigen::Vector3d w = A.w - B.w;                        // a's turning relative to b
  Eigen::Vector3d dM = Eigen::Vector3d::Zero();
  if (m.torsional_resistance > 0.0) {
    const double k = c.n.dot(K * c.n);
    if (k > 0.0) {
      const double bound = m.torsional_resistance * c.lambda_n;
      const double l = std::clamp(c.lambda_spin - c.n.dot(w) / k, -bound, bound);
      dM += (l - c.lambda_spin) * c.n;
      c.lambda_spin = l;
    }
  }
  if (m.rolling_resistance > 0.0) {
    const Eigen::Vector3d Kt1 = K * c.t1, Kt2 = K * c.t2;
    const double a = c.t1.dot(Kt1), b = c.t1.dot(Kt2), d = c.t2.dot(Kt2);
    // The largest eigenvalue of the 2 × 2 block: a step of −ω_t/k never overshoots.
    const double k = 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
    if (k > 0.0) {
      const double bound = m.rolling_resistance * c.lambda_n;
      Eigen::Vector2d l = c.lambda_roll - Eigen::Vector2d(c.t1.dot(w), c.t2.dot(w)) / k;
      const double norm = l.norm();
      if (norm > bound) l *= norm > 0.0 ? bound / norm : 0.0;
      const Eigen::Vector2d dl = l - c.lambda_roll;
      dM += dl.x() * c.t1 + dl.y() * c.t2;
      c.lambda_roll = l;
    }
  }
  A.w += ra.inv_inertia * dM;
  B.w -= rb.inv_inertia * dM;
  c.couple = c.lambda_spin * c.n + c.lambda_roll.x() * c.t1 + c.lambda_roll.y() * c.t2;
}

}  // namespace sim
}  // namespace cga_rigid_sim
