// The node's input topics (simulator.h): wrenches, impulses and joint efforts converted and
// handed to the World, and every refused input counted and warned about, throttled
// (doc/node.md).
#include <chrono>

#include "cga_rigid_sim/ros/conversions.h"
#include "simulator.h"

namespace cga_rigid_sim {
namespace node {

void Simulator::noteStartRefusals() {
  const std::uint64_t n = world_->startRefusalCount();
  if (n == start_refusals_seen_) return;
  const auto last = world_->lastStartRefusal();
  rejected_ += n - start_refusals_seen_ - 1;  // refuse() counts the last one
  start_refusals_seen_ = n;
  refuse(last->input + " (at its start)", last->message());
}

void Simulator::refuse(const std::string& what, const std::string& why) {
  ++rejected_;
  publishRejectedCount();
  // Throttled per topic/service on the wall clock: ROS_WARN_THROTTLE reads ros::Time, which
  // under use_sim_time stands still while paused (and is 0 before the first /clock), so it
  // would hide refusals exactly when a user is stepping by hand.
  Throttle& t = refusal_log_[what];
  const auto now = std::chrono::steady_clock::now();
  if (t.shown && now - t.last < kRefusalLogPeriod) {
    ++t.suppressed;
    return;
  }
  const std::string more =
      t.suppressed ? "; " + std::to_string(t.suppressed) + " more refused on it not shown" : "";
  ROS_WARN("simulator: refused %s: %s (%llu refused in all%s)", what.c_str(), why.c_str(),
           static_cast<unsigned long long>(rejected_), more.c_str());
  t = Throttle{true, now, 0};
}

void Simulator::onApplyWrench(const cga_rigid_sim::CgaWrench::ConstPtr& msg) {
  auto in = toWrenchInput(*msg, world_->config().world_frame, "apply_wrench");
  if (!in) return refuse("apply_wrench", in.error());
  auto ok = world_->applyWrench(*in);
  if (!ok) refuse("apply_wrench", refusalText(ok.failure(), "apply_wrench"));
}

void Simulator::onApplyImpulse(const cga_rigid_sim::CgaImpulse::ConstPtr& msg) {
  auto in = toImpulseInput(*msg, world_->config().world_frame, "apply_impulse");
  if (!in) return refuse("apply_impulse", in.error());
  auto ok = world_->applyImpulse(*in);
  if (!ok) refuse("apply_impulse", refusalText(ok.failure(), "apply_impulse"));
}

void Simulator::onWrench(const geometry_msgs::WrenchStamped::ConstPtr& msg) {
  auto in = toWrenchInput(*msg, world_->scene(), "wrench");
  if (!in) return refuse("wrench", in.error());
  auto ok = world_->applyWrench(*in);
  if (!ok) refuse("wrench", refusalText(ok.failure(), "wrench"));
}

void Simulator::onJointEfforts(const sensor_msgs::JointState::ConstPtr& msg) {
  // Refused as a whole (nothing applied), counted once, warned with the World's reason.
  auto ok = world_->setJointEfforts(toJointEffortInput(*msg));
  if (!ok) refuse("joint_efforts", refusalText(ok.failure(), "joint_efforts"));
}

}  // namespace node
}  // namespace cga_rigid_sim
