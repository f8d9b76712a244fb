// A shared benchmark case (bench/cases/cases.h) as the dynamics layer sees it: one Inertia, one
// BodyState, one Loads — and the way back to the engine-independent state the error metrics
// read (bench/cases/reference_solution.h).
//
// Frames. The case gives its moments along the axes of a case body frame F, and at t = 0 F is
// the world frame (q = identity, CoM at the origin). Inertia::fromPrincipal sorts the moments
// (asymmetric: J1 < J2 < J3; symmetric: distinct axis on e3), so its reference body B may be F
// with the axes permuted: x_F = R_FB x_B. Then
//   M_WB(0) = R_WF(0) R_FB = R_FB,      w_B = R_FBᵀ w_F,      v_B = R_WB(0)ᵀ v_W,
// and at the end q_WF = q_WB q_FB⁻¹. For a diagonal tensor R_FB is a signed permutation whose
// quaternion has entries 0, ±½, ±1/√2 or ±1; the vectors are turned with its rotation matrix,
// whose entries are exactly 0 and ±1 for the cyclic permutations the cases need, so the initial
// conditions reach the integrator unrounded.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cases.h"
#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/body/loads.h"
#include "reference_solution.h"

namespace cga_rigid_sim {
namespace benchmark {

struct CaseSetup {
  dynamics::Inertia inertia;
  dynamics::Loads loads;       ///< gravity; for a world torque, a world-axes couple
  dynamics::BodyState state0;  ///< at t = 0
  Eigen::Quaterniond R_FB;     ///< case body frame F ← principal frame B
  double lambda = 1.0;         ///< CGA length scale, m
};

/// The dynamics-layer problem of a case, with CGA length scale `lambda`. Aborts (with a message)
/// if the case's inertia is refused: the shared cases are valid by construction.
CaseSetup setupCase(const ::bench::Case& c, double lambda = 1.0);

/// The state in the form of the shared metrics: q_WF (Hamilton w, x, y, z), world angular
/// velocity, CoM position and velocity.
::bench::BodyState toCaseState(const CaseSetup& setup, const dynamics::BodyState& s);

/// The peers' blow-up rule (bench/peers/peer_common.cc): a non-finite number, or an angular
/// speed above 10⁶ times the initial one.
bool blownUp(const ::bench::Case& c, const ::bench::BodyState& s);

}  // namespace benchmark
}  // namespace cga_rigid_sim
