// Placing a body: the state of a body whose root link L0 is put at a given pose, with given
// velocities of its centre of mass and angular velocity (world axes). Used for initial states,
// set_body_state and spawn_urdf alike.
//
// The root link's frame sits at the constant M_BL0 in the body frame B (its LinkFrame), so
//   M_WB = M_WL0 M_BL0⁻¹,   Ω_B = (R̃ w, R̃ v/λ)   (R the rotation of M_WB; doc/conventions.md (E6)).
// M_WB is returned as a unit motor (normalised: the product of two unit motors is one only to
// round-off).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/cga/motor.h"

namespace cga_rigid_sim {
namespace scene {

/// The root link at (R_WL0, x_WL0): R_WL0 a unit quaternion (taken as it is), x_WL0 in m;
/// v_W the centre of mass's velocity and w_W the angular velocity, world axes.
dynamics::BodyState placedState(const cga::Motor& M_BL0, const Eigen::Quaterniond& R_WL0,
                                const Eigen::Vector3d& x_WL0, const Eigen::Vector3d& v_W,
                                const Eigen::Vector3d& w_W, double lambda);

/// The root link at pose_root, whose rotation (a proper rotation matrix within
/// rotationMatrixRule, rotation_rule.h) is taken as the normalised quaternion of
/// pose_root.linear().
dynamics::BodyState placedState(const cga::Motor& M_BL0, const Eigen::Isometry3d& pose_root,
                                const Eigen::Vector3d& v_W, const Eigen::Vector3d& w_W,
                                double lambda);

}  // namespace scene
}  // namespace cga_rigid_sim
