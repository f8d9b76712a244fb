// The controllers' topics (simulator.h, doc/node.md#controllers): per running controller
// `<name>/command` in, in the node's namespace as ros_control's controllers have it; per
// trajectory controller `<name>/state` out at its state_publish_rate; /joint_states at a joint
// state controller's publish_rate. Commands go through the World like every input: stamped in
// simulation time, queued for their step, refused whole with the field and the rule.
#include <cga_rigid_sim/JointTrajectoryControllerState.h>

#include <algorithm>

#include "cga_rigid_sim/ros/conversions.h"
#include "cga_rigid_sim/sim/data.h"
#include "simulator.h"

namespace cga_rigid_sim {
namespace node {
namespace {

// Per subscriber, as the other outputs (simulator.cc).
constexpr std::uint32_t kStateQueueSize = 1000;

}  // namespace

void Simulator::syncControllerTopics() {
  const auto& running = world_->data().controllers.running;
  const double dt = world_->config().dt;
  // /joint_states from the first joint on (a robot spawned into a scene without joints).
  if (!has_joints_ && !world_->scene().joints.empty()) {
    has_joints_ = true;
    joint_states_pub_ = nh_.advertise<sensor_msgs::JointState>("/joint_states", kOutputQueueSize);
  }
  std::map<std::string, std::size_t> index;
  for (std::size_t c = 0; c < running.size(); ++c) index[running[c].config.name] = c;
  // Topics of controllers gone with their robot are closed (the handles' last copies go).
  for (auto it = controller_commands_.begin(); it != controller_commands_.end();)
    it = index.count(it->first) ? std::next(it) : controller_commands_.erase(it);
  std::vector<ControllerState> states;
  for (ControllerState& cs : controller_states_) {
    const auto it = index.find(cs.name);
    if (it == index.end()) continue;
    cs.controller = it->second;
    states.push_back(std::move(cs));
  }
  controller_states_ = std::move(states);
  for (std::size_t c = 0; c < running.size(); ++c) {
    const control::ControllerConfig& config = running[c].config;
    const std::string& name = config.name;
    // A drive's wheel controller (simulator_drives.cc) takes its commands from the drive's
    // cmd_vel, not from a command topic of its own.
    if (std::any_of(drives_.begin(), drives_.end(),
                    [&](const Drive& d) { return d.controller == name; }))
      continue;
    if (config.type == control::ControllerType::kJointState) {
      // The node's own /joint_states then follows this rate (doc/node.md#controllers).
      if (has_joints_ && !joint_state_ticks_) joint_state_ticks_.emplace(dt, config.publish_rate);
      continue;
    }
    if (controller_commands_.count(name)) continue;
    if (control::isTrajectoryController(config.type)) {
      controller_commands_[name] = nh_.subscribe<trajectory_msgs::JointTrajectory>(
          name + "/command", kInputQueueSize,
          [this, name](const trajectory_msgs::JointTrajectory::ConstPtr& msg) {
            onTrajectoryCommand(name, msg);
          });
      controller_states_.push_back(
          ControllerState{name, c,
                          nh_.advertise<cga_rigid_sim::JointTrajectoryControllerState>(
                              name + "/state", kStateQueueSize),
                          TickSchedule(dt, config.publish_rate), UINT64_MAX, std::string()});
    } else {
      controller_commands_[name] = nh_.subscribe<std_msgs::Float64MultiArray>(
          name + "/command", kInputQueueSize,
          [this, name](const std_msgs::Float64MultiArray::ConstPtr& msg) {
            onGroupCommand(name, msg);
          });
    }
  }
}

void Simulator::onTrajectoryCommand(const std::string& controller,
                                    const trajectory_msgs::JointTrajectory::ConstPtr& msg) {
  // Refused whole (nothing queued), counted once, warned with the World's reason, which names
  // "<controller>/command.<field>" and the rule.
  auto ok = world_->commandTrajectory(controller, toJointTrajectory(*msg));
  if (!ok) refuse(controller + "/command", ok.failure().message());
}

void Simulator::onGroupCommand(const std::string& controller,
                               const std_msgs::Float64MultiArray::ConstPtr& msg) {
  auto ok = world_->commandGroup(controller, msg->data);
  if (!ok) refuse(controller + "/command", ok.failure().message());
}

void Simulator::publishJointStates() {
  const std::uint64_t s = world_->stepCount();
  if (!has_joints_ || s == last_joint_states_step_) return;
  last_joint_states_step_ = s;
  if (joint_states_pub_.getNumSubscribers() > 0)
    joint_states_pub_.publish(toJointStateMsg(world_->jointStates(), toRosTime(world_->time())));
}

void Simulator::publishControllerStates(bool always) {
  // Called after every step: without a trajectory controller there is nothing to publish and no
  // command to be refused at its step, and World::data() (which evaluates coasting bodies) is
  // not worth a call.
  if (controller_states_.empty()) return;
  const sim::Data& data = world_->data();
  // Commands the World refused at their step (a trajectory whose points had all passed by
  // then): counted, the last one warned about.
  const std::uint64_t refused = data.controllers.refused_at_step;
  if (refused != controller_refusals_seen_) {
    rejected_ += refused - controller_refusals_seen_ - 1;  // refuse() counts the last one
    controller_refusals_seen_ = refused;
    refuse("controller command (at its step)", data.controllers.last_refusal);
  }
  const std::uint64_t s = world_->stepCount();
  for (ControllerState& cs : controller_states_) {
    const sim::ControllerData& cd = data.controllers.running[cs.controller];
    const control::TrajectoryController& controller = *cd.trajectory;
    if (controller.status() == control::TrajectoryStatus::kAborted &&
        controller.reason() != cs.last_reason) {
      cs.last_reason = controller.reason();
      ROS_WARN("simulator: %s aborted its trajectory and holds: %s", cd.config.name.c_str(),
               controller.reason().c_str());
    }
    if (!(always || cs.ticks.isTick(s)) || s == cs.last_step) continue;
    cs.last_step = s;
    if (cs.publisher.getNumSubscribers() == 0) continue;
    // The state at this step's time: the controller sampled now against the joints now, on a
    // copy (the World's controller updates at the start of the next step, with the same values
    // unless a command is due then).
    const sim::TreeData& tree = data.trees[static_cast<std::size_t>(cd.tree)];
    control::TrajectoryController sample = controller;
    sample.update(world_->time(), tree.state.q, tree.state.v);
    cs.publisher.publish(toControllerStateMsg(sample.state(), toRosTime(world_->time()),
                                              ::ros::Duration(world_->time())));
  }
}

}  // namespace node
}  // namespace cga_rigid_sim
