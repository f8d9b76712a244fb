// Pacing of the simulator node: which steps publish (TickSchedule, simulation time) and when a
// step may run (RealTimePacer, wall time). Neither touches the simulation.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

namespace cga_rigid_sim {
namespace node {

/// Ticks at `rate` Hz of simulation time on a grid of steps of `dt`: step s is due when it is
/// the first step at or after a tick time k/rate. When 1/(rate·dt) is an integer N (the usual
/// case: dt = 1 ms, 100 Hz → N = 10) the ticks are exactly the multiples of N steps, decided
/// in integers so they never slip over long runs. A rate ≥ 1/dt (or ≤ 0) ticks every step.
class TickSchedule {
 public:
  TickSchedule(double dt, double rate);
  /// The tick index of step s (steps are done: s = stepCount after the step).
  std::uint64_t tickOf(std::uint64_t s) const;
  /// True when step s starts a new tick (its tick index differs from step s − 1's); step 0 is
  /// always a tick.
  bool isTick(std::uint64_t s) const { return s == 0 || tickOf(s) != tickOf(s - 1); }

 private:
  std::uint64_t every_ = 1;  ///< N steps per tick when exact, 0 when not
  double ticks_per_step_ = 1.0;
};

/// Keeps simulation time at `factor` × wall time with absolute deadlines on a steady clock:
/// step s (counted from the anchor) is due at anchor + s·dt/factor, so sleeping never adds up
/// to drift. When the node falls behind by more than kMaxLag (a slow step, a long service
/// call) it re-anchors instead of racing to catch up. Every kWindow of wall time it compares
/// the achieved factor with the requested one and reports the first shortfall (the node warns
/// once).
class RealTimePacer {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::milliseconds kMaxLag{100};
  static constexpr std::chrono::seconds kWindow{2};
  /// Achieved below this fraction of the requested factor counts as "cannot keep pace".
  static constexpr double kShortfall = 0.9;

  RealTimePacer(double dt, double factor) : dt_(dt), factor_(factor) {}

  /// Anchors at step count `step` now (after a pause, a service call, …); restarts the window.
  void restart(std::uint64_t step, Clock::time_point now);
  /// When the step that brings the count to `step_after` may run.
  Clock::time_point deadline(std::uint64_t step_after) const;
  /// After a step (count now `step_after`, done at `now`): re-anchors when far behind. Returns
  /// the achieved factor the first time a full window falls short, else nothing.
  std::optional<double> onStep(std::uint64_t step_after, Clock::time_point now);

 private:
  double dt_;
  double factor_;
  Clock::time_point anchor_time_{};
  std::uint64_t anchor_step_ = 0;
  Clock::time_point window_time_{};
  std::uint64_t window_step_ = 0;
  bool warned_ = false;
};

}  // namespace node
}  // namespace cga_rigid_sim
