// The node's services (simulator.h): pause, unpause, reset, clear_wrenches, step, body states,
// spawn and delete, timed joint efforts (doc/node.md).
#include "cga_rigid_sim/ros/conversions.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "simulator.h"

namespace cga_rigid_sim {
namespace node {

bool Simulator::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = true;
  markDisturbed();
  return true;
}

bool Simulator::onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = false;
  markDisturbed();
  return true;
}

bool Simulator::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  world_->reset();
  forgetSensors();
  markDisturbed();
  return true;
}

bool Simulator::onClearWrenches(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  world_->clearWrenches();
  return true;
}

bool Simulator::onStep(cga_rigid_sim::Step::Request& req, cga_rigid_sim::Step::Response& res) {
  if (req.steps > 0) {
    advance(req.steps);
    // The caller wants to see where the steps led, tick or not (at most once per stamp).
    // ~step 0 only reports the time: it publishes nothing, so polling it keeps bags on ticks.
    publishClock();
    publishOutputs();
    publishJointStates();
    publishControllerStates(/*always=*/true);
  }
  res.sim_time = toRosTime(world_->time());
  markDisturbed();
  return true;
}

bool Simulator::onGetBodyState(cga_rigid_sim::GetBodyState::Request& req,
                               cga_rigid_sim::GetBodyState::Response& res) {
  // A query changes nothing, so a failure is answered but not counted as a refused input.
  auto state = world_->getBodyState(req.body);
  res.success = state.ok();
  if (!state) {
    res.message = state.error();
    return true;
  }
  res.state = toBodyStateMsg(*state);
  return true;
}

bool Simulator::onSetBodyState(cga_rigid_sim::SetBodyState::Request& req,
                               cga_rigid_sim::SetBodyState::Response& res) {
  auto in = toPoseTwist(req.state.pose, req.state.twist, "set_body_state.state");
  auto ok = in ? world_->setBodyState(req.state.name, in->pose_root, in->linear_W, in->angular_W)
               : Result<bool>(in.failure());
  res.success = ok.ok();
  if (!ok) {
    res.message = ok.error();
    refuse("set_body_state", ok.error());
  }
  return true;
}

bool Simulator::onSetJointState(cga_rigid_sim::SetJointState::Request& req,
                                cga_rigid_sim::SetJointState::Response& res) {
  sim::JointStateInput in;
  in.names = req.state.name;
  in.positions = req.state.position;
  in.velocities = req.state.velocity;
  in.stamp = toSimTime(req.state.header.stamp);
  auto ok = world_->setJointState(in);
  res.success = ok.ok();
  if (!ok) {
    res.message = ok.error();
    refuse("set_joint_state", ok.error());
  }
  return true;
}

bool Simulator::onSpawnUrdf(cga_rigid_sim::SpawnUrdf::Request& req,
                            cga_rigid_sim::SpawnUrdf::Response& res) {
  // A robot runs the node's ~spawn_controllers under its namespace.
  sim::SpawnOptions options;
  options.robot_namespace = req.robot_namespace;
  if (!controller_params_.spawn_names.empty()) {
    options.controllers = controller_params_.controllers;
    options.controller_names = controller_params_.spawn_names;
    options.pid_gains = controller_params_.pid_gains;
  }
  const std::size_t warnings = world_->scene().warnings.size();
  auto in = toPoseTwist(req.pose, req.twist, "spawn_urdf");
  auto ok = in ? world_->spawnUrdf(req.name, req.urdf, in->pose_root, in->linear_W, in->angular_W,
                                   options)
               : Result<bool>(in.failure());
  res.success = ok.ok();
  markDisturbed();
  if (!ok) {
    res.message = ok.error();
    refuse("spawn_urdf", ok.error());
    return true;
  }
  const auto& all = world_->scene().warnings;
  for (std::size_t k = warnings; k < all.size(); ++k) ROS_WARN("simulator: %s", all[k].c_str());
  syncDrives();  // before the static frames (its odometry anchor) and the controllers' topics
  syncSensorTopics();
  publishStaticFrames();
  publishNewMovingFrames();
  syncControllerTopics();
  std::string controllers;
  if (world_->model().findRobot(req.name) >= 0)
    for (const sim::ControllerData& c : world_->data().controllers.running)
      if (!c.name_space.empty() && c.name_space == req.robot_namespace)
        controllers += (controllers.empty() ? "; controllers " : ", ") + c.config.name;
  ROS_INFO(
      "simulator: spawned '%s'%s%s", req.name.c_str(),
      req.robot_namespace.empty() ? "" : (" under namespace '" + req.robot_namespace + "'").c_str(),
      controllers.c_str());
  return true;
}

bool Simulator::onDeleteBody(cga_rigid_sim::DeleteBody::Request& req,
                             cga_rigid_sim::DeleteBody::Response& res) {
  auto ok = world_->deleteBody(req.body);
  res.success = ok.ok();
  if (!ok) {
    res.message = ok.error();
    refuse("delete_body", ok.error());
    return true;
  }
  syncDrives();
  syncSensorTopics();
  publishStaticFrames();
  syncControllerTopics();
  ROS_INFO("simulator: deleted '%s'", req.body.c_str());
  return true;
}

bool Simulator::onApplyJointEffort(cga_rigid_sim::ApplyJointEffort::Request& req,
                                   cga_rigid_sim::ApplyJointEffort::Response& res) {
  auto ok = world_->applyJointEffort(toTimedJointEffortInput(req));
  res.success = ok.ok();
  if (!ok) {
    res.message = refusalText(ok.failure(), "apply_joint_effort");
    refuse("apply_joint_effort", res.message);
  }
  return true;
}

}  // namespace node
}  // namespace cga_rigid_sim
