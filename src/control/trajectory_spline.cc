// Spline segments through trajectory points (trajectory_spline.h; doc/control.md#splines).
#include "cga_rigid_sim/control/trajectory_spline.h"

#include <algorithm>

namespace cga_rigid_sim {
namespace control {

SplineSegment SplineSegment::between(const SplineKnot& a, const SplineKnot& b) {
  SplineSegment s;
  s.begin = a.time;
  s.duration = b.time - a.time;
  const double T = s.duration;
  auto& c = s.c;
  if (!(T > 0)) {  // a jump to b: its state, held over no time
    c[0] = b.position;
    c[1] = b.has_velocity ? b.velocity : 0.0;
    c[2] = b.has_acceleration ? 0.5 * b.acceleration : 0.0;
    return s;
  }
  const double d = b.position - a.position;
  const bool velocities = a.has_velocity && b.has_velocity;
  const bool accelerations = velocities && a.has_acceleration && b.has_acceleration;
  c[0] = a.position;
  if (!velocities) {
    // Linear: q(0) = a, q(T) = b.
    s.kind = SegmentKind::kLinear;
    c[1] = d / T;
  } else if (!accelerations) {
    // Cubic Hermite: q, q̇ given at both ends; the two conditions at T solved for c2, c3.
    s.kind = SegmentKind::kCubic;
    const double v0 = a.velocity, v1 = b.velocity;
    c[1] = v0;
    c[2] = (3 * d - (2 * v0 + v1) * T) / (T * T);
    c[3] = (-2 * d + (v0 + v1) * T) / (T * T * T);
  } else {
    // Quintic: q, q̇, q̈ at both ends; c0..c2 from the start, c3..c5 from the three conditions
    // at T (the 3×3 system solved in closed form).
    s.kind = SegmentKind::kQuintic;
    const double v0 = a.velocity, v1 = b.velocity;
    const double a0 = a.acceleration, a1 = b.acceleration;
    const double T2 = T * T, T3 = T2 * T;
    c[1] = v0;
    c[2] = 0.5 * a0;
    c[3] = (20 * d - (8 * v1 + 12 * v0) * T - (3 * a0 - a1) * T2) / (2 * T3);
    c[4] = (-30 * d + (14 * v1 + 16 * v0) * T + (3 * a0 - 2 * a1) * T2) / (2 * T3 * T);
    c[5] = (12 * d - 6 * (v1 + v0) * T + (a1 - a0) * T2) / (2 * T3 * T2);
  }
  return s;
}

JointSample SplineSegment::at(double t) const {
  const double x = t - begin;
  // Horner for q, q̇, q̈.
  double q = c[5], qd = 5 * c[5], qdd = 20 * c[5];
  q = q * x + c[4];
  qd = qd * x + 4 * c[4];
  qdd = qdd * x + 12 * c[4];
  q = q * x + c[3];
  qd = qd * x + 3 * c[3];
  qdd = qdd * x + 6 * c[3];
  q = q * x + c[2];
  qd = qd * x + 2 * c[2];
  qdd = qdd * x + 2 * c[2];
  q = q * x + c[1];
  qd = qd * x + c[1];
  q = q * x + c[0];
  return {q, qd, qdd};
}

JointSpline JointSpline::hold(double time, double position) {
  JointSpline s;
  s.start_.time = time;
  s.start_.position = position;
  s.start_.has_velocity = s.start_.has_acceleration = true;
  return s;
}

JointSpline JointSpline::through(const SplineKnot& start, const std::vector<SplineKnot>& knots) {
  JointSpline s;
  s.start_ = start;
  s.segments_.reserve(knots.size());
  const SplineKnot* previous = &start;
  for (const SplineKnot& k : knots) {
    s.segments_.push_back(SplineSegment::between(*previous, k));
    previous = &k;
  }
  return s;
}

JointSpline JointSpline::splice(const JointSpline& current, double now, double t_b,
                                const std::vector<SplineKnot>& knots) {
  JointSpline s;
  // The part of `current` still to run before t_b: its segments that end after `now` and begin
  // before t_b, the last one cut at t_b.
  for (const SplineSegment& seg : current.segments_) {
    if (seg.end() < now || !(seg.begin < t_b)) continue;
    s.segments_.push_back(seg);
    s.segments_.back().duration = std::min(seg.end(), t_b) - seg.begin;
  }
  const JointSample at_b = current.sample(t_b);
  SplineKnot bridge;
  bridge.time = t_b;
  bridge.position = at_b.position;
  bridge.velocity = at_b.velocity;
  bridge.acceleration = at_b.acceleration;
  bridge.has_velocity = bridge.has_acceleration = true;
  if (s.segments_.empty()) {
    // Nothing of `current` runs in [now, t_b) but its held position: a constant until t_b.
    s.start_ = bridge;
    s.start_.time = std::min(now, t_b);
    s.start_.velocity = s.start_.acceleration = 0;
    s.segments_.push_back(SplineSegment::between(s.start_, bridge));
  } else {
    const SplineSegment& first = s.segments_.front();
    const JointSample q0 = first.at(first.begin);
    s.start_.time = first.begin;
    s.start_.position = q0.position;
    s.start_.velocity = q0.velocity;
    s.start_.acceleration = q0.acceleration;
    s.start_.has_velocity = s.start_.has_acceleration = true;
    if (s.segments_.back().end() < t_b) {  // `current` ended before t_b: its end held until then
      SplineKnot held = bridge;
      held.time = s.segments_.back().end();
      held.velocity = held.acceleration = 0;
      s.segments_.push_back(SplineSegment::between(held, bridge));
    }
  }
  const SplineKnot* previous = &bridge;
  for (const SplineKnot& k : knots) {
    s.segments_.push_back(SplineSegment::between(*previous, k));
    previous = &k;
  }
  return s;
}

JointSample JointSpline::sample(double t) const {
  if (segments_.empty() || t < start_.time) return {start_.position, 0.0, 0.0};
  const SplineSegment& last = segments_.back();
  if (t > last.end()) return {last.at(last.end()).position, 0.0, 0.0};
  // The first segment whose end is ≥ t (a knot's time belongs to the segment it ends).
  const auto it = std::lower_bound(segments_.begin(), segments_.end(), t,
                                   [](const SplineSegment& s, double x) { return s.end() < x; });
  return it->at(t);
}

std::vector<SplineKnot> knotsOfJoint(const std::vector<TrajectoryPoint>& points, double start_time,
                                     std::size_t j) {
  std::vector<SplineKnot> knots(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const TrajectoryPoint& p = points[k];
    SplineKnot& knot = knots[k];
    knot.time = start_time + p.time_from_start;
    knot.position = p.positions[j];
    knot.has_velocity = !p.velocities.empty();
    knot.velocity = knot.has_velocity ? p.velocities[j] : 0.0;
    knot.has_acceleration = !p.accelerations.empty();
    knot.acceleration = knot.has_acceleration ? p.accelerations[j] : 0.0;
  }
  return knots;
}

TrajectorySpline TrajectorySpline::build(double t0, const std::vector<JointSample>& start,
                                         const std::vector<TrajectoryPoint>& points,
                                         double start_time) {
  TrajectorySpline spline;
  spline.joints.reserve(start.size());
  for (std::size_t j = 0; j < start.size(); ++j) {
    SplineKnot s;
    s.time = t0;
    s.position = start[j].position;
    s.velocity = start[j].velocity;
    s.acceleration = start[j].acceleration;
    s.has_velocity = s.has_acceleration = true;
    spline.joints.push_back(JointSpline::through(s, knotsOfJoint(points, start_time, j)));
  }
  return spline;
}

void TrajectorySpline::sample(double t, std::vector<JointSample>& out) const {
  out.resize(joints.size());
  for (std::size_t j = 0; j < joints.size(); ++j) out[j] = joints[j].sample(t);
}

double TrajectorySpline::endTime() const {
  double end = joints.empty() ? 0.0 : joints.front().endTime();
  for (const JointSpline& j : joints) end = std::max(end, j.endTime());
  return end;
}

}  // namespace control
}  // namespace cga_rigid_sim
