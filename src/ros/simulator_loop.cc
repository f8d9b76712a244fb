// The node's main loop (simulator.h): steps the World, paced to real time or as fast as
// possible, services the callback queue between steps, and publishes at the output ticks
// (doc/node.md).
#include <ros/callback_queue.h>

#include <algorithm>
#include <chrono>

#include "simulator.h"

namespace cga_rigid_sim {
namespace node {
namespace {

// Steps between two shutdown checks inside a long ~step call.
constexpr std::uint64_t kShutdownCheckSteps = 1024;

::ros::WallDuration toWall(std::chrono::steady_clock::duration d) {
  return ::ros::WallDuration(std::chrono::duration<double>(d).count());
}

}  // namespace

int Simulator::run() {
  using Clock = RealTimePacer::Clock;
  ::ros::CallbackQueue& queue = *::ros::getGlobalCallbackQueue();

  publishRejectedCount();
  publishStaticFrames();
  publishClock();
  publishOutputs();
  publishJointStates();
  publishControllerStates(/*always=*/true);

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
  if (joint_state_ticks_ && joint_state_ticks_->isTick(s)) publishJointStates();
  publishControllerStates();
  publishSensors();
  publishDrives();
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

}  // namespace node
}  // namespace cga_rigid_sim
