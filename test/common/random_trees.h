// Random rigid-body and tree data for the articulated tests
// (test/tree/articulated_body_test.cc, tree_integrator_residual_test.cc): vectors, motors, box
// inertias and trees of revolute and prismatic joints (every third prismatic), all from a caller's
// seeded generator.
#pragma once

#include <optional>
#include <random>
#include <vector>

#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/cga/motor.h"
#include "cga_rigid_sim/tree/articulated_body.h"

namespace cga_rigid_sim {
namespace testing {

inline Eigen::Vector3d randomVector(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

inline cga::Motor randomMotor(std::mt19937& rng, double reach, double lambda) {
  Eigen::Quaterniond R(Eigen::Vector4d(randomVector(rng, 1).x(), randomVector(rng, 1).y(),
                                       randomVector(rng, 1).z(), 0.5));
  R.normalize();
  return cga::Motor::fromPose(R, randomVector(rng, reach), lambda);
}

/// A solid box a × b × c of mass m, each drawn from [0.2, 1.5].
inline dynamics::Inertia randomInertia(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.2, 1.5);
  const double m = u(rng), a = u(rng), b = u(rng), c = u(rng);
  return dynamics::Inertia::fromPrincipal(
             "link", m,
             {m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12})
      .value();
}

/// n joints, each hung from a random earlier link (or the base), with a floating root or a
/// fixed base.
inline dynamics::ArticulatedBody randomTree(std::mt19937& rng, int n, bool floating,
                                            double lambda) {
  std::vector<dynamics::TreeJoint> joints;
  for (int k = 0; k < n; ++k) {
    dynamics::TreeJoint j;
    j.kind = (k % 3 == 2) ? dynamics::JointKind::kPrismatic : dynamics::JointKind::kRevolute;
    j.parent = std::uniform_int_distribution<int>(0, k)(rng);
    j.M_PJ = randomMotor(rng, 0.8, lambda);
    j.M_JC = randomMotor(rng, 0.5, lambda);
    j.axis = randomVector(rng, 1).normalized();
    j.inertia = randomInertia(rng);
    joints.push_back(j);
  }
  return dynamics::ArticulatedBody(
      floating ? std::optional<dynamics::Inertia>(randomInertia(rng)) : std::nullopt, joints,
      lambda);
}

}  // namespace testing
}  // namespace cga_rigid_sim
