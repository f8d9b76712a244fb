// Roll, pitch, yaw as URDF and SDF define them (fixed axes): R = Rz(yaw) Ry(pitch) Rx(roll).
#pragma once

#include <Eigen/Geometry>

namespace cga_rigid_sim {
namespace math {

inline Eigen::Matrix3d rotationFromRpy(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace math
}  // namespace cga_rigid_sim
