// The end of a free body's contact step (doc/contacts.md#drift): the body the contacts stage
// kicked by its loads and contact impulses drifts torque-free over the step; a body its landing
// already stepped through the step is left as it is.
#include "contact/contact_drift.h"

#include "contact/contact_momentum.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

const dynamics::Loads kNoLoads;

}  // namespace

void finishBodyContactStep(const Model& model, int i, MovingBodyData& b) {
  const double h = model.config.dt, lambda = model.lambda;
  if (b.contact_step == MovingBodyData::ContactStep::kDone) {  // stepped by its landing
    b.contact_step = MovingBodyData::ContactStep::kNone;
    b.contact_momentum.pending = false;
    b.last_path = StepPath::kStepped;
    return;
  }
  // Kicked by its loads and contacts already: the drift of the splitting, torque-free.
  b.contact_step = MovingBodyData::ContactStep::kNone;
  const bool rest = b.state.omega_B.rot.isZero(0.0) && b.state.omega_B.trans.isZero(0.0);
  b.last_path = rest ? StepPath::kAtRest : StepPath::kStepped;
  if (!rest) b.integrator->step(model.moving[i].inertia, kNoLoads, lambda, h, b.state);
  b.integrator->reset();  // its caches hold the drift, not the body's loaded path
  // A body in contact drifts from a fresh anchor every step, so what a step rounds is
  // carried into the next (doc/contacts.md#drift): the rotor is renormalised as r + e r,
  // e = (1 − |r|²)/2, whose roundings are unbiased (r/|r| came out 0.44 ε too long on
  // average), and Ω_B is read off the momentum the body carries in world axes, which the
  // torque-free drift keeps (contact_momentum.h), rather than carried in body axes.
  if (!rest || !b.contact_shift_W.isZero(0.0)) {
    Eigen::Quaterniond r1 = b.state.M_WB.rotation();
    r1.coeffs() += (0.5 * (1.0 - r1.coeffs().squaredNorm())) * r1.coeffs();
    b.state.M_WB =
        cga::Motor::fromPose(r1, b.state.M_WB.translation(lambda) + b.contact_shift_W, lambda);
    b.contact_shift_W.setZero();
    b.last_path = StepPath::kStepped;
  }
  MovingBodyData::ContactMomentum& m = b.contact_momentum;
  if (m.pending) {
    if (!rest)
      b.state.omega_B = bodyVelocity(model.moving[i].inertia, b.state.M_WB.rotation(), m, lambda);
    m.key_omega_B = b.state.omega_B;
    m.key_r = b.state.M_WB.rotation().coeffs();
    m.valid = true;
    m.pending = false;
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
