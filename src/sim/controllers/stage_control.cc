// The control stage of the step (controllers.h): due commands, then every controller's servos.
#include <algorithm>

#include "sim/controllers/controllers.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// A group position command within the joint's limits (joint_limits_interface saturates so).
double withinLimits(const dynamics::TreeJoint& j, double q) {
  return std::clamp(q, j.lower, j.upper);
}

void applyDueCommands(const Model& model, Data& data) {
  ControllersData& cs = data.controllers;
  const double now = static_cast<double>(data.step_count) * model.config.dt;
  std::size_t taken = 0;
  for (; taken < cs.waiting.size() && cs.waiting[taken].step <= data.step_count; ++taken) {
    const ControllerCommand& command = cs.waiting[taken];
    ControllerData& cd = cs.running[command.controller];
    const TreeData& td = data.trees[cd.tree];
    if (cd.trajectory) {
      auto done = cd.trajectory->command(command.trajectory, now, td.state.q, td.state.v);
      if (!done) {  // checked on arrival for this step: only what changed since can refuse it
        ++cs.refused_at_step;
        cs.last_refusal = cd.config.name + "/command: " + done.failure().message();
      }
      continue;
    }
    const dynamics::ArticulatedBody& tree = model.trees[cd.tree].body;
    for (std::size_t j = 0; j < cd.joints.size(); ++j)
      cd.command[j] = cd.config.type == control::ControllerType::kGroupPosition
                          ? withinLimits(tree.joints()[cd.joints[j]], command.values[j])
                          : command.values[j];
  }
  cs.waiting.erase(cs.waiting.begin(), cs.waiting.begin() + static_cast<std::ptrdiff_t>(taken));
}

// The joint's <limit velocity> (rad/s or m/s; +∞ when absent).
double velocityLimit(const Model& model, int tree, int joint) {
  return model.scene.joints[model.trees[tree].scene_joint[joint]].limits.velocity;
}

// One controller's servos and feed-forward efforts for the step. <limit velocity> is enforced
// on the commands as joint_limits_interface's saturation does: a velocity reference is clamped
// to ±limit, and a group position command is approached at most at the limit (the reference
// moves by at most limit·h per step from the servo's last one).
void driveJoints(const Model& model, Data& data, ControllerData& cd) {
  TreeData& td = data.trees[cd.tree];
  const double h = model.config.dt, now = static_cast<double>(data.step_count) * h;
  const Eigen::VectorXd &q = td.state.q, &v = td.state.v;
  if (cd.trajectory) cd.trajectory->update(now, q, v);
  dynamics::JointServos& servos = td.loads.servos;
  for (std::size_t j = 0; j < cd.joints.size(); ++j) {
    const int k = cd.joints[j];
    const control::ServoGains& g = cd.gains[j];
    const double v_max = velocityLimit(model, cd.tree, k);
    double r = q[k], r_dot = v[k], error = 0.0, effort = 0.0;  // references r at t_k + ½h
    switch (cd.config.type) {
      case control::ControllerType::kGroupPosition: {
        // From the last reference (the pose at load before the first step), toward the command.
        const double last = servos.kp[k] > 0.0 ? servos.position[k] : q[k];
        r = std::clamp(cd.command[j], last - v_max * h, last + v_max * h);
        r_dot = 0.0;
        error = r - q[k];
        break;
      }
      case control::ControllerType::kGroupVelocity:
        r_dot = cd.command[j];
        break;
      case control::ControllerType::kGroupEffort:
        effort = cd.command[j];
        break;
      default: {  // a trajectory controller: its desired state at t_k, taken to the middle
        const control::JointSample& s = cd.trajectory->desired(j);
        r = s.position + 0.5 * h * s.velocity;
        r_dot = s.velocity + 0.5 * h * s.acceleration;
        error = s.position - q[k];
      }
    }
    r_dot = std::clamp(r_dot, -v_max, v_max);
    servos.kp[k] = g.kp;
    servos.kd[k] = g.kd;
    servos.position[k] = r;
    servos.velocity[k] = r_dot;
    if (g.ki != 0.0) effort += cd.integral[j].accumulate(error, h, cd.pid[j]);
    td.controller_effort[k] = effort + g.kff_velocity * r_dot;
  }
}

}  // namespace

void holdControllersAt(const Model& model, Data& data, int t) {
  const double now = static_cast<double>(data.step_count) * model.config.dt;
  TreeData& td = data.trees[t];
  for (ControllerData& cd : data.controllers.running) {
    if (cd.tree != t) continue;
    if (cd.trajectory) cd.trajectory->hold(now, td.state.q);
    for (std::size_t j = 0; j < cd.joints.size(); ++j) {
      const int k = cd.joints[j];
      if (cd.config.type == control::ControllerType::kGroupPosition) cd.command[j] = td.state.q[k];
      td.loads.servos.position[k] = td.state.q[k];
      cd.integral[j].reset();
    }
  }
}

void controlJoints(const Model& model, Data& data) {
  if (data.controllers.running.empty()) return;
  applyDueCommands(model, data);
  for (ControllerData& cd : data.controllers.running)
    if (cd.tree >= 0 && !data.trees[cd.tree].asleep) driveJoints(model, data, cd);
}

}  // namespace sim
}  // namespace cga_rigid_sim
