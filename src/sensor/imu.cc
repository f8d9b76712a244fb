// The IMU's reading from two body states one step apart (imu.h, doc/sensors.md#imu).
#include "cga_rigid_sim/sensor/imu.h"

#include "cga_rigid_sim/body/derived.h"

namespace cga_rigid_sim {
namespace sensor {

ImuSample imuSample(const dynamics::BodyState& before, const dynamics::BodyState& now, double h,
                    const Eigen::Isometry3d& X_BS, const Eigen::Vector3d& g_W, double lambda) {
  const Eigen::Quaterniond q_WB = now.M_WB.rotation();
  const Eigen::Matrix3d R_WB = q_WB.toRotationMatrix();
  const Eigen::Vector3d& w_B = now.omega_B.angular();
  const Eigen::Vector3d& r_B = X_BS.translation();
  // The centre's mean acceleration over the step (world), less gravity, in body axes.
  const Eigen::Vector3d a_c_W =
      (dynamics::comVelocity_W(now, lambda) - dynamics::comVelocity_W(before, lambda)) / h;
  const Eigen::Vector3d alpha_B = (w_B - before.omega_B.angular()) / h;
  const Eigen::Vector3d f_B =
      R_WB.transpose() * (a_c_W - g_W) + alpha_B.cross(r_B) + w_B.cross(w_B.cross(r_B));
  const Eigen::Matrix3d R_SB = X_BS.linear().transpose();
  ImuSample s;
  s.orientation_WS = (q_WB * Eigen::Quaterniond(X_BS.linear())).normalized();
  s.angular_velocity_S = R_SB * w_B;
  s.linear_acceleration_S = R_SB * f_B;
  return s;
}

}  // namespace sensor
}  // namespace cga_rigid_sim
