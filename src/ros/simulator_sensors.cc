// The sensors' topics (simulator.h, doc/sensors.md#in-the-node): each sensor the URDF declares
// in Gazebo's vocabulary publishes on its plugin's topic at its update rate on the simulation
// clock, stamped in simulation time, and is computed only while someone subscribes. Sample n of
// a sensor is its tick index, so its noise is the same whatever was subscribed before.
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>

#include <algorithm>
#include <cmath>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/ros/conversions.h"
#include "simulator.h"

namespace cga_rigid_sim {
namespace node {
namespace {

constexpr std::uint32_t kSensorQueueSize = 100;

geometry_msgs::Quaternion quaternionMsg(const Eigen::Quaterniond& q) {
  geometry_msgs::Quaternion m;
  m.x = q.x();
  m.y = q.y();
  m.z = q.z();
  m.w = q.w();
  return m;
}

// The diagonal of a 3×3 row-major covariance.
template <class Array>
void setDiagonal(Array& covariance, const Eigen::Vector3d& variances) {
  for (int a = 0; a < 3; ++a) covariance[4 * a] = variances[a];
}

// The sensors whose sample is a difference over the step before it (sensor/sensors.h).
bool differentiates(scene::SensorKind kind) {
  return kind == scene::SensorKind::kImu || kind == scene::SensorKind::kForceTorque;
}

}  // namespace

void Simulator::syncSensorTopics() {
  sensors_version_ = world_->topologyVersion();
  if (world_->scene().sensors.sensors.empty() && sensor_topics_.empty()) return;
  sensors_ = std::make_unique<sensor::Sensors>(*world_, params_.sensor_seed);
  std::vector<SensorTopic> before = std::move(sensor_topics_);
  sensor_topics_.clear();
  for (std::size_t k = 0; k < sensors_->size(); ++k) {
    const scene::SensorModel& s = sensors_->model(k);
    if (s.kind == scene::SensorKind::kForceTorque && !sensors_->measures(k)) {
      ROS_WARN(
          "simulator: force_torque sensor '%s' on joint '%s': the joint is fixed, merged into "
          "its body, and transmits nothing the simulation resolves: %s stays silent",
          s.name.c_str(), s.joint.c_str(), s.topic.c_str());
      continue;
    }
    // A sensor that had its topic before a spawn or a delete keeps it (and its subscribers).
    const auto kept = std::find_if(before.begin(), before.end(), [&s](const SensorTopic& t) {
      return t.kind == s.kind && t.topic == s.topic && t.publisher;
    });
    SensorTopic topic{k, s.kind, s.topic, {}, TickSchedule(world_->config().dt, s.update_rate)};
    if (kept != before.end()) {
      topic.publisher = kept->publisher;
      topic.last_step = kept->last_step;
      kept->publisher = ::ros::Publisher();
    } else {
      switch (s.kind) {
        case scene::SensorKind::kImu:
          topic.publisher = nh_.advertise<sensor_msgs::Imu>(s.topic, kSensorQueueSize);
          break;
        case scene::SensorKind::kGroundTruth:
          topic.publisher = nh_.advertise<nav_msgs::Odometry>(s.topic, kSensorQueueSize);
          break;
        case scene::SensorKind::kContact:
          topic.publisher = nh_.advertise<cga_rigid_sim::ContactArray>(s.topic, kSensorQueueSize);
          break;
        case scene::SensorKind::kForceTorque:
          topic.publisher = nh_.advertise<geometry_msgs::WrenchStamped>(s.topic, kSensorQueueSize);
          break;
      }
      if (!before.empty() || world_->stepCount() > 0)
        ROS_INFO("simulator: sensor '%s' (%s) on '%s' -> %s", s.name.c_str(),
                 scene::toString(s.kind), s.link.c_str(), s.topic.c_str());
    }
    if (differentiates(s.kind) && topic.ticks.isTick(world_->stepCount() + 1))
      sensors_->remember(k, *world_);
    sensor_topics_.push_back(std::move(topic));
  }
}

void Simulator::forgetSensors() {
  for (Drive& d : drives_) {  // the encoders' odometry restarts at the origin, as on Reset()
    d.pose = sensor::PlanarPose{};
    d.last_step = UINT64_MAX;
  }
  if (!sensors_) return;
  sensors_ = std::make_unique<sensor::Sensors>(*world_, params_.sensor_seed);
  for (const SensorTopic& t : sensor_topics_)
    if (differentiates(sensors_->model(t.sensor).kind) && t.ticks.isTick(world_->stepCount() + 1))
      sensors_->remember(t.sensor, *world_);
}

void Simulator::publishSensors() {
  if (sensor_topics_.empty()) return;
  // Bodies came or went (spawn and delete sync at once; this catches any other way): the
  // sensors' bodies are found again (their differences restart).
  if (world_->topologyVersion() != sensors_version_) syncSensorTopics();
  const std::uint64_t s = world_->stepCount();
  const ::ros::Time stamp = toRosTime(world_->time());
  for (SensorTopic& t : sensor_topics_) {
    if (!sensors_->present(t.sensor)) continue;  // its body was deleted
    const scene::SensorModel& m = sensors_->model(t.sensor);
    const std::uint64_t n = t.ticks.tickOf(s);
    if (t.ticks.isTick(s) && t.last_step != s && t.publisher.getNumSubscribers() > 0) {
      if (m.kind == scene::SensorKind::kImu && sensors_->ready(t.sensor, *world_)) {
        const sensor::ImuSample r = sensors_->imu(t.sensor, *world_, n);
        sensor_msgs::Imu msg;
        msg.header.stamp = stamp;
        msg.header.frame_id = m.frame_id;
        msg.orientation = quaternionMsg(r.orientation_WS);
        msg.angular_velocity = toVector3Msg(r.angular_velocity_S);
        msg.linear_acceleration = toVector3Msg(r.linear_acceleration_S);
        Eigen::Vector3d var_w, var_a;
        for (int a = 0; a < 3; ++a) {
          const double g2 = m.gaussian_noise * m.gaussian_noise;
          var_w[a] = g2 + std::pow(m.angular_velocity_noise[a].stddev, 2);
          var_a[a] = g2 + std::pow(m.linear_acceleration_noise[a].stddev, 2);
        }
        setDiagonal(msg.orientation_covariance,
                    Eigen::Vector3d::Constant(std::pow(m.gaussian_noise, 2)));
        setDiagonal(msg.angular_velocity_covariance, var_w);
        setDiagonal(msg.linear_acceleration_covariance, var_a);
        t.publisher.publish(msg);
        t.last_step = s;
      } else if (m.kind == scene::SensorKind::kGroundTruth) {
        const sensor::OdometrySample o = sensors_->odometry(t.sensor, *world_, n);
        nav_msgs::Odometry msg;
        msg.header.stamp = stamp;
        msg.header.frame_id = m.frame_id;
        msg.child_frame_id = m.link;
        msg.pose.pose = toPoseMsg(o.X_RL);
        msg.twist.twist.linear = toVector3Msg(o.linear_R);
        msg.twist.twist.angular = toVector3Msg(o.angular_R);
        const double g2 = m.gaussian_noise * m.gaussian_noise;
        for (int a = 0; a < 6; ++a) msg.pose.covariance[7 * a] = msg.twist.covariance[7 * a] = g2;
        t.publisher.publish(msg);
        t.last_step = s;
      } else if (m.kind == scene::SensorKind::kForceTorque && sensors_->ready(t.sensor, *world_)) {
        const sensor::WrenchSample w = sensors_->wrench(t.sensor, *world_, n);
        geometry_msgs::WrenchStamped msg;
        msg.header.stamp = stamp;
        msg.header.frame_id = m.frame_id;
        msg.wrench.force = toVector3Msg(w.force);
        msg.wrench.torque = toVector3Msg(w.torque);
        t.publisher.publish(msg);
        t.last_step = s;
      } else if (m.kind == scene::SensorKind::kContact) {
        auto msg = toContactArrayMsg(sensors_->contacts(t.sensor, *world_), stamp, m.frame_id);
        t.publisher.publish(msg);
        t.last_step = s;
      }
    }
    // The IMU and the force-torque sensor differentiate over the step before each sample: they
    // remember that step whether or not anyone listens (one body state copied), so a
    // subscriber's first sample is there.
    if (differentiates(m.kind) && t.ticks.isTick(s + 1)) sensors_->remember(t.sensor, *world_);
  }
}

}  // namespace node
}  // namespace cga_rigid_sim
