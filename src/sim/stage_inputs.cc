// Stage 1 of the step: the inputs due at step k take effect, in (step, arrival) order.
#include "cga_rigid_sim/body/impulse.h"
#include "cga_rigid_sim/sim/stages.h"
#include "sim/coasting.h"
#include "sim/controllers/controllers.h"
#include "sim/curved_bodies.h"
#include "sim/input/wrench_schedule.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// ΔΩ_B = (I∧n)⁻¹ T_imp (doc/conventions.md (E17)); the pose does not jump. A
// world-frame impulse acts at the world point at this step's pose; a link-frame one is in B.
void applyImpulseNow(const Model& model, Data& data, const QueuedInput& in) {
  MovingBodyData& b = data.bodies[in.body];
  const double lambda = model.lambda;
  endCoast(model, data, in.body);  // the state the impulse acts on is the state now
  if (model.curved_space) {        // 1 up (curved_bodies.h): in body axes, through the chart pose
    if (in.axes == dynamics::Axes::kWorld) {
      const Eigen::Quaterniond R_BW = b.state.M_WB.rotation().conjugate();
      const Eigen::Vector3d x_B = R_BW * (in.point - b.state.M_WB.translation(lambda));
      applyCurvedImpulse(model, in.body, R_BW * in.F.f, x_B, R_BW * in.couple, b);
    } else {
      applyCurvedImpulse(model, in.body, in.F.f, in.point, in.couple, b);
    }
    return;
  }
  const cga::Moment T_imp_B =
      in.axes == dynamics::Axes::kWorld
          ? dynamics::impulseMoment_B(b.state, in.F, in.point, in.couple, lambda)
          : cga::Moment::ofForceAt(in.F.f, in.point, lambda) + cga::Moment::couple(in.couple);
  const int t = model.tree_of_moving[in.body];
  if (t >= 0) {  // a tree's velocities jump by M⁻¹ Jᵀ T_imp (doc/articulated.md#impulses)
    const dynamics::ArticulatedBody& tree = model.trees[t].body;
    TreeData& td = data.trees[t];
    const Eigen::VectorXd dnu =
        dynamics::impulseResponse(tree, td.state, model.tree_body_of_moving[in.body], T_imp_B);
    dynamics::setVelocityVector(tree, dynamics::velocityVector(tree, td.state) + dnu, td.state);
    td.integrator->reset();
    writeTreeBodies(model, data, t);
    return;
  }
  dynamics::applyImpulse(model.moving[in.body].inertia, T_imp_B, lambda, b.state);
  b.integrator->reset();  // its caches describe the motion before the jump
}

// A joint's position and rate set from outside: a state edit (the integrator restarts, mimic
// joints follow, the links' states are rewritten), and the controllers of the tree hold the new
// positions (else their servos would pull the joint back to where it was).
void setJointNow(const Model& model, Data& data, const QueuedInput& in) {
  const dynamics::ArticulatedBody& tree = model.trees[in.tree].body;
  TreeData& td = data.trees[in.tree];
  td.state.q[in.joint] = in.position;
  td.state.v[in.joint] = in.velocity;
  dynamics::applyMimic(tree, td.state);
  td.integrator->reset();
  writeTreeBodies(model, data, in.tree);
  holdControllersAt(model, data, in.tree);
}

}  // namespace

void applyDueInputs(const Model& model, Data& data) {
  const std::uint64_t k = data.step_count;
  if (!data.queue.hasDue(k)) return;  // most steps: nothing to do, no frame to set up
  while (const QueuedInput* in = data.queue.popDue(k)) {
    if (in->kind == QueuedInput::Kind::kImpulse) {
      applyImpulseNow(model, data, *in);
    } else if (in->kind == QueuedInput::Kind::kHeldEffort) {
      data.trees[in->tree].held_effort[in->joint] = in->effort;
    } else if (in->kind == QueuedInput::Kind::kJointState) {
      setJointNow(model, data, *in);
    } else if (!mayStart(model, data, *in, k)) {
      continue;  // past a bound on active inputs: refused, counted in data.start_refusals
    } else if (in->kind == QueuedInput::Kind::kTimedEffort) {
      // Room was reserved when it was queued (World::applyJointEffort).
      data.trees[in->tree].timed.push_back(
          {in->joint, in->effort, in->steps == 0 ? kUntilCleared : k + in->steps});
    } else {
      startWrench(model, data, *in, k);
    }
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
