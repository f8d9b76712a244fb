// The contact model's extensions (doc/contact_model.md) against analytic solutions: static
// against kinetic friction, rolling and torsional resistance of a patch; and off, the plain
// model to the bit.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_fixtures.h"

namespace cga_rigid_sim {
namespace {

using testing::ball;
using testing::block;
using testing::makeScene;
using testing::slopeGravity;

constexpr double kG = 9.81;

std::unique_ptr<sim::World> modelWorld(scene::Scene scene, double mu, const sim::ContactModel& m,
                                       bool sleeping = true) {
  sim::WorldConfig config;
  config.dt = 1e-3;
  config.contact_mu = mu;
  config.contact_sleeping = sleeping;
  config.ground_plane = sim::GroundPlane{};
  config.contact_model = m;
  auto w = sim::World::create(std::move(scene), config);
  EXPECT_TRUE(w.ok()) << w.error();
  return w.ok() ? std::move(w.value()) : nullptr;
}

// Truth: with every extension at its default the solve is the plain model's: a block sliding
// at 2 m/s, a ball rolling and a landing box are bit-identical with a default ContactModel and
// with one whose inactive fields (the Stribeck speed) are changed.
TEST(ContactModel, OffIsThePlainModelToTheBit) {
  sim::ContactModel idle;
  idle.stribeck_speed = 0.3;  // used only with a static friction ratio above 1
  const auto scene = makeScene({block("b", 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1}, {2, 0.5, 0}),
                                ball("s", 1.0, 0.1, {3, 0, 0.1}, {1, 0, 0}, {0, 3, 2}),
                                block("c", 2.0, {0.1, 0.2, 0.3}, {-3, 0, 0.5}, {0, 0, 0},
                                      Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized())))},
                               {0, 0, -kG});
  auto plain = modelWorld(scene, 0.3, sim::ContactModel());
  auto off = modelWorld(scene, 0.3, idle);
  for (int s = 0; s < 1500; ++s) {
    plain->step();
    off->step();
    const auto a = plain->bodyStates(), b = off->bodyStates();
    for (std::size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(a[k].state.M_WB.coefficients(), b[k].state.M_WB.coefficients()) << s;
      ASSERT_EQ(a[k].state.omega_B.coefficients(), b[k].state.omega_B.coefficients()) << s;
    }
  }
}

// Truth (static friction): a block at rest on a slope with μ_k < tan θ ≤ μ_s stays at rest
// (static friction holds it), while the plain model with μ = μ_k slides it down at
// g (sin θ − μ_k cos θ). At rest its slip before each step's impulses is the gravity kick's,
// g sin θ h ≈ 4e-3 m/s, far below v_s = 0.1 m/s: μ(v) = μ_s (1 − 2e-3) ≥ tan θ, and the
// friction impulse balances the kick exactly each step, so the drift is round-off (1e-12 m in
// 2 s, as the plain model's sticking block).
TEST(ContactModel, StaticFrictionHoldsABlockTheKineticOneLetsSlide) {
  const double mu_k = 0.3, ratio = 1.5, tan_theta = 0.4;  // μ_s = 0.45
  const double theta = std::atan(tan_theta);
  sim::ContactModel m;
  m.static_friction_ratio = ratio;
  m.stribeck_speed = 0.1;
  const auto scene =
      makeScene({block("b", 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1})}, slopeGravity(kG, theta));
  auto held = modelWorld(scene, mu_k, m);
  auto plain = modelWorld(scene, mu_k, sim::ContactModel());
  held->step(2000);
  plain->step(2000);
  EXPECT_LE(std::abs(held->bodyStates()[0].com.x()), 1e-12);
  const double a = kG * (std::sin(theta) - mu_k * std::cos(theta));
  EXPECT_NEAR(plain->bodyStates()[0].com.x(), 0.5 * a * 4.0, 1e-9 * 2.0 * a);
}

// Truth (kinetic friction): a block sliding at v0 = 3 m/s with v_s = 0.01 m/s decelerates at
// μ_k g while it is fast (μ(v) − μ_k = μ_k (r − 1) e^{−(v/v_s)²} < 1e-300 above 0.3 m/s), so
// its speed after 0.5 s is v0 − μ_k g t to the solver's round-off; it then stops sooner than
// under μ_k alone: the distance v0²/(2 μ_k g) is missed only by the last part of the slide,
// below v ~ 3 v_s, where friction rises to μ_s: by less than (3 v_s)²/(2 μ_k g) = 1.5e-4 m
// (and by more than nothing: it does stop sooner).
TEST(ContactModel, FastSlidingFeelsTheKineticFrictionAndStopsSooner) {
  const double mu_k = 0.3, v0 = 3.0, vs = 0.01;
  sim::ContactModel m;
  m.static_friction_ratio = 2.0;
  m.stribeck_speed = vs;
  auto w = modelWorld(makeScene({block("b", 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1}, {v0, 0, 0})},
                                {0, 0, -kG}),
                      mu_k, m);
  w->step(500);
  EXPECT_NEAR(w->bodyStates()[0].linear_velocity.x(), v0 - mu_k * kG * 0.5, 1e-9);
  w->step(1500);
  const double x = w->bodyStates()[0].com.x(), full = v0 * v0 / (2 * mu_k * kG);
  EXPECT_LT(x, full);
  EXPECT_GT(x, full - 1.5e-4);
  EXPECT_LE(w->bodyStates()[0].linear_velocity.norm(), 1e-12);
}

// Truth (rolling resistance): a solid ball (I = (2/5) m r²) rolling at v0 on flat ground with a
// rolling couple ρ m g against its rolling decelerates at a = ρ g / (1.4 r) (torques about the
// contact point: (I + m r²) α = −ρ m g) and stops after v0² / (2a). The couple and the friction
// that keeps it rolling are solved per step; the speed falls by a h per step exactly while it
// rolls (tolerance 1e-9 m/s after 0.5 s: the solver's residuals), and the stopping point is
// within the last step's travel, a h² ~ 1e-7 m, plus the sweeps' residual: 1e-5 m.
TEST(ContactModel, RollingResistanceStopsARollingBall) {
  const double r = 0.1, v0 = 1.0, rho = 0.002, mu = 0.5;
  sim::ContactModel m;
  m.rolling_resistance = rho;
  auto w = modelWorld(makeScene({ball("s", 1.0, r, {0, 0, r}, {v0, 0, 0}, {0, v0 / r, 0})},
                                {0, 0, -kG}),
                      mu, m);
  const double a = rho * kG / (1.4 * r);
  w->step(500);
  EXPECT_NEAR(w->bodyStates()[0].linear_velocity.x(), v0 - a * 0.5, 1e-9);
  w->step(static_cast<int>(1000 * v0 / a));
  EXPECT_NEAR(w->bodyStates()[0].com.x(), v0 * v0 / (2 * a), 1e-5);
  EXPECT_LE(w->bodyStates()[0].linear_velocity.norm(), 1e-9);
}

// Truth (torsional resistance): a ball spinning about the vertical at ω0 on the ground takes a
// couple ρ_t m g against its spin and stops at t = I ω0 / (ρ_t m g) (I = (2/5) m r²); its spin
// falls linearly: ω(t) = ω0 − ρ_t m g t / I, to the solver's round-off (1e-9 rad/s).
TEST(ContactModel, TorsionalResistanceStopsASpinningBall) {
  const double r = 0.1, w0 = 20.0, rho = 0.004, mu = 0.5;
  sim::ContactModel m;
  m.torsional_resistance = rho;
  auto w = modelWorld(makeScene({ball("s", 1.0, r, {0, 0, r}, {0, 0, 0}, {0, 0, w0})},
                                {0, 0, -kG}),
                      mu, m);
  const double I = 0.4 * r * r, alpha = rho * kG / I;
  w->step(300);
  EXPECT_NEAR(w->bodyStates()[0].angular_velocity.z(), w0 - alpha * 0.3, 1e-9);
  w->step(static_cast<int>(1000 * w0 / alpha));
  EXPECT_LE(std::abs(w->bodyStates()[0].angular_velocity.z()), 1e-9);
  EXPECT_LE(w->bodyStates()[0].com.head<2>().norm(), 1e-12);  // it spins in place
}

// Truth: the rules of doc/contact_model.md, each refused by name.
TEST(ContactModel, UnphysicalSettingsAreRefusedByName) {
  const auto scene = makeScene({ball("s", 1.0, 0.1, {0, 0, 0.1})}, {0, 0, -kG});
  const auto refusal = [&](const sim::ContactModel& m) {
    sim::WorldConfig config;
    config.contact_model = m;
    auto w = sim::World::create(scene, config);
    return w.ok() ? std::string() : w.error();
  };
  sim::ContactModel m;
  m.static_friction_ratio = 0.5;
  EXPECT_NE(refusal(m).find("config.contact_model.static_friction_ratio: must be finite and >= 1"),
            std::string::npos)
      << refusal(m);
  m = {};
  m.stribeck_speed = 0.0;
  EXPECT_NE(refusal(m).find("contact_model.stribeck_speed: must be finite and > 0"),
            std::string::npos);
  m = {};
  m.rolling_resistance = -1e-3;
  EXPECT_NE(refusal(m).find("contact_model.rolling_resistance: must be finite and >= 0"),
            std::string::npos);
  m = {};
  m.torsional_resistance = std::nan("");
  EXPECT_NE(refusal(m).find("contact_model.torsional_resistance"), std::string::npos);
  EXPECT_EQ(refusal(sim::ContactModel()), "");
}

}  // namespace
}  // namespace cga_rigid_sim
