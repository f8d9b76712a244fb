// The node's construction (simulator.h): the configuration said, then the outputs advertised,
// the input topics subscribed and the services offered (doc/node.md).
#include "simulator.h"

#include <rosgraph_msgs/Clock.h>
#include <std_msgs/UInt64.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/ros/conversions.h"
#include "cga_rigid_sim/sim/data.h"

namespace cga_rigid_sim {
namespace node {
namespace {

constexpr std::uint32_t kClockQueueSize = 1000;  // as kOutputQueueSize

}  // namespace

void logInfoLines(const std::string& text) {
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    if (end > start) ROS_INFO("%s", text.substr(start, end - start).c_str());
    start = end + 1;
  }
}

Simulator::Simulator(::ros::NodeHandle nh, ::ros::NodeHandle pnh, const NodeParams& params,
                     ControllerParams controllers, std::unique_ptr<sim::World> world)
    : nh_(nh),
      pnh_(pnh),
      params_(params),
      world_(std::move(world)),
      output_ticks_(world_->config().dt, params.publish_rate),
      clock_ticks_(world_->config().dt, params.clock_rate),
      pacer_(world_->config().dt, params.real_time_factor),
      has_joints_(!world_->scene().joints.empty()),
      controller_params_(std::move(controllers)),
      paused_(params.paused) {
  // The configuration is said before anything is advertised: a client that sees a service up
  // has seen these lines too.
  // A joint state controller publishes /joint_states at its own rate (syncControllerTopics).
  bool joint_state_controller = false;
  for (const auto& c : world_->data().controllers.running)
    joint_state_controller |= c.config.type == control::ControllerType::kJointState;
  const std::string clock = !params_.publish_clock ? "off"
                            : params_.clock_rate > 0.0
                                ? "at " + std::to_string(params_.clock_rate) + " Hz"
                                : "every step";
  ROS_INFO(
      "simulator: dt %g s; %d thread%s; real_time_factor %g%s; tf, momentum, body states, "
      "contacts%s at %g Hz; /clock %s%s",
      world_->config().dt, world_->config().threads, world_->config().threads == 1 ? "" : "s",
      params_.real_time_factor, params_.real_time_factor == 0.0 ? " (as fast as possible)" : "",
      has_joints_ && !joint_state_controller ? " and /joint_states" : "", params_.publish_rate,
      clock.c_str(), paused_ ? "; paused (call ~unpause, or ~step)" : "");

  const sim::WorldConfig& config = world_->config();
  const std::string plane =
      config.ground_plane
          ? "ground plane at z = " + formatNumber(config.ground_plane->height) + " m (mu " +
                formatNumber(config.ground_plane->surface.mu.value_or(config.contact_mu)) +
                ", restitution " +
                formatNumber(
                    config.ground_plane->surface.restitution.value_or(config.contact_restitution)) +
                ")"
          : "no ground plane";
  ROS_INFO("simulator: %s; surfaces without their own: mu %s, restitution %s", plane.c_str(),
           formatNumber(config.contact_mu).c_str(),
           formatNumber(config.contact_restitution).c_str());

  if (config.curvature) {
    const double R = *config.curvature;
    ROS_INFO(
        "simulator: curved space, %s of radius %s m (~curvature); free bodies move 1 up "
        "(doc/curved_space.md). tf shows them in the stereographic chart from the antipode of "
        "the origin%s: conformal (angles and orientations true), lengths %s away from the origin "
        "by 1/(1 + K|x|^2/4), K = %s 1/m^2; 4-d momenta on ~curved_momentum",
        R > 0 ? "3-sphere" : "hyperbolic space", formatNumber(std::abs(R)).c_str(),
        R > 0 ? "" : " (the Poincare ball of radius 2|R|)", R > 0 ? "overstated" : "understated",
        formatNumber((R > 0 ? 1.0 : -1.0) / (R * R)).c_str());
    curved_momentum_pub_ =
        pnh_.advertise<cga_rigid_sim::CurvedMomentumArray>("curved_momentum", kOutputQueueSize);
  }

  // tf and /clock keep their global names (remappable as usual); the rest is private.
  tf_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf", kOutputQueueSize);
  tf_static_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf_static", 1, /*latch=*/true);
  if (params_.publish_clock)
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", kClockQueueSize);
  momentum_pub_ = pnh_.advertise<cga_rigid_sim::MomentumArray>("momentum", kOutputQueueSize);
  body_states_pub_ = pnh_.advertise<cga_rigid_sim::BodyStateArray>("body_states", kOutputQueueSize);
  contacts_pub_ = pnh_.advertise<cga_rigid_sim::ContactArray>("contacts", kOutputQueueSize);
  rejected_pub_ = pnh_.advertise<std_msgs::UInt64>("rejected_inputs", 1, /*latch=*/true);
  markers_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>("markers", kOutputQueueSize);
  // /joint_states keeps its global name too (robot_state_publisher and rviz listen there), and
  // exists only for a scene with joints: a node of free bodies is no source of joint states.
  if (has_joints_)
    joint_states_pub_ = nh_.advertise<sensor_msgs::JointState>("/joint_states", kOutputQueueSize);

  subscribers_.push_back(
      pnh_.subscribe("apply_wrench", kInputQueueSize, &Simulator::onApplyWrench, this));
  subscribers_.push_back(
      pnh_.subscribe("apply_impulse", kInputQueueSize, &Simulator::onApplyImpulse, this));
  subscribers_.push_back(pnh_.subscribe("wrench", kInputQueueSize, &Simulator::onWrench, this));
  subscribers_.push_back(
      pnh_.subscribe("joint_efforts", kInputQueueSize, &Simulator::onJointEfforts, this));

  services_.push_back(pnh_.advertiseService("pause", &Simulator::onPause, this));
  services_.push_back(pnh_.advertiseService("unpause", &Simulator::onUnpause, this));
  services_.push_back(pnh_.advertiseService("reset", &Simulator::onReset, this));
  services_.push_back(pnh_.advertiseService("clear_wrenches", &Simulator::onClearWrenches, this));
  services_.push_back(pnh_.advertiseService("step", &Simulator::onStep, this));
  services_.push_back(pnh_.advertiseService("get_body_state", &Simulator::onGetBodyState, this));
  services_.push_back(pnh_.advertiseService("set_body_state", &Simulator::onSetBodyState, this));
  services_.push_back(pnh_.advertiseService("set_joint_state", &Simulator::onSetJointState, this));
  services_.push_back(pnh_.advertiseService("spawn_urdf", &Simulator::onSpawnUrdf, this));
  services_.push_back(pnh_.advertiseService("delete_body", &Simulator::onDeleteBody, this));
  services_.push_back(
      pnh_.advertiseService("apply_joint_effort", &Simulator::onApplyJointEffort, this));
  syncDrives();  // before the controllers' topics, which leave the drives' controllers out
  syncControllerTopics();
  syncSensorTopics();
}

}  // namespace node
}  // namespace cga_rigid_sim
