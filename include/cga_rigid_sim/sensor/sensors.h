// The sensors of a World's scene at run time (doc/sensors.md): each SensorModel the URDF
// declares (scene/sensors.h) resolved to the body that carries it, with its noise channels and
// the state it remembered one step ago. Readings are computed from the World after a step; they
// never change the simulation. Which steps are sampled is the caller's (the node samples at each
// sensor's update rate): a sensor that differentiates (IMU, force-torque) must be told to
// remember() the step before each sample.
//
// Noise: sample n of sensor k draws from streams derived from (seed, k), so a reading depends on
// the seed, the sensor, the step's state and n only (noise.h): bit-identical across runs and
// bag replays, whatever was subscribed when.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/scene/sensors.h"
#include "cga_rigid_sim/sensor/imu.h"
#include "cga_rigid_sim/sensor/noise.h"
#include "cga_rigid_sim/sim/reports.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace sensor {

/// A link's pose and the velocity of its origin in a reference frame R (world or a link), as
/// gazebo_ros_p3d gives them: the twist is the difference of the origins' world velocities,
/// expressed in R's axes.
struct OdometrySample {
  Eigen::Isometry3d X_RL = Eigen::Isometry3d::Identity();
  Eigen::Vector3d linear_R = Eigen::Vector3d::Zero();   ///< m/s
  Eigen::Vector3d angular_R = Eigen::Vector3d::Zero();  ///< rad/s
};

/// The wrench a joint transmits (force-torque sensor), in the frame the sensor declares, in
/// the direction it declares (SDF's <measure_direction>).
///
/// What the parent applies on the child through the joint is what changes the momentum of
/// everything below the joint beyond the external loads on it: W = Σ_b (dP_b/dt, dL_b/dt) − Σ
/// (gravity, applied wrenches, contact impulses / h) over the subtree's bodies b, the rates
/// taken as the mean over the step that ends at the sample ((P(t) − P(t − h))/h, angular momenta
/// about one fixed point; gravity and the applied wrenches at the step's mean pose). It holds
/// the constraint wrench and the joint's own actuation, damping, friction and limit; from the
/// tree's actual motion, so it agrees with the inverse dynamics of that motion.
struct WrenchSample {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< N
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< N m, about the frame's origin
};

class Sensors {
 public:
  /// Every sensor of world.scene().sensors; `seed` keys the noise.
  Sensors(const sim::World& world, std::uint64_t seed);

  std::size_t size() const { return entries_.size(); }
  /// Whether sensor k's link is in the World (a deleted body's sensors read nothing; the
  /// readings below require it).
  bool present(std::size_t k) const { return entries_[k].body >= 0; }
  const scene::SensorModel& model(std::size_t k) const { return entries_[k].model; }

  /// Sensor k remembers the World's current step: the start of the difference its next sample
  /// takes (IMU, force-torque). Cheap: one body state (or a tree's rates) copied.
  void remember(std::size_t k, const sim::World& world);
  /// Whether sensor k remembered the step just before the current one (else its next sample
  /// has no difference to take and is skipped).
  bool ready(std::size_t k, const sim::World& world) const;

  /// IMU k's sample n at the current step, noise applied. Requires ready(k).
  ImuSample imu(std::size_t k, const sim::World& world, std::uint64_t n) const;
  /// Ground-truth odometry k's sample n at the current step, noise applied.
  OdometrySample odometry(std::size_t k, const sim::World& world, std::uint64_t n) const;
  /// Force-torque k's sample n at the current step, noise applied. Requires ready(k). A sensor
  /// on a joint that is not a revolute, continuous or prismatic joint of a tree (a fixed joint,
  /// merged into its body) reads nothing: measures(k) is false.
  WrenchSample wrench(std::size_t k, const sim::World& world, std::uint64_t n) const;
  bool measures(std::size_t k) const {
    return !entries_[k].subtree.empty() ||
           entries_[k].model.kind != scene::SensorKind::kForceTorque;
  }

  /// The contacts of the last step that touch sensor k's link — its collision the sensor names,
  /// or any — with the link on side a (normals and impulses turned to act on it), expressed in
  /// the sensor's frameName (the world, or a link's frame now).
  std::vector<sim::ContactReport> contacts(std::size_t k, const sim::World& world) const;

  /// The state of the body carrying sensor k at the current step (a static body's pose, at
  /// rest).
  dynamics::BodyState bodyState(std::size_t k, const sim::World& world) const;

 private:
  struct Entry {
    scene::SensorModel model;
    int moving = -1;  ///< moving index of the body carrying the link; −1: static
    int body = -1;    ///< scene body index
    Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();  ///< the link in the body
    Eigen::Isometry3d X_BS = Eigen::Isometry3d::Identity();  ///< the sensor in the body
    /// p3d, contact: frameName's body (−1: the world) and the link in that body.
    int reference_body = -1;
    Eigen::Isometry3d X_RB_L = Eigen::Isometry3d::Identity();
    std::vector<int> shapes;  ///< contact: the collision shapes reported (indices in the body)
    std::array<NoisyChannel, 3> angular_velocity, linear_acceleration;
    std::uint64_t stream = 0;  ///< the plugin's gaussianNoise stream
    /// force_torque: the moving bodies below the joint (its child first), whether each moving
    /// body is one of them (by moving index), their states one step ago, and the joint's parent
    /// body (−1: the world; for its frame).
    std::vector<int> subtree;
    std::vector<bool> in_subtree;
    std::vector<dynamics::BodyState> subtree_before;
    int parent_body = -1;
    Eigen::Isometry3d X_PL = Eigen::Isometry3d::Identity();  ///< parent link in its body
    dynamics::BodyState before;
    std::uint64_t before_step = UINT64_MAX;
    Eigen::Quaterniond initial_orientation = Eigen::Quaterniond::Identity();
  };
  dynamics::BodyState stateOf(int moving, int body, const sim::World& world) const;
  void resolveJoint(const sim::World& world, Entry* e);
  void resolveCollisions(const sim::World& world, int link, Entry* e);

  std::uint64_t seed_;
  std::vector<Entry> entries_;
};

}  // namespace sensor
}  // namespace cga_rigid_sim
