// The loads on a tree's bodies and the response to an impulse (tree_integrator.h); the tree
// integrators by name are in integrator_registry.cc, with the free-body ones.
#include <Eigen/Cholesky>

#include "cga_rigid_sim/tree/tree_integrator.h"
#include "tree/tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

void externalMoments(const ArticulatedBody& tree, const TreeKinematics& kin, const TreeLoads& loads,
                     BodyMoments& out) {
  gravityMoments(tree, kin, loads.gravity_W, out);
  for (int b = 0; b < tree.bodyCount() && b < static_cast<int>(loads.applied.size()); ++b)
    if (loads.applied[b] && (b > 0 || tree.floating()))
      out[b] += loads.applied[b]->appliedMoment_B(kin.M_W[b], tree.lambda());
}

Eigen::VectorXd impulseResponse(const ArticulatedBody& tree, const TreeState& state, int body,
                                const cga::Moment& T_b) {
  TreeState still = state;
  setVelocityVector(tree, Eigen::VectorXd::Zero(tree.velocityCount()), still);
  TreeKinematics kin;
  treeKinematics(tree, still, kin);
  BodyMoments f(tree.bodyCount());
  f[body] = T_b;
  // RNEA at rest with no acceleration returns −Jᵀ T: the generalized impulse, negated.
  const Eigen::VectorXd g =
      -inverseDynamics(tree, still, kin, Eigen::VectorXd::Zero(tree.velocityCount()), f);
  Eigen::MatrixXd M, M_r;
  massMatrix(tree, kin, M);
  // With mimic joints the impulse moves the tree within ν = G ν_r: Δν = G M_r⁻¹ Gᵀ g.
  Eigen::VectorXd g_r, dnu;
  reduceForce(tree, g, g_r);
  reduceMatrix(tree, M, M_r);
  expandVelocity(tree, M_r.llt().solve(g_r), dnu);
  return dnu;
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
