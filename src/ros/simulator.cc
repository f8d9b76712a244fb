#include "simulator.h"

#include <ros/callback_queue.h>
#include <rosgraph_msgs/Clock.h>
#include <std_msgs/UInt64.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <future>
#include <system_error>
#include <unordered_set>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/ros/conversions.h"

namespace cga_rigid_sim {
namespace node {
namespace {

// Queue sizes of the output publishers (per subscriber): large enough that a ~step burst
// reaches rosbag without drops, bounded so a slow subscriber cannot exhaust memory.
constexpr std::uint32_t kOutputQueueSize = 1000;
constexpr std::uint32_t kClockQueueSize = 1000;

// Steps between two shutdown checks inside a long ~step call.
constexpr std::uint64_t kShutdownCheckSteps = 1024;

::ros::WallDuration toWall(std::chrono::steady_clock::duration d) {
  return ::ros::WallDuration(std::chrono::duration<double>(d).count());
}

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
                     std::unique_ptr<sim::World> world)
    : nh_(nh),
      pnh_(pnh),
      params_(params),
      world_(std::move(world)),
      output_ticks_(world_->config().dt, params.publish_rate),
      clock_ticks_(world_->config().dt, params.clock_rate),
      pacer_(world_->config().dt, params.real_time_factor),
      has_joints_(!world_->scene().joints.empty()),
      paused_(params.paused) {
  // The configuration is said before anything is advertised: a client that sees a service up
  // has seen these lines too.
  const std::string clock = !params_.publish_clock ? "off"
                            : params_.clock_rate > 0.0
                                ? "at " + std::to_string(params_.clock_rate) + " Hz"
                                : "every step";
  ROS_INFO(
      "simulator: dt %g s; %d thread%s; real_time_factor %g%s; tf, momentum, body states, "
      "contacts%s at %g Hz; /clock %s%s",
      world_->config().dt, world_->config().threads, world_->config().threads == 1 ? "" : "s",
      params_.real_time_factor, params_.real_time_factor == 0.0 ? " (as fast as possible)" : "",
      has_joints_ ? " and /joint_states" : "", params_.publish_rate, clock.c_str(),
      paused_ ? "; paused (call ~unpause, or ~step)" : "");

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
  services_.push_back(pnh_.advertiseService("spawn_urdf", &Simulator::onSpawnUrdf, this));
  services_.push_back(pnh_.advertiseService("delete_body", &Simulator::onDeleteBody, this));
  services_.push_back(
      pnh_.advertiseService("apply_joint_effort", &Simulator::onApplyJointEffort, this));
}

// ---- main loop ----

int Simulator::run() {
  using Clock = RealTimePacer::Clock;
  ::ros::CallbackQueue& queue = *::ros::getGlobalCallbackQueue();

  publishRejectedCount();
  publishStaticFrames();
  publishClock();
  publishOutputs();

  const bool paced = params_.real_time_factor > 0.0;
  pacer_.restart(world_->stepCount(), Clock::now());
  Clock::time_point last_service = Clock::now();
  while (::ros::ok()) {
    if (paused_) {
      queue.callAvailable(toWall(kMaxWait));
      disturbed_ = true;  // time spent paused does not count against real time
      continue;
    }
    if (disturbed_) {
      disturbed_ = false;
      pacer_.restart(world_->stepCount(), Clock::now());
    }

    if (paced) {
      // Sleep until the step's deadline, servicing callbacks meanwhile.
      const Clock::time_point deadline = pacer_.deadline(world_->stepCount() + 1);
      bool interrupted = false;
      for (Clock::time_point now = Clock::now(); now < deadline; now = Clock::now()) {
        queue.callAvailable(toWall(std::min<Clock::duration>(deadline - now, kMaxWait)));
        last_service = Clock::now();
        if (paused_ || disturbed_ || !::ros::ok()) {
          interrupted = true;
          break;
        }
      }
      if (interrupted) continue;
    }
    // As fast as possible, or behind the deadlines: still service callbacks regularly.
    if (Clock::now() - last_service >= kServiceInterval) {
      queue.callAvailable(::ros::WallDuration(0));
      last_service = Clock::now();
      if (paused_ || disturbed_) continue;
    }

    world_->step();
    publishAfterStep();

    if (paced) {
      if (auto achieved = pacer_.onStep(world_->stepCount(), Clock::now())) {
        ROS_WARN(
            "simulator: cannot keep real_time_factor %g: achieved %.3g over the last %g s "
            "of wall time (set ~real_time_factor lower, or 0 for as fast as possible)",
            params_.real_time_factor, *achieved,
            std::chrono::duration<double>(RealTimePacer::kWindow).count());
      }
    }
  }
  ROS_INFO("simulator: shutting down at t = %.6f s after %llu steps", world_->time(),
           static_cast<unsigned long long>(world_->stepCount()));
  return 0;
}

void Simulator::advance(std::uint64_t n) {
  for (std::uint64_t i = 0; i < n; ++i) {
    if (i % kShutdownCheckSteps == kShutdownCheckSteps - 1 && !::ros::ok()) break;
    world_->step();
    publishAfterStep();
  }
}

void Simulator::publishAfterStep() {
  noteStartRefusals();
  noteTreeFaults();
  const std::uint64_t s = world_->stepCount();
  if (params_.publish_clock && clock_ticks_.isTick(s)) publishClock();
  if (output_ticks_.isTick(s)) publishOutputs();
}

// ---- publishing ----

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
  if (world_->config().threads > 1 && (want_tf || want_states)) {
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
  if (has_joints_ && joint_states_pub_.getNumSubscribers() > 0)
    joint_states_pub_.publish(toJointStateMsg(world_->jointStates(), stamp));
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
  const std::vector<sim::FramePose> frames = world_->staticFrames();
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

void Simulator::noteStartRefusals() {
  const std::uint64_t n = world_->startRefusalCount();
  if (n == start_refusals_seen_) return;
  const auto last = world_->lastStartRefusal();
  rejected_ += n - start_refusals_seen_ - 1;  // refuse() counts the last one
  start_refusals_seen_ = n;
  refuse(last->input + " (at its start)", last->message());
}

void Simulator::noteTreeFaults() {
  const std::uint64_t n = world_->treeFaultCount();
  if (n == tree_faults_seen_) return;
  const auto now = std::chrono::steady_clock::now();  // wall clock, as in refuse()
  if (fault_log_.shown && now - fault_log_.last < kRefusalLogPeriod) return;
  const std::uint64_t unseen = n - tree_faults_seen_;
  tree_faults_seen_ = n;
  fault_log_ = Throttle{true, now, 0};
  ROS_ERROR("simulator: %s (%llu such steps in all, %llu since the last report)",
            world_->lastTreeFault()->message().c_str(), static_cast<unsigned long long>(n),
            static_cast<unsigned long long>(unseen));
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

// ---- topics ----

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

// ---- services ----

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

bool Simulator::onSpawnUrdf(cga_rigid_sim::SpawnUrdf::Request& req,
                            cga_rigid_sim::SpawnUrdf::Response& res) {
  auto in = toPoseTwist(req.pose, req.twist, "spawn_urdf");
  auto ok = in ? world_->spawnUrdf(req.name, req.urdf, in->pose_root, in->linear_W, in->angular_W)
               : Result<bool>(in.failure());
  res.success = ok.ok();
  markDisturbed();
  if (!ok) {
    res.message = ok.error();
    refuse("spawn_urdf", ok.error());
    return true;
  }
  publishStaticFrames();
  publishNewMovingFrames();
  ROS_INFO("simulator: spawned '%s'", req.name.c_str());
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
  publishStaticFrames();
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
