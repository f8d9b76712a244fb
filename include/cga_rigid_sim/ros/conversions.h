// Conversions between ROS messages and the core's types (sim/world.h, sim/input/inputs.h).
//
// The node is thin glue: these functions only change representation. Where a message can hold
// something the core type cannot (a non-unit quaternion, NaN in a field the core never sees),
// the conversion refuses it with an error naming the message field and the rule, in the same
// style as World's own refusals ("apply_wrench.f.x: not finite"). Physics validation (limits,
// unknown bodies and frames, stamps already past) stays in World.
//
// Time: every stamp is simulation time. A ROS time t ↔ t.toSec() seconds of simulation; the
// zero stamp means "the next step" for inputs (sim/input/inputs.h).
//
// Defined in src/ros/: conversions.cc (time, geometry), conversions_inputs.cc (inputs, refusal
// texts, pose and twist), conversions_outputs.cc (outputs, built anew or in place) and
// conversions_controllers.cc (controller commands and states).
#pragma once

#include <cga_rigid_sim/ApplyJointEffort.h>
#include <cga_rigid_sim/BodyState.h>
#include <cga_rigid_sim/BodyStateArray.h>
#include <cga_rigid_sim/CgaImpulse.h>
#include <cga_rigid_sim/CgaWrench.h>
#include <cga_rigid_sim/Contact.h>
#include <cga_rigid_sim/ContactArray.h>
#include <cga_rigid_sim/CurvedMomentumArray.h>
#include <cga_rigid_sim/JointTrajectoryControllerState.h>
#include <cga_rigid_sim/Momentum.h>
#include <cga_rigid_sim/MomentumArray.h>
#include <geometry_msgs/Point.h>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/Vector3.h>
#include <geometry_msgs/WrenchStamped.h>
#include <ros/time.h>
#include <sensor_msgs/JointState.h>
#include <tf2_msgs/TFMessage.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "cga_rigid_sim/control/joint_trajectory.h"
#include "cga_rigid_sim/control/trajectory_controller.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/sim/input/inputs.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace node {

// ---- time ----

/// Simulation time t (s) as a ROS time (rounded to the nanosecond).
::ros::Time toRosTime(double t);
/// A ROS stamp as simulation time, s.
double toSimTime(const ::ros::Time& stamp);

// ---- geometry ----

Eigen::Vector3d toEigen(const geometry_msgs::Vector3& v);
Eigen::Vector3d toEigen(const geometry_msgs::Point& p);
geometry_msgs::Vector3 toVector3Msg(const Eigen::Vector3d& v);
geometry_msgs::Point toPointMsg(const Eigen::Vector3d& p);
geometry_msgs::Pose toPoseMsg(const Eigen::Isometry3d& T);
geometry_msgs::Transform toTransformMsg(const Eigen::Isometry3d& T);

/// A pose as an isometry. Refuses non-finite coordinates and quaternions that break the one
/// rotation rule (scene/rotation_rule.h: norm within 1e-3 of 1, then normalised; the all-zero
/// default of a message is refused); `field` names the pose in the error ("spawn_urdf.pose").
Result<Eigen::Isometry3d> toIsometry(const geometry_msgs::Pose& pose, const std::string& field);

/// `field`: not finite → error "<field>.x: not finite (NaN or Inf)"; else the vector.
Result<Eigen::Vector3d> toFiniteEigen(const geometry_msgs::Vector3& v, const std::string& field);
Result<Eigen::Vector3d> toFiniteEigen(const geometry_msgs::Point& p, const std::string& field);

// ---- inputs (messages → core) ----

/// CgaWrench → WrenchInput. An empty header.frame_id means the world frame. `topic` names the
/// message in errors ("apply_wrench").
Result<sim::WrenchInput> toWrenchInput(const cga_rigid_sim::CgaWrench& msg,
                                       const std::string& world_frame, const std::string& topic);
/// CgaImpulse → ImpulseInput (frames as for CgaWrench).
Result<sim::ImpulseInput> toImpulseInput(const cga_rigid_sim::CgaImpulse& msg,
                                         const std::string& world_frame, const std::string& topic);
/// The plain ROS form: header.frame_id names a link, force and torque act at that link's
/// origin in its axes, for one step starting at header.stamp. The body is the one that owns
/// the link (looked up in `scene`).
Result<sim::WrenchInput> toWrenchInput(const geometry_msgs::WrenchStamped& msg,
                                       const scene::Scene& scene, const std::string& topic);

/// sensor_msgs/JointState → held joint efforts: `name`, `effort` and header.stamp (simulation
/// time to take effect, zero = the next step); `position` and `velocity` are ignored (an effort
/// command, as ros_control's effort controllers take it). Never refuses: World checks the
/// lengths, the names, finiteness and the stamp (sim/input/inputs.h JointEffortInput).
sim::JointEffortInput toJointEffortInput(const sensor_msgs::JointState& msg);
/// The ~apply_joint_effort request as a timed effort (the fields map one to one).
sim::TimedJointEffortInput toTimedJointEffortInput(
    const cga_rigid_sim::ApplyJointEffort::Request& req);

/// The text of a World refusal as the user of `topic` reads it. The core's Error names its
/// own input and fields (sim/input/inputs.h: apply_impulse.J, apply_wrench.couple, start_time,
/// frame, joint_efforts.stamp); this names the topic and the message's own field instead
/// (apply_impulse.f, apply_wrench.torque, header.stamp, header.frame_id; for the plain `wrench`
/// topic wrench.wrench.force, …), keeping the sub-field (".x", "[2]") and the rule. `topic` is
/// "apply_wrench", "apply_impulse", "wrench", "joint_efforts" or "apply_joint_effort" (whose
/// request fields are the core's names); an Error without input is its message.
std::string refusalText(const Error& core, const std::string& topic);

/// What set_body_state and spawn_urdf carry: the root link's pose and the velocities of the
/// centre of mass and the angular velocity, world axes.
struct PoseTwist {
  Eigen::Isometry3d pose_root = Eigen::Isometry3d::Identity();
  Eigen::Vector3d linear_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_W = Eigen::Vector3d::Zero();
};
/// Pose and twist, validated (finite, unit quaternion); `field` prefixes errors.
Result<PoseTwist> toPoseTwist(const geometry_msgs::Pose& pose, const geometry_msgs::Twist& twist,
                              const std::string& field);

// ---- outputs (core → messages) ----

cga_rigid_sim::Momentum toMomentumMsg(const sim::MomentumReport& r);
cga_rigid_sim::MomentumArray toMomentumArrayMsg(const std::vector<sim::MomentumReport>& reports,
                                                const ::ros::Time& stamp,
                                                const std::string& world_frame);
/// Curved space: the 4-d momenta (World::curvedMomentum) and the radius R.
cga_rigid_sim::CurvedMomentumArray toCurvedMomentumArrayMsg(
    const std::vector<sim::CurvedMomentumReport>& reports, double curvature_radius,
    const ::ros::Time& stamp, const std::string& world_frame);
/// Pose, CoM, twist (world axes) and the blade coefficients of M_WB and Ω_B.
cga_rigid_sim::BodyState toBodyStateMsg(const sim::BodyStateReport& r);
cga_rigid_sim::BodyStateArray toBodyStateArrayMsg(const std::vector<sim::BodyStateReport>& reports,
                                                  const ::ros::Time& stamp,
                                                  const std::string& world_frame);
/// A contact of the last step: names, point and normal (world), depth, impulses on body a.
cga_rigid_sim::Contact toContactMsg(const sim::ContactReport& r);
cga_rigid_sim::ContactArray toContactArrayMsg(const std::vector<sim::ContactReport>& reports,
                                              const ::ros::Time& stamp,
                                              const std::string& world_frame);
/// Every joint of every tree (World::jointStates(), scene order) in one message, stamped in
/// simulation time: name, position (rad or m), velocity, and effort = what the actuator applied
/// in the last step (held + timed, clamped to <limit effort>; 0 before the first step).
sensor_msgs::JointState toJointStateMsg(const std::vector<sim::JointStateReport>& reports,
                                        const ::ros::Time& stamp);
geometry_msgs::TransformStamped toTransformStampedMsg(const sim::FramePose& frame,
                                                      const ::ros::Time& stamp);
tf2_msgs::TFMessage toTfMessage(const std::vector<sim::FramePose>& frames,
                                const ::ros::Time& stamp);

// ---- outputs in place (messages kept from tick to tick) ----
//
// The node's per-tick outputs are overwritten rather than built anew (10 000 bodies make
// megabytes per tick): the result equals the to…Msg conversion above, but the strings (frame
// ids, body names) are written only when `names` is true or the number of entries changed, and
// the message's memory is reused. The caller passes `names` = true whenever the set of bodies
// may have changed (World::topologyVersion()); the numbers and stamps are written every time.
void fillTfMessage(const std::vector<sim::FramePose>& frames, const ::ros::Time& stamp, bool names,
                   tf2_msgs::TFMessage* msg);
/// tf of the moving frames made from the body states instead (World::bodyStates(): a body's
/// name is its root link's name, pose_root that link's pose in the world): the transforms of
/// World::movingFrames(), in its order, without reading the World a second time when the node
/// publishes both.
void fillTfMessage(const std::vector<sim::BodyStateReport>& states, const std::string& world_frame,
                   const ::ros::Time& stamp, bool names, tf2_msgs::TFMessage* msg);
void fillMomentumArrayMsg(const std::vector<sim::MomentumReport>& reports, const ::ros::Time& stamp,
                          const std::string& world_frame, bool names,
                          cga_rigid_sim::MomentumArray* msg);
void fillBodyStateArrayMsg(const std::vector<sim::BodyStateReport>& reports,
                           const ::ros::Time& stamp, const std::string& world_frame, bool names,
                           cga_rigid_sim::BodyStateArray* msg);

// ---- controllers (doc/node.md#controllers) ----

/// trajectory_msgs/JointTrajectory → the core's trajectory: header.stamp → start_time (0 = now),
/// joint_names, and per point positions, velocities, accelerations, effort and time_from_start
/// (s). Never refuses: World::commandTrajectory checks it (control::validate).
control::JointTrajectory toJointTrajectory(const trajectory_msgs::JointTrajectory& msg);
/// A trajectory controller's state (desired, actual, error in its joints' order) as
/// `<controller>/state`, stamped `stamp`; every point's time_from_start is `uptime`.
cga_rigid_sim::JointTrajectoryControllerState toControllerStateMsg(
    const control::TrajectoryControllerState& state, const ::ros::Time& stamp,
    const ::ros::Duration& uptime);

}  // namespace node
}  // namespace cga_rigid_sim
