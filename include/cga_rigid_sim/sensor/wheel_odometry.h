// Wheel odometry of a differential (or skid-steer) drive (doc/sensors.md#drives): dead reckoning
// of the base's planar pose from how far its left and right wheels rolled, as
// gazebo_ros_diff_drive's encoder odometry does — which drifts from the truth when the wheels
// slip, as it should.
#pragma once

#include <cmath>

namespace cga_rigid_sim {
namespace sensor {

/// The base's pose in the odometry frame: position (m) and heading (rad) in the plane.
struct PlanarPose {
  double x = 0.0, y = 0.0, theta = 0.0;
};

/// One interval of dead reckoning: the left and right wheels' contact points rolled s_l and s_r
/// (m, wheel angle × radius), the wheels `separation` (m) apart. The base moves along an arc of
/// length s = (s_l + s_r)/2 turning by Δθ = (s_r − s_l)/separation: the chord of that arc,
/// 2 (s/Δθ) sin(Δθ/2), at the mid heading θ + Δθ/2 — exact for wheel speeds constant over the
/// interval (the unicycle's circle), where Gazebo's plugin takes the arc's length for the
/// chord's (an O(Δθ²) relative error per interval).
inline PlanarPose integrateWheels(const PlanarPose& pose, double s_l, double s_r,
                                  double separation) {
  const double s = 0.5 * (s_l + s_r);
  const double dtheta = (s_r - s_l) / separation;
  // chord / arc = sin(Δθ/2) / (Δθ/2); its Taylor series 1 − x²/6 below |x| = 1e-4, where the
  // next term x⁴/120 is below 1e-18 (under the rounding of 1).
  const double half = 0.5 * dtheta;
  const double ratio = std::abs(half) < 1e-4 ? 1.0 - half * half / 6.0 : std::sin(half) / half;
  const double heading = pose.theta + half;
  PlanarPose next;
  next.x = pose.x + s * ratio * std::cos(heading);
  next.y = pose.y + s * ratio * std::sin(heading);
  next.theta = pose.theta + dtheta;
  return next;
}

}  // namespace sensor
}  // namespace cga_rigid_sim
