// Conversions between the algebra's value types and Eigen's geometry types.
// Motor ↔ Isometry3d/Quaterniond live on Motor itself (fromPose, toIsometry, rotation); this
// header gathers the free functions so call sites read like the math.
#pragma once

#include <Eigen/Geometry>

#include "cga_rigid_sim/cga/motor.h"

namespace cga_rigid_sim {
namespace cga {

inline Motor toMotor(const Eigen::Isometry3d& T, double lambda) {
  return Motor::fromIsometry(T, lambda);
}
inline Eigen::Isometry3d toIsometry(const Motor& M, double lambda) { return M.toIsometry(lambda); }
inline Eigen::Quaterniond toQuaternion(const Motor& M) { return M.rotation(); }
inline Motor toMotor(const Eigen::Quaterniond& R) { return Motor::rotor(R.normalized()); }

}  // namespace cga
}  // namespace cga_rigid_sim
