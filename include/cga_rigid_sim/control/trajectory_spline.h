// Splines through a trajectory's points, per joint, as joint_trajectory_controller builds them
// (doc/control.md#splines): each segment's polynomial is chosen by what its two ends give —
// positions only → linear, positions and velocities → cubic (Hermite), positions, velocities and
// accelerations → quintic. Before the start the start position is held, after the last point
// its position, both with zero velocity and acceleration.
#pragma once

#include <array>
#include <vector>

#include "cga_rigid_sim/control/joint_trajectory.h"

namespace cga_rigid_sim {
namespace control {

/// A joint's position, velocity and acceleration at one instant.
struct JointSample {
  double position = 0;
  double velocity = 0;
  double acceleration = 0;
};

/// One end of a segment: its time (absolute, s) and what it gives.
struct SplineKnot {
  double time = 0;
  double position = 0;
  double velocity = 0;      ///< read only when has_velocity
  double acceleration = 0;  ///< read only when has_acceleration
  bool has_velocity = false;
  bool has_acceleration = false;
};

/// What a segment interpolates: set by the less informative of its two ends.
enum class SegmentKind { kLinear, kCubic, kQuintic };

/// q(t) = Σ c[k] (t − begin)^k on [begin, begin + duration].
struct SplineSegment {
  double begin = 0;
  double duration = 0;
  SegmentKind kind = SegmentKind::kLinear;
  std::array<double, 6> c{};

  /// The segment from `a` to `b` (b.time ≥ a.time): linear unless both ends give velocities,
  /// cubic unless both also give accelerations, else quintic. A zero duration gives b's state.
  static SplineSegment between(const SplineKnot& a, const SplineKnot& b);
  /// The polynomial and its two derivatives at t (not clamped to the segment).
  JointSample at(double t) const;
  double end() const { return begin + duration; }
};

/// One joint's spline: a start knot and segments through the following knots.
class JointSpline {
 public:
  /// Holds `position` (velocity and acceleration 0) at every time.
  static JointSpline hold(double time, double position);
  /// From `start` through `knots` (times strictly increasing and > start.time, except that the
  /// first may equal start.time: the desired state then jumps to it).
  static JointSpline through(const SplineKnot& start, const std::vector<SplineKnot>& knots);
  /// `current` until t_b, then from current's state at t_b (position, velocity, acceleration)
  /// through `knots` (times ≥ t_b, strictly increasing). Segments of `current` that ended
  /// before `now` (≤ t_b) are dropped: the result is only meant to be sampled from `now` on.
  static JointSpline splice(const JointSpline& current, double now, double t_b,
                            const std::vector<SplineKnot>& knots);

  /// The desired state at t: before the start the start position, after the end the last
  /// position, both at rest (joint_trajectory_controller's sampling).
  JointSample sample(double t) const;
  double startTime() const { return start_.time; }
  /// The time of the last knot (= startTime() for a hold).
  double endTime() const { return segments_.empty() ? start_.time : segments_.back().end(); }
  const std::vector<SplineSegment>& segments() const { return segments_; }

 private:
  SplineKnot start_;
  std::vector<SplineSegment> segments_;
};

/// The knots of a trajectory's points for joint `j` (the points' column j) at absolute times
/// start_time + time_from_start.
std::vector<SplineKnot> knotsOfJoint(const std::vector<TrajectoryPoint>& points, double start_time,
                                     std::size_t j);

/// One spline per joint of a trajectory, started from each joint's state at t0.
struct TrajectorySpline {
  std::vector<JointSpline> joints;

  /// Splines from `start` (one JointSample per joint, at time t0, all of position, velocity and
  /// acceleration given) through `points` (values in the order of `start`, at absolute times
  /// start_time + time_from_start, all ≥ t0).
  static TrajectorySpline build(double t0, const std::vector<JointSample>& start,
                                const std::vector<TrajectoryPoint>& points, double start_time);
  /// Samples every joint at t into `out` (resized to the joints).
  void sample(double t, std::vector<JointSample>& out) const;
  /// The latest end time of the joints.
  double endTime() const;
};

}  // namespace control
}  // namespace cga_rigid_sim
