// TreeWorkspace: the work arrays of the tree algorithms (articulated_body.h: ABA, the mass
// matrix, the momentum map, the mimic reduction), held by whoever calls them — a tree
// integrator, the World's Data — and reused from call to call, so that the algorithms allocate
// nothing once the arrays have grown to the tree. One workspace serves one call at a time (one
// thread); each algorithm has its own members, so one may call another with the same workspace.
#pragma once

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <vector>

#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/moment.h"
#include "cga_rigid_sim/math/cholesky.h"

namespace cga_rigid_sim {
namespace dynamics {

/// A composite rigid body in one body's frame, the CRBA's ten numbers: the inertia about the
/// frame's origin I_o (xx, yy, zz, xy, xz, yz), the first moment h = m c and the mass m.
struct CompositeInertia {
  double I[6];
  double h[3];
  double m;
};

struct TreeWorkspace {
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  using Vector6d = Eigen::Matrix<double, 6, 1>;

  /// forwardDynamics, ABA's passes: articulated inertias and bias moments, velocity-product
  /// terms, U = I_A s, the accelerations, D = sᵀ U and u per joint.
  struct Aba {
    std::vector<Matrix6d, Eigen::aligned_allocator<Matrix6d>> IA;
    std::vector<Vector6d, Eigen::aligned_allocator<Vector6d>> pA, c, U;
    std::vector<cga::Bivelocity> a;
    std::vector<double> D, u;
  } aba;
  /// forwardDynamics with mimic joints: ν̇ = G M_r⁻¹ Gᵀ (τ − b).
  struct Mimic {
    Eigen::VectorXd zero, Q, Q_r;
    Eigen::MatrixXd M, M_r;
    math::Cholesky llt;
  } mimic;
  /// massMatrix: the composite inertias, each in its own body's frame.
  std::vector<CompositeInertia> composites;
  /// momentumAndGradient: per body, the subtree's momentum H and external moments F.
  std::vector<cga::Moment> subtree_momentum, subtree_moments;
  /// reduceMatrix: Gᵀ M.
  Eigen::MatrixXd reduce_rows;
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
