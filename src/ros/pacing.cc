#include "pacing.h"

#include <cmath>

namespace cga_rigid_sim {
namespace node {

TickSchedule::TickSchedule(double dt, double rate) {
  ticks_per_step_ = rate * dt;
  if (!(rate > 0.0) || ticks_per_step_ >= 1.0) {
    every_ = 1;
    return;
  }
  // Exact grid when 1/(rate·dt) is an integer up to round-off of the division (1e-9 relative:
  // far above ε, far below any meaningful difference of rates).
  const double steps_per_tick = 1.0 / ticks_per_step_;
  const double n = std::round(steps_per_tick);
  every_ = std::abs(steps_per_tick - n) <= 1e-9 * n ? static_cast<std::uint64_t>(n) : 0;
}

std::uint64_t TickSchedule::tickOf(std::uint64_t s) const {
  if (every_ > 0) return s / every_;
  // Not an integer grid: floor(s·rate·dt), nudged by 1e-9 so a tick time that is a step time
  // up to round-off counts as reached.
  return static_cast<std::uint64_t>(std::floor(static_cast<double>(s) * ticks_per_step_ + 1e-9));
}

void RealTimePacer::restart(std::uint64_t step, Clock::time_point now) {
  anchor_time_ = window_time_ = now;
  anchor_step_ = window_step_ = step;
}

RealTimePacer::Clock::time_point RealTimePacer::deadline(std::uint64_t step_after) const {
  const double wall_s = static_cast<double>(step_after - anchor_step_) * dt_ / factor_;
  return anchor_time_ +
         std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wall_s));
}

std::optional<double> RealTimePacer::onStep(std::uint64_t step_after, Clock::time_point now) {
  // Far behind: drop the backlog rather than run a burst of steps faster than real time.
  if (now - deadline(step_after) > kMaxLag) {
    anchor_time_ = now;
    anchor_step_ = step_after;
  }
  const auto elapsed = now - window_time_;
  if (elapsed < kWindow) return std::nullopt;
  const double achieved = static_cast<double>(step_after - window_step_) * dt_ /
                          std::chrono::duration<double>(elapsed).count();
  window_time_ = now;
  window_step_ = step_after;
  if (!warned_ && achieved < kShortfall * factor_) {
    warned_ = true;
    return achieved;
  }
  return std::nullopt;
}

}  // namespace node
}  // namespace cga_rigid_sim
