// Small fixtures shared by the tree tests (test/tree/tree_integrator_test.cc, mimic_test.cc):
// a tree integrator by name, and a tree's energy under uniform gravity.
#pragma once

#include <memory>
#include <string>

#include "cga_rigid_sim/tree/articulated_body.h"
#include "cga_rigid_sim/tree/tree_integrator.h"

namespace cga_rigid_sim {
namespace testing {

/// The tree integrator of that name (it must exist).
inline std::unique_ptr<dynamics::TreeIntegrator> treeIntegrator(const std::string& name) {
  return std::move(dynamics::makeTreeIntegrator(name).value());
}

/// Kinetic plus potential energy (potential −Σ m g·x of the centres of mass), J.
inline double treeEnergy(const dynamics::ArticulatedBody& tree, const dynamics::TreeState& s,
                         const Eigen::Vector3d& g) {
  dynamics::TreeKinematics kin;
  dynamics::treeKinematics(tree, s, kin);
  double V = 0.0;
  for (int b = tree.floating() ? 0 : 1; b < tree.bodyCount(); ++b)
    V -= tree.inertiaOf(b).mass() * g.dot(kin.M_W[b].translation(tree.lambda()));
  return dynamics::kineticEnergy(tree, kin) + V;
}

}  // namespace testing
}  // namespace cga_rigid_sim
