// The drift of a body in contact (stage_integrate.cc): it starts from a fresh anchor every step,
// so whatever rounding the step leaves in the rotor's norm is carried into the next step and
// turns, through R and R̃, into a scale of the body's velocity.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_fixtures.h"

namespace cga_rigid_sim {
namespace testing {
namespace {

constexpr double kG = 9.81;

// Truth: a ball rolling without slipping on level ground keeps its speed (no rolling resistance;
// gravity and the normal impulse are vertical, and the friction impulse vanishes at zero slip).
// Its body turns 0.02 rad a step and v_B with it. Two roundings used to add up with a bias
// (measured on this case): the rotor renormalised as r/|r| came out 0.44 ε too long on average,
// and v_B was carried to the world and back through the whole attitude, whose norm error then
// scales it; the speed drifted by 1.6e-12 relative in these 10⁴ steps (4e-13 with the unbiased
// renormalisation r + e r alone). Turned by the step's own small rotor instead, v_B picks up a
// few unbiased roundings of ε/2 |v| a step (measured rms 2.5e-16 relative), a random walk of
// ~2.5e-14 after 10⁴ steps (measured 3.7e-15). Bound: 1e-13, four times the walk's spread and a
// quarter of the smaller biased drift.
TEST(ContactDrift, RollingBallKeepsItsSpeedOverTenThousandSteps) {
  const double mu = 0.5, r = 0.1, v = 2.0, h = 1e-3;
  auto w = contactWorld(
      makeScene({ball("s", 1.0, r, {0, 0, r}, {v, 0, 0}, {0, v / r, 0})}, {0, 0, -kG}), mu, 0.0, h);
  ASSERT_TRUE(w);
  w->step(10000);
  const auto states = w->bodyStates();
  ASSERT_EQ(states.size(), 1u);
  EXPECT_LE(std::abs(states[0].linear_velocity.x() - v), 1e-13 * v);
  // And it still rolls: the slip stays at round-off.
  EXPECT_LE(std::abs(states[0].linear_velocity.x() - states[0].angular_velocity.y() * r), 1e-13);
}

}  // namespace
}  // namespace testing
}  // namespace cga_rigid_sim
