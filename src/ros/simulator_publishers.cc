// The node's outputs (simulator.h): tf, momentum, body states, contacts, joint states and
// markers at each output tick, /clock, the latched /tf_static and the count of refused inputs
// (doc/node.md).
#include <rosgraph_msgs/Clock.h>
#include <std_msgs/UInt64.h>
#include <tf2_msgs/TFMessage.h>

#include <future>
#include <system_error>
#include <unordered_set>

#include "cga_rigid_sim/ros/conversions.h"
#include "simulator.h"

namespace cga_rigid_sim {
namespace node {
namespace {

// Fewer frames than this are filled and sent on the main thread even with ~threads > 1: a
// thread started per tick, and the main thread waiting for it while the subscribers' processes
// hold the other cores, costs more than filling a few hundred transforms (doc/node.md).
constexpr std::size_t kFramesWorthAThread = 500;

}  // namespace

void Simulator::publishOutputs() {
  const std::uint64_t s = world_->stepCount();
  if (s == last_tf_step_) return;
  const ::ros::Time stamp = toRosTime(world_->time());
  const std::string& world_frame = world_->config().world_frame;
  const std::uint64_t topology = world_->topologyVersion();
  last_tf_step_ = s;
  late_tf_children_.clear();

  // Messages nobody subscribes to are not even built (10 000 bodies make megabytes per tick).
  // Those of many bodies are overwritten in place (names only when the bodies changed) and
  // published by pointer: serialised once for all subscribers, never copied.
  const bool want_tf = tf_pub_.getNumSubscribers() > 0;
  const bool want_states = body_states_pub_.getNumSubscribers() > 0;
  // The body states hold every moving root link's pose: with both wanted, one read serves tf.
  std::vector<sim::BodyStateReport> states;
  std::vector<sim::FramePose> frames;
  if (want_states)
    states = world_->bodyStates();
  else if (want_tf)
    frames = world_->movingFrames();
  tf_msg_sent_ = want_tf;
  // tf and the body states need nothing more from the World (which is read on this thread
  // only): with a second core (~threads > 1) a helper fills and sends them while this thread
  // reads and sends the momentum; it is joined before returning.
  auto send_tf_and_states = [&] {
    if (want_tf) {
      const bool names = tf_msg_.namesChangedFor(topology);
      if (want_states)
        fillTfMessage(states, world_frame, stamp, names, &tf_msg_.writable());
      else
        fillTfMessage(frames, stamp, names, &tf_msg_.writable());
      if (!tf_msg_.ptr()->transforms.empty()) tf_pub_.publish(tf_msg_.ptr());
    }
    if (want_states) {
      const bool names = body_states_msg_.namesChangedFor(topology);
      fillBodyStateArrayMsg(states, stamp, world_frame, names, &body_states_msg_.writable());
      body_states_pub_.publish(body_states_msg_.ptr());
    }
  };
  std::future<void> helper;
  const std::size_t frames_sent = want_states ? states.size() : frames.size();
  if (world_->config().threads > 1 && frames_sent >= kFramesWorthAThread) {
    try {
      helper = std::async(std::launch::async, send_tf_and_states);
    } catch (const std::system_error&) {  // no thread to be had: done here instead
      send_tf_and_states();
    }
  } else {
    send_tf_and_states();
  }
  if (momentum_pub_.getNumSubscribers() > 0) {
    const bool names = momentum_msg_.namesChangedFor(topology);
    fillMomentumArrayMsg(world_->momentum(), stamp, world_frame, names, &momentum_msg_.writable());
    momentum_pub_.publish(momentum_msg_.ptr());
  }
  if (world_->config().curvature && curved_momentum_pub_.getNumSubscribers() > 0)
    curved_momentum_pub_.publish(toCurvedMomentumArrayMsg(
        world_->curvedMomentum(), *world_->config().curvature, stamp, world_frame));
  if (helper.valid()) helper.get();
  if (contacts_pub_.getNumSubscribers() > 0)
    contacts_pub_.publish(toContactArrayMsg(world_->contacts(), stamp, world_frame));
  if (!joint_state_ticks_) publishJointStates();  // else at the joint state controller's rate
  if (markers_pub_.getNumSubscribers() > 0)
    markers_pub_.publish(markersOf(*world_, params_.markers, &marker_refs_, stamp));
}

void Simulator::publishClock() {
  if (!params_.publish_clock) return;
  const std::uint64_t s = world_->stepCount();
  if (s == last_clock_step_) return;
  rosgraph_msgs::Clock msg;
  msg.clock = toRosTime(world_->time());
  clock_pub_.publish(msg);
  last_clock_step_ = s;
}

void Simulator::publishStaticFrames() {
  const std::uint64_t version = world_->topologyVersion();
  if (version == static_version_) return;
  std::vector<sim::FramePose> frames = world_->staticFrames();
  for (sim::FramePose& anchor : odometryAnchors()) frames.push_back(std::move(anchor));
  // Latched: the one message a late subscriber gets must hold every static frame. A scene
  // without static frames sends nothing at start, but an empty message after a delete.
  if (!frames.empty() || static_version_ != UINT64_MAX)
    tf_static_pub_.publish(toTfMessage(frames, toRosTime(world_->time())));
  static_version_ = version;
}

void Simulator::publishNewMovingFrames() {
  if (last_tf_step_ != world_->stepCount()) return;  // the next tick sends every frame
  // The children already sent at this stamp, gathered here (after a spawn, rarely) rather than
  // kept in a set at every tick.
  std::unordered_set<std::string> sent(late_tf_children_.begin(), late_tf_children_.end());
  if (tf_msg_sent_)
    for (const auto& t : tf_msg_.ptr()->transforms) sent.insert(t.child_frame_id);
  std::vector<sim::FramePose> fresh;
  for (const auto& f : world_->movingFrames()) {
    if (!sent.insert(f.child).second) continue;
    late_tf_children_.push_back(f.child);
    fresh.push_back(f);
  }
  if (!fresh.empty()) tf_pub_.publish(toTfMessage(fresh, toRosTime(world_->time())));
}

void Simulator::publishRejectedCount() {
  std_msgs::UInt64 msg;
  msg.data = rejected_;
  rejected_pub_.publish(msg);
}

}  // namespace node
}  // namespace cga_rigid_sim
