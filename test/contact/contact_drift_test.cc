// The drift of a body in contact (stage_integrate.cc): it starts from a fresh anchor every step,
// so whatever a step rounds is carried into the next; the body carries its momentum in world
// axes between contact steps (src/contact/contact_momentum.h).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>

#include "contact/contact_fixtures.h"

namespace cga_rigid_sim {
namespace testing {
namespace contact_drift_test {

constexpr double kG = 9.81;

// Truth: a ball rolling without slipping on level ground keeps its speed (no rolling resistance;
// gravity and the normal impulse are vertical, and the friction impulse vanishes at zero slip).
// Its body turns 0.02 rad a step. History of this bound (measured on this case): with v_B
// carried in body axes, the rotor renormalised as r/|r| (0.44 ε too long on average) and v_B
// taken to the world and back through the whole attitude, the speed drifted by 1.6e-12
// relative in these 10⁴ steps; with an unbiased renormalisation and v_B turned by the step's
// own rotor, a random walk of roundings was left (3.7e-15). Now the body carries its momentum
// in world axes (doc/contacts.md#world-momentum), where gravity's kick and the normal impulse
// cancel exactly and the friction impulse is zero, so nothing accumulates: what is left is the
// report's own rounding, v_W read off the state as R (R̃ v_W), two rotations of ~1 ε each
// (measured: 0 in v_x, 1.1e-16 m/s in v_z). Bound 4 ε |v|.
TEST(ContactDrift, RollingBallKeepsItsSpeedOverTenThousandSteps) {
  const double mu = 0.5, r = 0.1, v = 2.0, h = 1e-3;
  auto w = contactWorld(
      makeScene({ball("s", 1.0, r, {0, 0, r}, {v, 0, 0}, {0, v / r, 0})}, {0, 0, -kG}), mu, 0.0, h);
  ASSERT_TRUE(w);
  w->step(10000);
  const auto states = w->bodyStates();
  ASSERT_EQ(states.size(), 1u);
  EXPECT_LE((states[0].linear_velocity - Eigen::Vector3d(v, 0, 0)).norm(), 4 * DBL_EPSILON * v);
  // And it still rolls: the slip stays at round-off (the same two rotations, for v and ω r).
  EXPECT_LE(std::abs(states[0].linear_velocity.x() - states[0].angular_velocity.y() * r),
            8 * DBL_EPSILON * v);
}

// Truth: the carried momentum is only the state's while nothing else has changed the state. A
// ball slides on frictionless ground at 1 m/s (contact steps every step, so it carries its
// momentum); an impulse J at its centre then changes its velocity by J/m, and a state set
// through setBodyState is the state it goes on from. Each within 4 ε of the exact velocity (the
// report's two rotations); a momentum carried past either would leave the old velocity, off
// by 0.25 m/s and more.
TEST(ContactDrift, InputsAndEditsBetweenContactStepsAreNotLostToTheCarriedMomentum) {
  const double m = 2.0, r = 0.1;
  auto w = contactWorld(
      makeScene({ball("s", m, r, {0, 0, r}, {1.0, 0, 0}, {0, 0, 3.0})}, {0, 0, -kG}), 0.0, 0.0);
  ASSERT_TRUE(w);
  const auto state = [&w] { return w->bodyStates().at(0); };
  w->step(100);
  ASSERT_GT(w->data().contacts.size(), 0u);
  sim::ImpulseInput imp;
  imp.body = "s";
  imp.J = cga::Force(Eigen::Vector3d(0.5, 0.25, 0), 0.0);
  imp.point = state().com;
  ASSERT_TRUE(w->applyImpulse(imp).ok());
  w->step(10);
  const Eigen::Vector3d after_impulse(1.0 + 0.5 / m, 0.25 / m, 0);
  EXPECT_LE((state().linear_velocity - after_impulse).norm(), 4 * DBL_EPSILON * 1.25);
  EXPECT_LE((state().angular_velocity - Eigen::Vector3d(0, 0, 3.0)).norm(), 4 * DBL_EPSILON * 3.0);

  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = state().com;
  const Eigen::Vector3d v_set(-0.5, 0.75, 0), w_set(0, 0, -2.0);
  ASSERT_TRUE(w->setBodyState("s", pose, v_set, w_set).ok());
  w->step(10);
  EXPECT_LE((state().linear_velocity - v_set).norm(), 4 * DBL_EPSILON * 0.9);
  EXPECT_LE((state().angular_velocity - w_set).norm(), 4 * DBL_EPSILON * 2.0);
}

}  // namespace contact_drift_test
}  // namespace testing
}  // namespace cga_rigid_sim
