// Commands for the joint controllers (controllers.h): validated when they arrive, queued for
// their step in (step, arrival) order like every input.
#include <algorithm>
#include <cmath>

#include "cga_rigid_sim/format.h"
#include "sim/controllers/controllers.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// The running controller called `name`, or the refusal naming those there are.
Result<int> findController(const Data& data, const std::string& name, const std::string& input) {
  std::string known;
  for (std::size_t c = 0; c < data.controllers.running.size(); ++c) {
    if (data.controllers.running[c].config.name == name) return static_cast<int>(c);
    known += (known.empty() ? "" : ", ") + inQuotes(data.controllers.running[c].config.name);
  }
  return Error(input, "",
               "no controller '" + name + "' is running" +
                   (known.empty() ? std::string(" (none is)") : " (running: " + known + ")"));
}

Result<bool> roomFor(const Model& model, const Data& data, const std::string& input) {
  if (data.controllers.waiting.size() >= static_cast<std::size_t>(model.config.max_queued_inputs))
    return Error(input, "",
                 std::to_string(data.controllers.waiting.size()) +
                     " commands are already waiting for their step (max_queued_inputs)");
  return true;
}

void enqueue(Data& data, ControllerCommand command) {
  command.arrival = data.controllers.arrivals++;
  auto& waiting = data.controllers.waiting;
  const auto at =
      std::upper_bound(waiting.begin(), waiting.end(), command,
                       [](const ControllerCommand& a, const ControllerCommand& b) {
                         return a.step != b.step ? a.step < b.step : a.arrival < b.arrival;
                       });
  waiting.insert(at, std::move(command));
}

}  // namespace

Result<bool> queueTrajectory(const Model& model, Data& data, const std::string& controller,
                             const control::JointTrajectory& trajectory) {
  const std::string input = controller + "/command";
  auto c = findController(data, controller, input);
  if (!c) return c.failure();
  const ControllerData& cd = data.controllers.running[*c];
  if (!cd.trajectory)
    return Error(input, "",
                 "controller '" + controller + "' is a " + control::typeName(cd.config.type) +
                     ", not a trajectory controller (it takes std_msgs/Float64MultiArray)");
  // A spawned robot's controller takes its joints by their names in the URDF too, as a
  // controller in a robot's namespace has them under Gazebo.
  if (!cd.name_space.empty()) {
    const std::string prefix = cd.name_space + "/";
    control::JointTrajectory named = trajectory;
    bool renamed = false;
    for (std::string& joint : named.joint_names)
      if (joint.compare(0, prefix.size(), prefix) != 0) joint = prefix + joint, renamed = true;
    if (renamed) return queueTrajectory(model, data, controller, named);
  }
  if (auto valid = control::validate(trajectory); !valid)
    return Error(input, valid.failure().field, valid.failure().rule);
  const double dt = model.config.dt;
  if (trajectory.start_time / dt > 1e15)
    return Error(input, "header.stamp",
                 "start " + formatNumber(trajectory.start_time) + " s is too far ahead");
  std::uint64_t step = data.step_count;
  if (trajectory.start_time > 0)
    step =
        std::max(step, static_cast<std::uint64_t>(std::floor(trajectory.start_time / dt + 1e-9)));
  // The controller's own rules (its joints, all of them unless partial goals are allowed), on a
  // copy at the step the command is due at: what it refuses then is refused now.
  control::TrajectoryController dry = *cd.trajectory;
  const TreeData& td = data.trees[cd.tree];
  const double due = static_cast<double>(step) * dt;
  if (auto taken = dry.command(trajectory, due, td.state.q, td.state.v); !taken)
    return Error(input, taken.failure().field, taken.failure().rule);
  if (auto room = roomFor(model, data, input); !room) return room;
  ControllerCommand command;
  command.step = step;
  command.controller = *c;
  command.trajectory = trajectory;
  enqueue(data, std::move(command));
  return true;
}

Result<bool> queueGroupCommand(const Model& model, Data& data, const std::string& controller,
                               const std::vector<double>& values) {
  const std::string input = controller + "/command";
  auto c = findController(data, controller, input);
  if (!c) return c.failure();
  const ControllerData& cd = data.controllers.running[*c];
  if (cd.trajectory || cd.tree < 0)
    return Error(input, "",
                 "controller '" + controller + "' is a " + control::typeName(cd.config.type) +
                     ", not a group controller" +
                     (cd.trajectory ? " (it takes trajectory_msgs/JointTrajectory)" : ""));
  if (values.size() != cd.joints.size())
    return Error(input, "data",
                 "has " + std::to_string(values.size()) + " values for " +
                     std::to_string(cd.joints.size()) + " joints (one per joint, in the order of " +
                     controller + "/joints)");
  for (std::size_t j = 0; j < values.size(); ++j) {
    const std::string field = "data[" + std::to_string(j) + "]";
    if (!std::isfinite(values[j]))
      return Error(input, field, "not finite (" + formatNumber(values[j]) + ")");
    if (cd.config.type == control::ControllerType::kGroupEffort &&
        std::abs(values[j]) > model.config.max_force)
      return Error(input, field,
                   "effort " + formatNumber(values[j]) + " is beyond max_force " +
                       formatNumber(model.config.max_force));
  }
  if (auto room = roomFor(model, data, input); !room) return room;
  ControllerCommand command;
  command.step = data.step_count;
  command.controller = *c;
  command.values = values;
  enqueue(data, std::move(command));
  return true;
}

}  // namespace sim
}  // namespace cga_rigid_sim
