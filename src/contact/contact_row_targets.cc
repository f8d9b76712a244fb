// Each row's target (doc/contacts.md#solver, doc/contact_model.md), from the velocities before
// any contact impulse: the lower bound of its normal velocity after the step — 0 in touch,
// −gap/h across a gap, e times the approach at an impact — its friction coefficient at its
// slip, its tangential target, or a compliant contact's fixed spring impulse.
#include <algorithm>
#include <limits>

#include "contact/contact_friction.h"
#include "contact/contact_solver_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {

void setTarget(const SolverSettings& st, const SolverWork& work,
               const std::vector<SolverTree>& trees, bool bounce, std::size_t k, ContactRow& c) {
  Eigen::Vector3d u = relativeVelocity(work.vel, work.a[k], work.b[k], c);
  if (onTree(c)) u += treeVelocity<&SolverTree::nu>(trees, c);
  const double u_n = c.n.dot(u);
  const double h = st.h;
  const double d = c.depth;
  // An impact: the bodies approach faster than the resting threshold and touch within the
  // step.
  const bool impact = u_n < -st.bounce_speed && (d > 0 || u_n * h < d);
  c.mu = frictionCoefficient(st.model,
                             c.face ? st.model.face_friction_ratio * c.mu_surface : c.mu_surface,
                             (u - u_n * c.n).norm());
  if (impact) c.mu = impactFriction(st.model, c.mu);
  c.impact = 0.0;
  c.compliant = st.model.compliant() && !onTree(c);
  if (c.compliant) {  // the spring's impulse; no target, no bounce
    // δ̇ at the step's start: against an immovable side, without the step's gravity kick
    // (at rest the kick's g h would read as an approach and the damper would push too hard).
    const bool one_sided = work.b[k] + 1 == static_cast<int>(work.response.size());
    const double approach = -u_n + (one_sided ? c.n.dot(st.gravity_kick_W) : 0.0);
    c.lambda_fixed = compliantImpulse(st.model, d, approach, h);
    c.target = -std::numeric_limits<double>::infinity();
    return;
  }
  // A gap may close, no more; a gap within round-off of contact is contact (targets of
  // ±1e-12 m / h under the four corners of a face would disagree, and Gauss–Seidel would
  // chase them for ever).
  double target = d >= -st.touching ? 0.0 : d / h;
  // At an impact Newton's law sends them apart at e times the approach speed.
  c.target_t.setZero();
  if (bounce && (c.restitution > 0 || st.model.tangential_restitution > 0) && impact) {
    c.impact = -u_n;
    const double e = c.face ? faceRestitution(st.model, c.restitution) : c.restitution;
    target = std::max(target, restitutionCoefficient(st.model, e, c.impact) * c.impact);
    // Tangential restitution (doc/contact_model.md): the slip reversed, if the cone allows.
    if (st.model.tangential_restitution > 0)
      c.target_t = -st.model.tangential_restitution * Eigen::Vector2d(c.t1.dot(u), c.t2.dot(u));
  }
  c.target = target;
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
