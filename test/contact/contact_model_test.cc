// The contact model's extensions (doc/contact_model.md) against analytic solutions: static
// against kinetic friction, rolling and torsional resistance of a patch, speed-dependent and
// tangential restitution, rounded edges, compliant contact, a face's friction and bounce,
// friction in an impact; and off, the plain model to the bit.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "contact/contact_fixtures.h"

namespace cga_rigid_sim {
namespace contact_model_test {

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
  idle.stribeck_speed = 0.3;               // used only with a static friction ratio above 1
  idle.restitution_reference_speed = 0.3;  // used only with a restitution exponent above 0
  const auto scene = makeScene(
      {block("b", 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1}, {2, 0.5, 0}),
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
  auto w = modelWorld(
      makeScene({block("b", 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1}, {v0, 0, 0})}, {0, 0, -kG}), mu_k, m);
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
  auto w = modelWorld(
      makeScene({ball("s", 1.0, r, {0, 0, r}, {v0, 0, 0}, {0, v0 / r, 0})}, {0, 0, -kG}), mu, m);
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
  auto w = modelWorld(makeScene({ball("s", 1.0, r, {0, 0, r}, {0, 0, 0}, {0, 0, w0})}, {0, 0, -kG}),
                      mu, m);
  const double I = 0.4 * r * r, alpha = rho * kG / I;
  w->step(300);
  EXPECT_NEAR(w->bodyStates()[0].angular_velocity.z(), w0 - alpha * 0.3, 1e-9);
  w->step(static_cast<int>(1000 * w0 / alpha));
  EXPECT_LE(std::abs(w->bodyStates()[0].angular_velocity.z()), 1e-9);
  EXPECT_LE(w->bodyStates()[0].com.head<2>().norm(), 1e-12);  // it spins in place
}

// Truth (Johnson's speed-dependent restitution): a ball dropped from h0 hits at v1 = √(2 g h0)
// and leaves at e(v1) v1, e(v) = e (v_ref / v)^p, so its first apex is (e(v1) v1)² / (2 g). It
// lands at the instant of touch (doc/contacts.md): the apex is exact but for the step's
// sampling, ½ g h² = 4.9e-6 m: tolerance 1e-5 m.
TEST(ContactModel, RestitutionFallsWithTheImpactSpeedAsJohnsonsLaw) {
  const double h0 = 1.0, r = 0.1, e = 0.5, p = 0.25, v_ref = 0.5;
  sim::ContactModel m;
  m.restitution_speed_exponent = p;
  m.restitution_reference_speed = v_ref;
  sim::WorldConfig config;
  config.contact_restitution = e;
  config.ground_plane = sim::GroundPlane{};
  config.contact_model = m;
  auto w = sim::World::create(makeScene({ball("b", 1.0, r, {0, 0, h0 + r})}, {0, 0, -kG}), config);
  ASSERT_TRUE(w.ok()) << w.error();
  const double v1 = std::sqrt(2 * kG * h0);
  const double e1 = std::min(1.0, e * std::pow(v_ref / v1, p));
  double prev = 0.0, apex = -1.0;
  for (int s = 0; s < 1500 && apex < 0; ++s) {
    (*w)->step();
    const double vz = (*w)->bodyStates()[0].linear_velocity.z();
    if (prev > 0 && vz <= 0) apex = (*w)->bodyStates()[0].com.z() - r;
    prev = vz;
  }
  EXPECT_NEAR(apex, std::pow(e1 * v1, 2) / (2 * kG), 1e-5);
  // The law, not e: at 4.4 m/s, above v_ref, e(v1) = 0.29 and the bounce is a third of e² h0.
  EXPECT_LT(apex, 0.5 * e * e * h0);
}

// Truth (rounded edges): a box of half-width a with edges rounded by r, standing on an edge
// (turned 45° about x), touches the plane when its centre is (a − r)√2 + r high, lower than a
// sharp box's a√2 by r(√2 − 1); the two corners of that edge then report a depth of 0 (to
// round-off) at x = ±(a − r), on the plane. The same pose overlaps a sharp box by r(√2 − 1).
// A face lying flat still rests at height a, its corners inset by r.
TEST(ContactModel, RoundedEdgesTouchLowerOnAnEdgeAndLieFlatOnAFace) {
  const double a = 0.05, r = 0.01;
  const double z = (a - r) * std::sqrt(2.0) + r;
  const Eigen::Quaterniond R(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitX()));
  for (const double radius : {r, 0.0}) {
    sim::ContactModel m;
    m.box_edge_radius = radius;
    sim::WorldConfig config;
    config.ground_plane = sim::GroundPlane{};
    config.contact_model = m;
    auto w = sim::World::create(
        makeScene({block("b", 1.0, {2 * a, 2 * a, 2 * a}, {0, 0, z}, {0, 0, 0}, R)}, {0, 0, 0}),
        config);
    ASSERT_TRUE(w.ok()) << w.error();
    (*w)->step();
    int touching = 0;
    for (const auto& c : (*w)->contacts()) {
      if (c.depth < -1e-9) continue;
      ++touching;
      EXPECT_NEAR(c.depth, radius > 0 ? 0.0 : r * (std::sqrt(2.0) - 1), 1e-12);
      EXPECT_NEAR(std::abs(c.point.x()), a - radius, 1e-12);
      EXPECT_NEAR(c.point.z(), radius > 0 ? 0.0 : -r * (std::sqrt(2.0) - 1), 1e-12);
    }
    EXPECT_EQ(touching, 2);
  }
  sim::ContactModel m;
  m.box_edge_radius = r;
  auto flat = modelWorld(
      makeScene({block("b", 1.0, {2 * a, 2 * a, 2 * a}, {0, 0, a})}, {0, 0, -kG}), 0.5, m);
  flat->step(1000);
  EXPECT_NEAR(flat->bodyStates()[0].com.z(), a, 1e-10);
  for (const auto& c : flat->contacts()) EXPECT_NEAR(std::abs(c.point.x()), a - r, 1e-12);
}

// Truth (compliant contact): a box on four corner springs of stiffness k settles where they
// carry its weight, 4 k δ = m g, and oscillates about it at ω = √(4k/m) until the dissipation
// stills it (damping ratio 0.27, decay time 0.04 s): after 3 s the centre is δ below its
// half-width to 1e-9 m. The damper reads the velocity before the step's gravity kick: at rest
// it adds nothing (with the kicked velocity it would push 1 + d g h = 4.9 % too hard).
TEST(ContactModel, CompliantContactSinksUnderTheWeightBySpringLaw) {
  const double a = 0.05, mass = 1.0, k = 2000.0;
  sim::ContactModel m;
  m.normal_stiffness = k;
  m.normal_dissipation = 5.0;
  auto w = modelWorld(makeScene({block("b", mass, {2 * a, 2 * a, 2 * a}, {0, 0, a})}, {0, 0, -kG}),
                      0.5, m, /*sleeping=*/false);
  w->step(3000);
  EXPECT_NEAR(w->bodyStates()[0].com.z(), a - mass * kG / (4 * k), 1e-9);
}

// Truth (tangential restitution): a ball (no spin) hits the plane at 2 m/s down and 1 m/s
// across with friction high enough to stick; with e_t the contact point leaves slipping at
// −e_t times its arrival slip (1 m/s), and keeps that in flight (no torque): slip = v_x − ω_y r
// = −e_t to the solver's tolerance (1e-9 m/s).
TEST(ContactModel, TangentialRestitutionReversesTheSlipAtAnImpact) {
  const double r = 0.1, e_t = 0.4;
  sim::ContactModel m;
  m.tangential_restitution = e_t;
  sim::WorldConfig config;
  config.contact_mu = 10.0;
  config.contact_restitution = 0.5;
  config.ground_plane = sim::GroundPlane{};
  config.contact_model = m;
  auto w = sim::World::create(
      makeScene({ball("b", 1.0, r, {0, 0, r + 0.0105}, {1.0, 0, -2.0})}, {0, 0, 0}), config);
  ASSERT_TRUE(w.ok()) << w.error();
  (*w)->step(20);
  const auto b = (*w)->bodyStates()[0];
  ASSERT_GT(b.linear_velocity.z(), 0.0);  // it bounced
  EXPECT_NEAR(b.linear_velocity.x() - b.angular_velocity.y() * r, -e_t * 1.0, 1e-9);
}

// Truth (pressure-dependent friction): a box sliding flat on a face, its four corners a face
// block, decelerates at f μ g and stops after v0² / (2 f μ g) (to the last step's travel,
// 1e-5 m as the plain model's test); a ball's single contact keeps μ.
TEST(ContactModel, AFaceSlidesWithTheFaceFrictionRatio) {
  const double mu = 0.2, f = 1.5, v0 = 2.0;
  sim::ContactModel m;
  m.face_friction_ratio = f;
  auto w = modelWorld(makeScene({block("b", 1.0, {0.2, 0.2, 0.2}, {0, 0, 0.1}, {v0, 0, 0}),
                                 ball("s", 1.0, 0.1, {0, 3, 0.1}, {v0, 0, 0})},
                                {0, 0, -kG}),
                      mu, m);
  w->step(100);
  EXPECT_NEAR(w->bodyStates()[1].linear_velocity.x(), v0 - mu * kG * 0.1, 1e-10);
  w->step(1900);
  EXPECT_NEAR(w->bodyStates()[0].com.x(), v0 * v0 / (2 * f * mu * kG), 1e-5);
}

// Truth (friction in an impact): a ball without spin hits the plane at v_n = 2 m/s down and
// v_t = 1 m/s across, e = 0.5, μ = 0.08 and the impact ratio 0.5 (and 1, off). Its normal through
// the centre decouples the normal from the slip: P_n = m (1 + e) v_n; the slip needs 2/7 m v_t
// to stop, more than μ_i P_n (0.12 m; 0.24 m off), so it slides throughout and P_t = μ_i P_n:
// it leaves with v_x = v_t − μ_i (1 + e) v_n and ω_y r = (5/2) μ_i (1 + e) v_n (a solid ball,
// I = 2/5 m r²). Exact but for the solver's tolerance (1e-9 m/s). A ball sliding on the plane, no
// impact, keeps μ: v0 − μ g t after 0.1 s (to 1e-10 m/s, as the face test's ball).
TEST(ContactModel, AnImpactSlidesWithTheImpactFrictionRatio) {
  const double r = 0.1, e = 0.5, mu = 0.08, ratio = 0.5, v_n = 2.0, v_t = 1.0, v0 = 2.0;
  for (const double k : {ratio, 1.0}) {  // 1: off, the plain model's μ
    sim::ContactModel m;
    m.impact_friction_ratio = k;
    sim::WorldConfig config;
    config.contact_mu = mu;
    config.contact_restitution = e;
    config.ground_plane = sim::GroundPlane{};
    config.contact_model = m;
    auto w = sim::World::create(
        makeScene({ball("b", 1.0, r, {0, 0, r + 0.0105}, {v_t, 0, -v_n})}, {0, 0, 0}), config);
    ASSERT_TRUE(w.ok()) << w.error();
    (*w)->step(20);
    const auto b = (*w)->bodyStates()[0];
    const double p_t = k * mu * (1 + e) * v_n;          // per unit mass
    ASSERT_NEAR(b.linear_velocity.z(), e * v_n, 1e-9);  // it bounced, Newton's e
    EXPECT_NEAR(b.linear_velocity.x(), v_t - p_t, 1e-9);
    EXPECT_NEAR(b.angular_velocity.y() * r, 2.5 * p_t, 1e-9);
  }
  sim::ContactModel m;
  m.impact_friction_ratio = ratio;
  auto w = modelWorld(makeScene({ball("s", 1.0, r, {0, 0, r}, {v0, 0, 0})}, {0, 0, -kG}), mu, m);
  w->step(100);
  EXPECT_NEAR(w->bodyStates()[0].linear_velocity.x(), v0 - mu * kG * 0.1, 1e-10);
}

// Truth (a face landing flat): a box dropped flat from h0 lands on its four corners, a face
// block, at v1 = √(2 g h0) and leaves at f e v1, so its first apex is (f e v1)² / (2 g); a ball
// dropped beside it lands on one contact and keeps e: (e v1)² / (2 g). Both land at the instant
// of touch: exact but for the step's sampling, ½ g h² = 4.9e-6 m (tolerance 1e-5 m, as
// Johnson's test).
TEST(ContactModel, AFaceLandingFlatBouncesWithTheFaceRestitutionRatio) {
  const double h0 = 0.5, a = 0.1, r = 0.1, e = 0.6, f = 0.5;
  sim::ContactModel m;
  m.face_restitution_ratio = f;
  sim::WorldConfig config;
  config.contact_restitution = e;
  config.ground_plane = sim::GroundPlane{};
  config.contact_model = m;
  auto w = sim::World::create(makeScene({block("b", 1.0, {2 * a, 2 * a, 2 * a}, {0, 0, a + h0}),
                                         ball("s", 1.0, r, {3, 0, r + h0})},
                                        {0, 0, -kG}),
                              config);
  ASSERT_TRUE(w.ok()) << w.error();
  const double v1 = std::sqrt(2 * kG * h0);
  double prev[2] = {0, 0}, apex[2] = {-1, -1};
  for (int s = 0; s < 1500 && (apex[0] < 0 || apex[1] < 0); ++s) {
    (*w)->step();
    for (int k = 0; k < 2; ++k) {
      const double vz = (*w)->bodyStates()[k].linear_velocity.z();
      if (apex[k] < 0 && prev[k] > 0 && vz <= 0)
        apex[k] = (*w)->bodyStates()[k].com.z() - (k == 0 ? a : r);
      prev[k] = vz;
    }
  }
  EXPECT_NEAR(apex[0], std::pow(f * e * v1, 2) / (2 * kG), 1e-5);
  EXPECT_NEAR(apex[1], std::pow(e * v1, 2) / (2 * kG), 1e-5);
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
  // Each case: a setting broken, and the message it must give.
  const std::vector<std::pair<void (*)(sim::ContactModel&), std::string>> cases = {
      {[](sim::ContactModel& m) { m.static_friction_ratio = 0.5; },
       "config.contact_model.static_friction_ratio: must be finite and >= 1"},
      {[](sim::ContactModel& m) { m.stribeck_speed = 0.0; },
       "contact_model.stribeck_speed: must be finite and > 0"},
      {[](sim::ContactModel& m) { m.rolling_resistance = -1e-3; },
       "contact_model.rolling_resistance: must be finite and >= 0"},
      {[](sim::ContactModel& m) { m.torsional_resistance = std::nan(""); },
       "contact_model.torsional_resistance: must be finite and >= 0"},
      {[](sim::ContactModel& m) { m.tangential_restitution = 1.5; },
       "contact_model.tangential_restitution: must be in [0, 1]"},
      {[](sim::ContactModel& m) { m.face_friction_ratio = 0.0; },
       "contact_model.face_friction_ratio: must be finite and > 0"},
      {[](sim::ContactModel& m) { m.impact_friction_ratio = -0.5; },
       "contact_model.impact_friction_ratio: must be finite and > 0"},
      {[](sim::ContactModel& m) { m.face_restitution_ratio = 1.5; },
       "contact_model.face_restitution_ratio: must be in [0, 1]"},
      {[](sim::ContactModel& m) { m.normal_stiffness = -1.0; },
       "contact_model.normal_stiffness: must be finite and >= 0"},
      {[](sim::ContactModel& m) { m.restitution_reference_speed = 0.0; },
       "contact_model.restitution_reference_speed: must be finite and > 0"},
      {[](sim::ContactModel& m) { m.box_edge_radius = -0.01; },
       "contact_model.box_edge_radius: must be finite and >= 0"},
  };
  for (const auto& [breaks, message] : cases) {
    sim::ContactModel m;
    breaks(m);
    EXPECT_NE(refusal(m).find(message), std::string::npos) << refusal(m);
  }
  EXPECT_EQ(refusal(sim::ContactModel()), "");
}

}  // namespace contact_model_test
}  // namespace cga_rigid_sim
