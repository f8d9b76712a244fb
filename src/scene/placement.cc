#include "cga_rigid_sim/scene/placement.h"

#include "cga_rigid_sim/cga/bivelocity.h"

namespace cga_rigid_sim {
namespace scene {

dynamics::BodyState placedState(const cga::Motor& M_BL0, const Eigen::Quaterniond& R_WL0,
                                const Eigen::Vector3d& x_WL0, const Eigen::Vector3d& v_W,
                                const Eigen::Vector3d& w_W, double lambda) {
  const cga::Motor M_WL0 = cga::Motor::fromPose(R_WL0, x_WL0, lambda);
  dynamics::BodyState s;
  s.M_WB = (M_WL0 * M_BL0.reverse()).normalized();
  const Eigen::Quaterniond R_BW = s.M_WB.rotation().conjugate();
  s.omega_B = cga::Bivelocity::fromVelocities(R_BW * w_W, R_BW * v_W, lambda);
  return s;
}

dynamics::BodyState placedState(const cga::Motor& M_BL0, const Eigen::Isometry3d& pose_root,
                                const Eigen::Vector3d& v_W, const Eigen::Vector3d& w_W,
                                double lambda) {
  const Eigen::Quaterniond R_WL0(Eigen::Quaterniond(pose_root.linear()).normalized());
  return placedState(M_BL0, R_WL0, pose_root.translation(), v_W, w_W, lambda);
}

}  // namespace scene
}  // namespace cga_rigid_sim
