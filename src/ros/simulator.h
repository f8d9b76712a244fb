// Simulator: the ROS face of one sim::World. Parameters, topics, services, tf2 and /clock
// (doc/node.md has the interface tables). Thin: every callback converts a
// message to the core's types (conversions.h), calls World, and converts the answer back.
// Its rooms: simulator.cc (construction), simulator_loop.cc (the main loop),
// simulator_publishers.cc (outputs), simulator_inputs.cc (input topics, refusals),
// simulator_services.cc (services) and simulator_controllers.cc (the controllers' topics).
//
// Threading: one thread. The main loop steps the World and services the callback queue
// between steps (waiting on it until the next real-time deadline, or every kServiceInterval
// of wall time when running as fast as possible), so callbacks never race a step and World
// needs no lock. Each subscriber queue holds at most kInputQueueSize messages, which bounds
// the work done between two steps. The World is read on this thread only; with ~threads > 1
// an output tick hands the filling and sending of tf and body states to a helper thread (the
// World's workers are idle then) while it reads the momentum, and joins it before going on.
//
// Time: every stamp is simulation time t = stepCount·dt. Inputs carry their own stamps and
// World applies them at the step they belong to, never by arrival time, so replaying a bag of
// inputs into a fresh paused node driven by ~step reproduces a run bit for bit.
#pragma once

#include <cga_rigid_sim/ApplyJointEffort.h>
#include <cga_rigid_sim/BodyStateArray.h>
#include <cga_rigid_sim/CgaImpulse.h>
#include <cga_rigid_sim/CgaWrench.h>
#include <cga_rigid_sim/DeleteBody.h>
#include <cga_rigid_sim/GetBodyState.h>
#include <cga_rigid_sim/MomentumArray.h>
#include <cga_rigid_sim/SetBodyState.h>
#include <cga_rigid_sim/SetJointState.h>
#include <cga_rigid_sim/SpawnUrdf.h>
#include <cga_rigid_sim/Step.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/WrenchStamped.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64MultiArray.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cga_rigid_sim/ros/controller_params.h"
#include "cga_rigid_sim/ros/markers.h"
#include "cga_rigid_sim/ros/parameters.h"
#include "cga_rigid_sim/sensor/sensors.h"
#include "cga_rigid_sim/sensor/wheel_odometry.h"
#include "cga_rigid_sim/sim/world.h"
#include "pacing.h"
#include "reused_message.h"

namespace cga_rigid_sim {
namespace node {

/// Logs a multi-line text with ROS_INFO line by line, so every line carries the log prefix.
void logInfoLines(const std::string& text);

class Simulator {
 public:
  /// Bound on each subscriber's queue (messages): a flood is dropped by roscpp, not stored.
  static constexpr std::uint32_t kInputQueueSize = 1000;
  /// Queue size of the output publishers (per subscriber): large enough that a ~step burst
  /// reaches rosbag without drops, bounded so a slow subscriber cannot exhaust memory.
  static constexpr std::uint32_t kOutputQueueSize = 1000;
  /// Callbacks are serviced at least this often (wall time) while stepping.
  static constexpr std::chrono::milliseconds kServiceInterval{2};
  /// Longest single wait on the callback queue (paused, or between real-time steps): bounds
  /// the reaction to Ctrl-C.
  static constexpr std::chrono::milliseconds kMaxWait{50};
  /// Refusal warnings per topic or service are throttled to one per this wall time.
  static constexpr std::chrono::seconds kRefusalLogPeriod{1};

  /// `controllers`: the node's controllers parameters, which ~spawn_urdf starts for a spawned
  /// robot (~spawn_controllers, doc/node.md#spawning-robots).
  Simulator(::ros::NodeHandle nh, ::ros::NodeHandle pnh, const NodeParams& params,
            ControllerParams controllers, std::unique_ptr<sim::World> world);

  /// Publishes the initial state, then steps until shutdown. Returns the exit status.
  int run();

 private:
  // ---- stepping and publishing ----
  /// Advances n steps, publishing /clock and the outputs at their ticks; stops early on
  /// shutdown.
  void advance(std::uint64_t n);
  void publishAfterStep();
  /// tf (moving frames), momentum, body states, contacts and (scenes with joints) joint states
  /// at the current step, unless tf for this stamp was already sent (tf2 must never see the
  /// same stamp twice).
  void publishOutputs();
  void publishClock();
  /// The latched /tf_static: every static frame in one message (resent when bodies change).
  void publishStaticFrames();
  /// After a spawn at an already published stamp: the new bodies' frames only.
  void publishNewMovingFrames();
  void publishRejectedCount();
  /// Counts and logs one refused input; `what` names the topic or service. The warning names
  /// the message, the field and the rule; at most one per kRefusalLogPeriod per `what`.
  void refuse(const std::string& what, const std::string& why);
  /// Counts and warns about the inputs the World refused when they were due to start (past a
  /// bound on active wrenches; sim::World::startRefusalCount).
  void noteStartRefusals();
  /// Logs an error when the World undid tree steps that left a non-finite state
  /// (sim::World::treeFaultCount): the first at once, then at most one per kRefusalLogPeriod.
  void noteTreeFaults();
  /// Called by every service: the wall time it took must not count against real time.
  void markDisturbed() { disturbed_ = true; }

  // ---- controllers (simulator_controllers.cc, doc/node.md#controllers) ----
  /// Per running controller: `<name>/command` subscribed; for a trajectory controller
  /// `<name>/state` advertised with its state_publish_rate; for a joint state controller
  /// /joint_states at its publish_rate instead of at the output ticks. Called at start and after
  /// every spawn and delete: the topics of controllers that no longer run are closed, those of
  /// new ones opened, and /joint_states advertised once the world has joints.
  void syncControllerTopics();
  /// /joint_states at the current step, at most once per stamp.
  void publishJointStates();
  /// After each step: the trajectory controllers' states at their ticks (`always`: at the
  /// current step whatever the ticks, once per stamp), their aborts logged, and the commands the
  /// World refused at their step counted.
  void publishControllerStates(bool always = false);
  void onTrajectoryCommand(const std::string& controller,
                           const trajectory_msgs::JointTrajectory::ConstPtr& msg);
  void onGroupCommand(const std::string& controller,
                      const std_msgs::Float64MultiArray::ConstPtr& msg);

  // ---- sensors (simulator_sensors.cc, doc/sensors.md#in-the-node) ----
  /// One topic per sensor the scene declares (the URDF's and the spawned robots'), advertised
  /// on its plugin's topic; after a spawn or a delete the sensors find their bodies again and
  /// the topics follow (a topic kept keeps its publisher).
  void syncSensorTopics();
  /// After each step: the sensors due at this step, for the topics with subscribers; the
  /// differentiating ones remember the step before their next sample.
  void publishSensors();
  /// Drops what the sensors remembered (after a reset: no difference across the jump).
  void forgetSensors();
  // ---- drives (simulator_drives.cc, doc/sensors.md#drives) ----
  /// Per drive the scene declares: its wheels' velocity controller loaded, commandTopic
  /// subscribed, odometry advertised; a drive whose robot was deleted is dropped.
  void syncDrives();
  void onCmdVel(const std::string& controller, const geometry_msgs::Twist::ConstPtr& msg);
  /// After each step: the wheels' commands ramped (wheelAcceleration), each drive's odometry
  /// (and tf) at its update rate.
  void publishDrives();
  /// world → odometry frame of each drive that publishes its odom tf: where its odometry
  /// started (doc/sensors.md#drives). For the latched /tf_static.
  std::vector<sim::FramePose> odometryAnchors() const;

  // ---- callbacks ----
  void onApplyWrench(const cga_rigid_sim::CgaWrench::ConstPtr& msg);
  void onApplyImpulse(const cga_rigid_sim::CgaImpulse::ConstPtr& msg);
  void onWrench(const geometry_msgs::WrenchStamped::ConstPtr& msg);
  void onJointEfforts(const sensor_msgs::JointState::ConstPtr& msg);
  bool onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onClearWrenches(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool onStep(cga_rigid_sim::Step::Request& req, cga_rigid_sim::Step::Response& res);
  bool onGetBodyState(cga_rigid_sim::GetBodyState::Request& req,
                      cga_rigid_sim::GetBodyState::Response& res);
  bool onSetBodyState(cga_rigid_sim::SetBodyState::Request& req,
                      cga_rigid_sim::SetBodyState::Response& res);
  bool onSetJointState(cga_rigid_sim::SetJointState::Request& req,
                       cga_rigid_sim::SetJointState::Response& res);
  bool onSpawnUrdf(cga_rigid_sim::SpawnUrdf::Request& req, cga_rigid_sim::SpawnUrdf::Response& res);
  bool onDeleteBody(cga_rigid_sim::DeleteBody::Request& req,
                    cga_rigid_sim::DeleteBody::Response& res);
  bool onApplyJointEffort(cga_rigid_sim::ApplyJointEffort::Request& req,
                          cga_rigid_sim::ApplyJointEffort::Response& res);

  ::ros::NodeHandle nh_, pnh_;
  NodeParams params_;
  std::unique_ptr<sim::World> world_;
  TickSchedule output_ticks_;
  TickSchedule clock_ticks_;
  RealTimePacer pacer_;

  /// The world has had articulated joints: /joint_states is advertised and published (from
  /// start, or from the first robot ~spawn_urdf adds; it stays advertised when robots go).
  bool has_joints_ = false;
  ControllerParams controller_params_;
  bool paused_ = false;
  bool disturbed_ = false;
  std::uint64_t rejected_ = 0;
  std::uint64_t start_refusals_seen_ = 0;  ///< of world_->startRefusalCount()
  std::uint64_t tree_faults_seen_ = 0;     ///< of world_->treeFaultCount(), logged
  struct Throttle {
    bool shown = false;
    std::chrono::steady_clock::time_point last{};
    std::uint64_t suppressed = 0;
  };
  std::map<std::string, Throttle> refusal_log_;
  Throttle fault_log_;
  /// Step count of the last tf and of the last /clock sent (none yet: UINT64_MAX), and the
  /// topology version of the last /tf_static.
  std::uint64_t last_tf_step_ = UINT64_MAX;
  std::uint64_t last_clock_step_ = UINT64_MAX;
  std::uint64_t static_version_ = UINT64_MAX;
  /// The children sent at last_tf_step_ (tf2 must not see a child twice at one stamp): those
  /// of tf_msg_ when tf_msg_sent_, plus the late_tf_children_ that publishNewMovingFrames sent.
  bool tf_msg_sent_ = false;
  std::vector<std::string> late_tf_children_;

  /// The per-tick outputs of many bodies, overwritten at every tick (reused_message.h).
  ReusedMessage<tf2_msgs::TFMessage> tf_msg_;
  ReusedMessage<cga_rigid_sim::MomentumArray> momentum_msg_;
  ReusedMessage<cga_rigid_sim::BodyStateArray> body_states_msg_;

  ::ros::Publisher tf_pub_, tf_static_pub_, clock_pub_;
  ::ros::Publisher momentum_pub_, body_states_pub_, contacts_pub_, rejected_pub_;
  ::ros::Publisher curved_momentum_pub_;  ///< only with ~curvature (doc/curved_space.md)
  ::ros::Publisher joint_states_pub_;
  ::ros::Publisher markers_pub_;  ///< ~markers for rviz (markers.h), built only when subscribed
  MarkerReferences marker_refs_;  ///< the arrows' scales in use (grow with the motion seen)
  std::vector<::ros::Subscriber> subscribers_;
  std::vector<::ros::ServiceServer> services_;

  /// Per running controller (not joint state controllers), by name: its `<name>/command`.
  std::map<std::string, ::ros::Subscriber> controller_commands_;
  /// One trajectory controller's `<name>/state` (index into World::data().controllers.running,
  /// kept in step with it by syncControllerTopics).
  struct ControllerState {
    std::string name;
    std::size_t controller = 0;
    ::ros::Publisher publisher;
    TickSchedule ticks;
    std::uint64_t last_step = UINT64_MAX;  ///< of the last state sent
    std::string last_reason;               ///< of the last abort logged
  };
  std::vector<ControllerState> controller_states_;
  /// The sensors (none when the URDF declares none) and one topic per simulated sensor.
  std::unique_ptr<sensor::Sensors> sensors_;
  std::uint64_t sensors_version_ = 0;  ///< the topology version they were made for
  struct SensorTopic {
    std::size_t sensor = 0;
    scene::SensorKind kind = scene::SensorKind::kImu;
    std::string topic;
    ::ros::Publisher publisher;
    TickSchedule ticks;
    std::uint64_t last_step = UINT64_MAX;
  };
  std::vector<SensorTopic> sensor_topics_;
  /// One base drive: its wheels' controller, cmd_vel, wheel odometry.
  struct Drive {
    scene::DriveModel model;
    std::string controller;  ///< the velocity group controller of its wheels
    std::string base_link;   ///< the wheels' parent link (odometrySource world)
    ::ros::Subscriber command;
    ::ros::Publisher odometry;
    /// The wheels' speeds cmd_vel asks for and the ones commanded now (they differ while a
    /// wheelAcceleration ramps them), rad/s, left wheels first.
    std::vector<double> target, commanded;
    /// world → odometry frame: the base's planar pose when the drive started.
    Eigen::Isometry3d X_WO = Eigen::Isometry3d::Identity();
    TickSchedule ticks{1.0, 1.0};
    bool publish_tf = false;
    std::uint64_t last_step = UINT64_MAX;              ///< of the last tick
    double left_position = 0.0, right_position = 0.0;  ///< mean wheel angles then, rad
    sensor::PlanarPose pose;                           ///< dead-reckoned in the odometry frame
  };
  std::vector<Drive> drives_;
  /// A joint_state_controller's publish_rate, when one runs: /joint_states at its ticks.
  std::optional<TickSchedule> joint_state_ticks_;
  std::uint64_t last_joint_states_step_ = UINT64_MAX;
  std::uint64_t controller_refusals_seen_ = 0;  ///< of data().controllers.refused_at_step
};

}  // namespace node
}  // namespace cga_rigid_sim
