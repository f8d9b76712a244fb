// The base drives a URDF declares the Gazebo way (simulator.h, doc/sensors.md#drives):
// gazebo_ros_diff_drive and gazebo_ros_skid_steer_drive. Each takes geometry_msgs/Twist on its
// commandTopic and turns its wheels through a velocity group controller (the World's velocity
// servos, doc/control.md) — left wheels at (v − ω s/2)/r, right at (v + ω s/2)/r — and publishes
// nav_msgs/Odometry on its odometryTopic at its updateRate: dead reckoning from the wheels'
// travel (odometrySource encoder) or the base's true pose (world), and the odom → base tf.
#include <nav_msgs/Odometry.h>

#include <algorithm>
#include <cmath>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/ros/conversions.h"
#include "simulator.h"

namespace cga_rigid_sim {
namespace node {
namespace {

// The velocity servo's gain per N m of wheel torque (pid_gains p, N m s/rad): a speed error of
// 0.1 rad/s asks for the whole torque, which the joint's <limit effort> then caps.
constexpr double kServoGainPerTorque = 10.0;

}  // namespace

void Simulator::syncDrives() {
  const auto& declared = world_->scene().sensors.drives;
  // Drives whose robot was deleted (their wheels' controller went with it) are dropped.
  drives_.erase(std::remove_if(drives_.begin(), drives_.end(),
                               [&declared](const Drive& d) {
                                 return std::none_of(declared.begin(), declared.end(),
                                                     [&d](const scene::DriveModel& m) {
                                                       return m.left_joints == d.model.left_joints;
                                                     });
                               }),
                drives_.end());
  for (const scene::DriveModel& d : declared) {
    if (std::any_of(drives_.begin(), drives_.end(),
                    [&d](const Drive& x) { return x.model.left_joints == d.left_joints; }))
      continue;
    Drive drive;
    drive.model = d;
    // The controller's name: the drive's, under its robot's namespace (the wheels' joints'
    // prefix) so that two copies of one robot each have theirs.
    const std::string& wheel = d.left_joints.front();
    const std::size_t slash = wheel.rfind('/');
    const std::string prefix = slash == std::string::npos ? "" : wheel.substr(0, slash + 1);
    drive.controller = prefix + "drive_" + d.name + "_wheels";
    scene::ParamValue::List joints;
    scene::ParamValue::Map gains;
    const double p = kServoGainPerTorque * std::max(d.wheel_torque, 0.1);
    for (const auto* side : {&d.left_joints, &d.right_joints})
      for (const std::string& j : *side) {
        joints.push_back(j);
        gains[j] = scene::ParamValue::Map{{"p", p}, {"i", 0.0}, {"d", 0.0}};
      }
    const scene::ParamValue config = scene::ParamValue::Map{
        {drive.controller,
         scene::ParamValue::Map{{"type", "velocity_controllers/JointGroupVelocityController"},
                                {"joints", joints}}}};
    auto loaded = world_->loadControllers(config, {drive.controller}, gains);
    if (!loaded) {
      ROS_ERROR("simulator: drive '%s' (%s) cannot drive its wheels: %s; %s is not subscribed",
                d.name.c_str(), d.plugin.c_str(), loaded.error().c_str(), d.command_topic.c_str());
      continue;
    }
    drive.target.assign(d.left_joints.size() + d.right_joints.size(), 0.0);
    drive.commanded = drive.target;
    // The base: the wheels' parent link (the body the plugin's model moves).
    const int joint = world_->scene().findJoint(wheel);
    drive.base_link = world_->scene().joints[joint].parent_link;
    drive.ticks = TickSchedule(world_->config().dt, d.update_rate);
    drive.odometry = nh_.advertise<nav_msgs::Odometry>(d.odometry_topic, kInputQueueSize);
    // tf: odom → robotBaseFrame, unless that frame is one of the robot's links, which the node's
    // tf already places under the world frame (a second parent would break the tf tree).
    drive.publish_tf = d.publish_odom_tf;
    if (drive.publish_tf && world_->model().link_owner.count(d.robot_base_frame)) {
      ROS_WARN(
          "simulator: drive '%s': robotBaseFrame '%s' is a link the node's tf already places "
          "under '%s'; the odom tf is not published (name a frame of its own, e.g. "
          "base_footprint without a link, to get it)",
          d.name.c_str(), d.robot_base_frame.c_str(), world_->config().world_frame.c_str());
      drive.publish_tf = false;
    }
    // The odometry frame in the world: where the encoders' dead reckoning starts (the base's
    // position on z = 0 and its heading now), or the world itself for odometrySource world.
    if (!d.odometry_from_world)
      if (auto base = world_->getBodyState(drive.base_link)) {
        const Eigen::Isometry3d& X = base->pose_root;
        drive.X_WO.translation() = Eigen::Vector3d(X.translation().x(), X.translation().y(), 0);
        drive.X_WO.linear() = Eigen::AngleAxisd(std::atan2(X.linear()(1, 0), X.linear()(0, 0)),
                                                Eigen::Vector3d::UnitZ())
                                  .toRotationMatrix();
      }
    const std::string controller = drive.controller;
    drive.command = nh_.subscribe<geometry_msgs::Twist>(
        d.command_topic, kInputQueueSize,
        [this, controller](const geometry_msgs::Twist::ConstPtr& msg) {
          onCmdVel(controller, msg);
        });
    ROS_INFO("simulator: drive '%s' (%s): %s -> wheels %zu + %zu -> %s (odometry from %s)",
             d.name.c_str(), d.plugin.c_str(), d.command_topic.c_str(), d.left_joints.size(),
             d.right_joints.size(), d.odometry_topic.c_str(),
             d.odometry_from_world ? "the world" : "the wheels");
    drives_.push_back(std::move(drive));
  }
}

std::vector<sim::FramePose> Simulator::odometryAnchors() const {
  std::vector<sim::FramePose> out;
  for (const Drive& d : drives_)
    if (d.publish_tf && d.model.odometry_frame != world_->config().world_frame &&
        !world_->model().link_owner.count(d.model.odometry_frame))
      out.push_back({world_->config().world_frame, d.model.odometry_frame, d.X_WO});
  return out;
}

void Simulator::onCmdVel(const std::string& controller, const geometry_msgs::Twist::ConstPtr& msg) {
  const auto it = std::find_if(drives_.begin(), drives_.end(), [&controller](const Drive& d) {
    return d.controller == controller;
  });
  if (it == drives_.end()) return;  // its robot was deleted while the message waited
  Drive& d = *it;
  if (!std::isfinite(msg->linear.x) || !std::isfinite(msg->angular.z)) {
    refuse(d.model.command_topic, d.model.command_topic +
                                      ": linear.x and angular.z must be finite (the message "
                                      "is ignored; the wheels keep their last command)");
    return;
  }
  // The wheels' speeds, as the plugin computes them: v ∓ ω s/2 over the radius.
  const double r = 0.5 * d.model.wheel_diameter, half = 0.5 * d.model.wheel_separation;
  const double left = (msg->linear.x - msg->angular.z * half) / r;
  const double right = (msg->linear.x + msg->angular.z * half) / r;
  const std::size_t n_left = d.model.left_joints.size();
  for (std::size_t k = 0; k < d.target.size(); ++k) d.target[k] = k < n_left ? left : right;
  if (d.model.wheel_acceleration > 0) return;  // publishDrives ramps the commands
  d.commanded = d.target;
  auto done = world_->commandGroup(d.controller, d.commanded);
  if (!done) refuse(d.model.command_topic, done.error());
}

void Simulator::publishDrives() {
  if (drives_.empty()) return;
  const std::uint64_t s = world_->stepCount();
  for (Drive& d : drives_) {
    // gazebo_ros_diff_drive's wheelAcceleration (m/s² at the wheel's rim): each step the
    // commanded speeds move towards cmd_vel's by at most a/r · dt.
    if (d.model.wheel_acceleration > 0 && d.commanded != d.target) {
      const double step =
          d.model.wheel_acceleration / (0.5 * d.model.wheel_diameter) * world_->config().dt;
      for (std::size_t k = 0; k < d.target.size(); ++k)
        d.commanded[k] += std::clamp(d.target[k] - d.commanded[k], -step, step);
      auto done = world_->commandGroup(d.controller, d.commanded);
      if (!done) refuse(d.model.command_topic, done.error());
    }
    if (!d.ticks.isTick(s) || d.last_step == s) continue;
    // The wheels' positions now (mean of each side), for the encoder's travel since the last
    // tick.
    double left = 0.0, right = 0.0;
    for (const sim::JointStateReport& j : world_->jointStates()) {
      for (const auto& n : d.model.left_joints)
        if (j.name == n) left += j.position / d.model.left_joints.size();
      for (const auto& n : d.model.right_joints)
        if (j.name == n) right += j.position / d.model.right_joints.size();
    }
    const double r = 0.5 * d.model.wheel_diameter;
    const double interval = d.last_step == UINT64_MAX
                                ? 0.0
                                : static_cast<double>(s - d.last_step) * world_->config().dt;
    const sensor::PlanarPose before = d.pose;
    if (d.last_step != UINT64_MAX)
      d.pose = sensor::integrateWheels(d.pose, (left - d.left_position) * r,
                                       (right - d.right_position) * r, d.model.wheel_separation);
    d.left_position = left;
    d.right_position = right;
    d.last_step = s;
    if (d.odometry.getNumSubscribers() == 0 && !d.publish_tf) continue;

    nav_msgs::Odometry msg;
    msg.header.stamp = toRosTime(world_->time());
    msg.header.frame_id = d.model.odometry_frame;
    msg.child_frame_id = d.model.robot_base_frame;
    Eigen::Vector3d position;
    Eigen::Quaterniond attitude;
    if (d.model.odometry_from_world) {
      auto state = world_->getBodyState(d.base_link);
      if (!state) continue;  // the robot was deleted (~delete_body): no odometry
      const Eigen::Isometry3d& X = state->pose_root;
      position = X.translation();
      attitude = Eigen::Quaterniond(X.linear());
      const double yaw = std::atan2(X.linear()(1, 0), X.linear()(0, 0));
      const Eigen::Vector3d& v = state->linear_velocity;
      msg.twist.twist.linear.x = std::cos(yaw) * v.x() + std::sin(yaw) * v.y();
      msg.twist.twist.linear.y = std::cos(yaw) * v.y() - std::sin(yaw) * v.x();
      msg.twist.twist.angular.z = state->angular_velocity.z();
    } else {
      position = Eigen::Vector3d(d.pose.x, d.pose.y, 0.0);
      attitude = Eigen::AngleAxisd(d.pose.theta, Eigen::Vector3d::UnitZ());
      if (interval > 0) {
        const double dx = d.pose.x - before.x, dy = d.pose.y - before.y;
        const double forward = std::cos(before.theta) * dx + std::sin(before.theta) * dy;
        msg.twist.twist.linear.x = std::copysign(std::hypot(dx, dy), forward) / interval;
        msg.twist.twist.angular.z = (d.pose.theta - before.theta) / interval;
      }
    }
    msg.pose.pose.position.x = position.x();
    msg.pose.pose.position.y = position.y();
    msg.pose.pose.position.z = position.z();
    msg.pose.pose.orientation.x = attitude.x();
    msg.pose.pose.orientation.y = attitude.y();
    msg.pose.pose.orientation.z = attitude.z();
    msg.pose.pose.orientation.w = attitude.w();
    // The plugin's covariances: planar pose well known, z and the tilts unknown.
    msg.pose.covariance[0] = msg.pose.covariance[7] = 1e-5;
    msg.pose.covariance[14] = msg.pose.covariance[21] = msg.pose.covariance[28] = 1e12;
    msg.pose.covariance[35] = 1e-3;
    if (d.odometry.getNumSubscribers() > 0) d.odometry.publish(msg);
    if (d.publish_tf) {
      tf2_msgs::TFMessage tf;
      geometry_msgs::TransformStamped t;
      t.header = msg.header;
      t.child_frame_id = msg.child_frame_id;
      t.transform.translation.x = position.x();
      t.transform.translation.y = position.y();
      t.transform.translation.z = position.z();
      t.transform.rotation = msg.pose.pose.orientation;
      tf.transforms.push_back(t);
      tf_pub_.publish(tf);
    }
  }
}

}  // namespace node
}  // namespace cga_rigid_sim
