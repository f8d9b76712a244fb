// What an IMU fixed to a rigid body measures (doc/sensors.md#imu): the specific force (the
// acceleration of its point minus gravity) and the angular velocity, both in the sensor's axes,
// and its orientation in the world. At rest it reads +g up; in free fall, 0.
//
// The acceleration of the sensor's point S on body B (centre of mass at B's origin, r = the
// point in B's axes) is a_S = a_c + α × r + ω × (ω × r) (body axes). Over the step of length h
// that ends at the sample, the centre's acceleration is taken as the mean (v_c(t) − v_c(t − h))/h
// in world axes — it holds the contact impulses of the step, which act over it — and
// α = (ω_B(t) − ω_B(t − h))/h (the body-axes derivative of ω equals the world one rotated, as
// ω × ω = 0). Exact, to rounding, for a body at rest, in free fall, and spinning steadily about a
// principal axis (α = 0, the centripetal term ω × (ω × r) evaluated at t); otherwise the mean of
// the step, as a real IMU's sample averages its interval.
#pragma once

#include <Eigen/Geometry>

#include "cga_rigid_sim/body/body_state.h"

namespace cga_rigid_sim {
namespace sensor {

struct ImuSample {
  Eigen::Quaterniond orientation_WS = Eigen::Quaterniond::Identity();  ///< S in the world
  Eigen::Vector3d angular_velocity_S = Eigen::Vector3d::Zero();        ///< rad/s, S axes
  Eigen::Vector3d linear_acceleration_S = Eigen::Vector3d::Zero();     ///< m/s², specific force
};

/// The IMU at X_BS on a body whose state was `before` one step of `h` seconds ago and is `now`;
/// g_W the gravity, lambda the CGA length scale.
ImuSample imuSample(const dynamics::BodyState& before, const dynamics::BodyState& now, double h,
                    const Eigen::Isometry3d& X_BS, const Eigen::Vector3d& g_W, double lambda);

}  // namespace sensor
}  // namespace cga_rigid_sim
