// Sensors and base drives as a robot description declares them in Gazebo's vocabulary
// (doc/sensors.md): <gazebo reference="link"><sensor type="imu|force_torque|contact"> with its
// gazebo_ros plugin, and the model plugins gazebo_ros_p3d, gazebo_ros_imu, gazebo_ros_diff_drive
// and gazebo_ros_skid_steer_drive. Read by the URDF loader (urdf_xml_gazebo.cc), ROS-free,
// constant after loading. Parameter names, defaults and meanings are gazebo_ros's; topics are
// resolved to the name the plugin would publish on (its robotNamespace joined to its topic).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

namespace cga_rigid_sim {
namespace scene {

/// SDF's <noise type="gaussian">: each sample is value + bias + N(mean, stddev²); the bias is
/// drawn once per run as N(bias_mean, bias_stddev²) with a random sign, as Gazebo does.
struct GaussianNoise {
  double mean = 0.0;
  double stddev = 0.0;       ///< ≥ 0
  double bias_mean = 0.0;    ///< ≥ 0 (its sign is drawn)
  double bias_stddev = 0.0;  ///< ≥ 0
  bool any() const {
    return mean != 0.0 || stddev != 0.0 || bias_mean != 0.0 || bias_stddev != 0.0;
  }
};

enum class SensorKind {
  kImu,          ///< sensor_msgs/Imu
  kForceTorque,  ///< geometry_msgs/WrenchStamped: a joint's reaction wrench
  kContact,      ///< the contacts of one link (bumper)
  kGroundTruth,  ///< nav_msgs/Odometry of a link (p3d)
};
const char* toString(SensorKind k);

/// force_torque <frame>: the axes and reference point the wrench is given in.
enum class WrenchFrame { kChild, kParent, kSensor };
/// force_torque <measure_direction>, as SDF defines it: parent_to_child is the wrench the parent
/// applies on the child through the joint, child_to_parent (the default) the wrench the child
/// applies on the parent (its negative).
enum class MeasureDirection { kChildToParent, kParentToChild };

struct SensorModel {
  SensorKind kind = SensorKind::kImu;
  std::string name;    ///< <sensor name> or the model plugin's name
  std::string plugin;  ///< the plugin's filename as written
  int line = 0;        ///< of the <sensor> or model <plugin>, for messages
  /// The link the sensor is fixed to (imu, contact, p3d's bodyName); for force_torque the
  /// joint's child link.
  std::string link;
  std::string joint;  ///< force_torque: the joint it measures
  /// The sensor frame S in the link frame L: SDF <pose> (x y z roll pitch yaw) composed with
  /// the plugin's xyzOffset / rpyOffset where the plugin applies them.
  Eigen::Isometry3d X_LS = Eigen::Isometry3d::Identity();
  std::string topic;     ///< resolved topic name (relative names stay relative to the node)
  std::string frame_id;  ///< header.frame_id of the messages
  /// Samples per second of simulation time; 0 = every step (Gazebo's "as fast as possible").
  double update_rate = 0.0;

  // ---- IMU ----
  /// Per axis x, y, z, from <imu><angular_velocity>/<linear_acceleration> <noise>.
  std::array<GaussianNoise, 3> angular_velocity_noise, linear_acceleration_noise;
  /// gazebo_ros_imu_sensor's and gazebo_ros_imu's <gaussianNoise>: σ added to each of the
  /// orientation quaternion's, angular velocity's and linear acceleration's components.
  double gaussian_noise = 0.0;
  /// The orientation published is relative to the sensor's initial orientation instead of the
  /// world (gazebo_ros_imu_sensor's <initialOrientationAsReference>; default false, REP 145).
  bool initial_orientation_as_reference = false;

  // ---- force_torque ----
  WrenchFrame wrench_frame = WrenchFrame::kChild;
  MeasureDirection measure_direction = MeasureDirection::kChildToParent;

  // ---- contact ----
  /// The k-th <collision> of `link` (from 0) that <contact><collision> names by its SDF name
  /// (doc/sensors.md#bumper); −1: every collision of the link.
  int collision = -1;

  // ---- p3d, contact ----
  /// gazebo_ros_p3d's and gazebo_ros_bumper's <frameName>: p3d's pose and twist are relative to
  /// this link, the bumper's points, normals and impulses are expressed in it ("world": the
  /// world frame).
  std::string reference_link;
  Eigen::Vector3d xyz_offset = Eigen::Vector3d::Zero();  ///< p3d <xyzOffset>
  Eigen::Vector3d rpy_offset = Eigen::Vector3d::Zero();  ///< p3d <rpyOffset>
};

enum class DriveKind { kDifferential, kSkidSteer };

/// gazebo_ros_diff_drive or gazebo_ros_skid_steer_drive: cmd_vel (geometry_msgs/Twist) → wheel
/// velocities through the wheel joints' velocity servos; wheel odometry on odometryTopic.
struct DriveModel {
  DriveKind kind = DriveKind::kDifferential;
  std::string name, plugin;
  int line = 0;
  std::vector<std::string> left_joints, right_joints;  ///< 1 each (diff) or 2 each (skid)
  double wheel_separation = 0.34;  ///< m, between the left and right wheels' contact points
  double wheel_diameter = 0.15;    ///< m
  double wheel_torque = 5.0;       ///< N m the servo may apply (diff: wheelTorque)
  /// gazebo_ros_diff_drive's wheelAcceleration: m/s² at the wheel's rim, the bound on how fast
  /// the commanded wheel speed follows cmd_vel (0: at once)
  double wheel_acceleration = 0.0;
  std::string command_topic = "cmd_vel";
  std::string odometry_topic = "odom";
  std::string odometry_frame = "odom";
  std::string robot_base_frame = "base_footprint";
  bool publish_odom_tf = true;
  bool publish_wheel_tf = false;
  bool publish_wheel_joint_state = false;
  /// diff drive's <odometrySource>: encoder (integrated from the wheels) or world (truth).
  bool odometry_from_world = false;
  double update_rate = 100.0;  ///< Hz of odometry
  /// Seconds without a command after which the wheels are stopped (skid steer's
  /// commandTimeout ... diff drive has none: 0 = never).
  double command_timeout = 0.0;
};

/// Everything of this kind a URDF declares.
struct SensorSet {
  std::vector<SensorModel> sensors;
  std::vector<DriveModel> drives;
  bool empty() const { return sensors.empty() && drives.empty(); }
};

}  // namespace scene
}  // namespace cga_rigid_sim
