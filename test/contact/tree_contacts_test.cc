// Links of articulated trees in contact (doc/contacts.md#trees): a tree is kicked by its loads,
// takes the contact impulses through its links' Jacobians together with every other body, and
// drifts. Each test sets a tree where the outcome follows from conservation laws or statics.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <sstream>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace sim {
namespace tree_contacts_test {

constexpr double kG = 9.81;

std::string num(double x) {
  std::ostringstream os;
  os << std::setprecision(17) << x;
  return os.str();
}

std::string contactTag(double mu, double e) {
  return "<cga_rigid_sim:contact mu='" + num(mu) + "' restitution='" + num(e) + "'/>";
}

// A pendulum hanging from the world at height `pivot` about y: a bob of mass m and radius r at
// distance L below the pivot (a solid ball's inertia about its centre), optionally a static
// wall whose face is at x = wall_x (nothing if NaN), surfaces with restitution e.
std::string pendulumUrdf(double m, double r, double L, double pivot, double e, double wall_x) {
  const double J = 0.4 * m * r * r;
  std::string u =
      "<robot name='p' xmlns:cga_rigid_sim='urn:cga_rigid_sim:urdf_extension'>"
      "<link name='world'/>"
      "<link name='arm'><inertial><origin xyz='0 0 " +
      num(-L) + "'/><mass value='" + num(m) + "'/><inertia ixx='" + num(J) + "' iyy='" + num(J) +
      "' izz='" + num(J) +
      "' ixy='0' ixz='0' iyz='0'/></inertial>"
      "<collision><origin xyz='0 0 " +
      num(-L) + "'/><geometry><sphere radius='" + num(r) + "'/></geometry>" + contactTag(0.0, e) +
      "</collision></link>"
      "<joint name='hinge' type='continuous'><parent link='world'/><child link='arm'/>"
      "<origin xyz='0 0 " +
      num(pivot) + "'/><axis xyz='0 1 0'/></joint>";
  if (std::isfinite(wall_x))
    u += "<link name='wall'><collision><geometry><box size='0.2 1 1'/></geometry>" +
         contactTag(0.0, e) +
         "</collision></link>"
         "<joint name='wall_fixed' type='fixed'><parent link='world'/><child link='wall'/>"
         "<origin xyz='" +
         num(wall_x + 0.1) + " 0 " + num(pivot - L) + "'/></joint>";
  return u + "</robot>";
}

std::unique_ptr<World> makeWorld(const std::string& urdf, WorldConfig config,
                                 scene::ParamValue initial, Eigen::Vector3d g) {
  scene::SceneOptions options;
  options.gravity_W = g;
  options.initial_state = initial;
  auto scene = scene::loadUrdfString(urdf, "test", options);
  EXPECT_TRUE(scene.ok()) << scene.error();
  if (!scene.ok()) return nullptr;
  auto world = World::create(std::move(scene.value()), config);
  EXPECT_TRUE(world.ok()) << world.error();
  if (!world.ok()) return nullptr;
  return std::move(world.value());
}

scene::ParamValue jointPosition(const char* joint, double q) {
  scene::ParamValue::Map entry, m;
  entry["position"] = scene::ParamValue(q);
  m[joint] = scene::ParamValue(entry);
  return scene::ParamValue(m);
}

double jointVelocity(const World& w, const std::string& name) {
  for (const auto& j : w.jointStates())
    if (j.name == name) return j.velocity;
  ADD_FAILURE() << "no joint " << name;
  return 0;
}

double jointPositionOf(const World& w, const std::string& name) {
  for (const auto& j : w.jointStates())
    if (j.name == name) return j.position;
  ADD_FAILURE() << "no joint " << name;
  return 0;
}

// Released at θ0, the bob swings down and meets the wall at the bottom of its arc moving
// horizontally: the impulse along x is normal to the arm, so ω⁺ = −e ω⁻ whatever the inertia,
// and the rebound rises to 1 − cos θ1 = e² (1 − cos θ0).
class PendulumIntoWall : public ::testing::TestWithParam<double> {};

TEST_P(PendulumIntoWall, ReboundsToESquaredOfItsHeight) {
  const double e = GetParam(), m = 2.0, r = 0.1, L = 1.0, theta0 = 1.0;
  WorldConfig config;
  config.dt = 1e-3;
  auto w = makeWorld(pendulumUrdf(m, r, L, 2.0, e, r), config, jointPosition("hinge", theta0),
                     {0, 0, -kG});
  ASSERT_TRUE(w);
  // Swing down (θ decreasing to 0 at the wall), then out again the other way: the largest
  // |θ| after the impact is the rebound amplitude.
  bool hit = false;
  double amplitude = 0.0, before = 0.0;
  for (int k = 0; k < 4000; ++k) {
    const double v_before = jointVelocity(*w, "hinge");
    w->step();
    const double v = jointVelocity(*w, "hinge");
    if (!hit && v_before < 0 && v >= 0) {
      hit = true;
      before = -v_before;
      if (e > 0) {
        // Newton's law across the impact step: ω⁺ = e ω⁻ up to the step's gravity (the bob
        // moves horizontally there, so gravity's torque is ~ m g L θ with θ ≤ ω h: a change of
        // g θ h / L ≈ 3e-5 rad/s at most). Measured 8.3e-6 relative.
        EXPECT_NEAR(v, e * before, 3e-5) << "step " << k;
      }
    }
    if (hit) amplitude = std::max(amplitude, std::abs(jointPositionOf(*w, "hinge")));
    if (hit && v < 0) break;  // turned back: the rebound's top has passed
  }
  ASSERT_TRUE(hit);
  // The bob meets the wall up to one step early (a speculative contact), ~ω L h = 3 mm before
  // the bottom, where the speed differs from the lowest point's in second order only
  // (θ²/2 ≈ 5e-6 of the drop); the midpoint keeps the swing's energy to ~1e-5 of it. Measured:
  // 4.3e-5 of the drop at e = 1, 2.0e-5 at e = 0.5; the bound is 2e-4 of the drop.
  const double drop = 1 - std::cos(theta0);
  EXPECT_NEAR(1 - std::cos(amplitude), e * e * drop, 2e-4 * drop) << "e = " << e;
  // The wall stops the bob at x = 0: the arm never passes the vertical by more than the bob's
  // speculative margin.
  for (int k = 0; k < 500; ++k) {
    w->step();
    EXPECT_GE(jointPositionOf(*w, "hinge"), -1e-3);
  }
}

INSTANTIATE_TEST_SUITE_P(Restitution, PendulumIntoWall, ::testing::Values(1.0, 0.5, 0.0));

// A ball hits a hanging pendulum's bob in zero gravity (a ballistic pendulum). The hinge holds
// the bob but exerts no moment about itself, so the angular momentum about the hinge is
// conserved: m v L = I_p ω + m v' L, and Newton's law gives ω L − v' = e v. Hence
// ω = m v L (1 + e) / (I_p + m L²).
TEST(TreeContacts, BallisticPendulumKeepsAngularMomentumAboutItsHinge) {
  const double M = 3.0, r = 0.1, L = 1.0, pivot = 2.0, e = 0.6;
  const double m = 0.5, rb = 0.05, v = 2.0;
  const double Ip = 0.4 * M * r * r + M * L * L;
  // The ball's link sits beside the pendulum in the same URDF (a free root of its own).
  std::string urdf = pendulumUrdf(M, r, L, pivot, e, std::nan(""));
  const double Jb = 0.4 * m * rb * rb;
  urdf.insert(urdf.size() - std::string("</robot>").size(),
              "<link name='ball'><inertial><mass value='" + num(m) + "'/><inertia ixx='" + num(Jb) +
                  "' iyy='" + num(Jb) + "' izz='" + num(Jb) +
                  "' ixy='0' ixz='0' iyz='0'/></inertial><collision><geometry><sphere radius='" +
                  num(rb) + "'/></geometry>" + contactTag(0.0, e) +
                  "</collision></link><joint name='ball_free' type='floating'>"
                  "<parent link='world'/><child link='ball'/></joint>");
  scene::ParamValue::Map ball, lin, joints, hinge;
  ball["position"] = scene::ParamValue(std::vector<scene::ParamValue>{
      scene::ParamValue(-0.3), scene::ParamValue(0.0), scene::ParamValue(pivot - L)});
  ball["linear_velocity"] = scene::ParamValue(std::vector<scene::ParamValue>{
      scene::ParamValue(v), scene::ParamValue(0.0), scene::ParamValue(0.0)});
  scene::ParamValue::Map initial;
  initial["ball"] = scene::ParamValue(ball);
  WorldConfig config;
  config.dt = 1e-4;
  auto w = makeWorld(urdf, config, scene::ParamValue(initial), {0, 0, 0});
  ASSERT_TRUE(w);
  for (int k = 0; k < 2000; ++k) w->step();  // the ball flies 0.15 m to the bob and beyond
  // A push along +x turns the arm by negative θ (a turn by +θ about y carries −z towards −x).
  const double omega = -jointVelocity(*w, "hinge");
  ASSERT_GT(omega, 0.1) << "no impact";
  // The ball's line of flight passes through the bob's centre and the impact is resolved at
  // the step's start, where the arm hangs straight: the impulse is normal to the arm and the
  // balance is exact up to round-off (measured 6e-16 relative); 1e-12 allows for the solver's
  // velocity tolerance.
  const double expected = m * v * L * (1 + e) / (Ip + m * L * L);
  EXPECT_NEAR(omega, expected, 1e-12 * expected);
  const auto b = w->getBodyState("ball");
  ASSERT_TRUE(b.ok());
  const double v_ball = b.value().linear_velocity.x();
  // Newton's law and the angular momentum about the hinge, to the same round-off.
  EXPECT_NEAR(omega * L - v_ball, e * v, 1e-12 * v);
  EXPECT_NEAR(Ip * omega + m * v_ball * L, m * v * L, 1e-12 * m * v * L);
}

// A floating tree — a box chassis with a flap hinged to its side — lies flat on the ground:
// it stays put, and at rest the ground carries its weight: the normal impulses of a step add
// up to (m_chassis + m_flap) g h.
const char* kChassisWithFlap =
    "<robot name='cart' xmlns:cga_rigid_sim='urn:cga_rigid_sim:urdf_extension'>"
    "<link name='chassis'><inertial><mass value='4'/>"
    "<inertia ixx='0.0867' iyy='0.1367' izz='0.2067' ixy='0' ixz='0' iyz='0'/></inertial>"
    "<collision><geometry><box size='0.6 0.4 0.1'/></geometry></collision></link>"
    "<link name='flap'><inertial><origin xyz='0.15 0 0'/><mass value='1'/>"
    "<inertia ixx='0.0142' iyy='0.0083' izz='0.0208' ixy='0' ixz='0' iyz='0'/></inertial>"
    "<collision><origin xyz='0.1 0 0'/><geometry><box size='0.28 0.4 0.1'/></geometry>"
    "</collision></link>"
    "<joint name='flap_hinge' type='revolute'><parent link='chassis'/><child link='flap'/>"
    "<origin xyz='0.3 0 0'/><axis xyz='0 1 0'/>"
    "<limit lower='-1.5' upper='1.5' effort='10' velocity='10'/></joint>"
    "</robot>";

std::unique_ptr<World> chassisOnGround(double height, double mu = 0.8, double e = 0.0) {
  scene::ParamValue::Map root;
  root["position"] = scene::ParamValue(std::vector<scene::ParamValue>{
      scene::ParamValue(0.0), scene::ParamValue(0.0), scene::ParamValue(height)});
  scene::ParamValue::Map initial;
  initial["chassis"] = scene::ParamValue(root);
  WorldConfig config;
  config.dt = 1e-3;
  GroundPlane plane;
  plane.surface.mu = mu;
  plane.surface.restitution = e;
  config.ground_plane = plane;
  return makeWorld(kChassisWithFlap, config, scene::ParamValue(initial), {0, 0, -kG});
}

TEST(TreeContacts, FloatingTreeRestsOnTheGroundAndTheGroundCarriesItsWeight) {
  auto w = chassisOnGround(0.05);
  ASSERT_TRUE(w);
  const auto start = w->getBodyState("chassis").value();
  const double q0 = jointPositionOf(*w, "flap_hinge");
  for (int k = 0; k < 2000; ++k) w->step();
  const auto end = w->getBodyState("chassis").value();
  // Resting contact: no creep of the chassis or the hinge in 2 s. The solver stops within
  // ~1e-10 g h ≈ 1e-12 m/s per step, at most 2e-9 m over 2000 steps if it all went one way
  // (measured: 3.5e-17 m, hinge 9.5e-17 rad, kinetic energy 1e-37 J).
  EXPECT_LT((end.com - start.com).norm(), 2e-9);
  EXPECT_NEAR(jointPositionOf(*w, "flap_hinge"), q0, 2e-9);
  EXPECT_LT(w->momentum().back().kinetic_energy, 1e-15);
  double normal = 0.0;
  for (const auto& c : w->contacts()) normal += c.normal_impulse;
  // Statics: Σ λ_n = m g h over the step; the solver's velocity tolerance (1e-10 of g h)
  // bounds the residual (measured 4e-16 relative).
  EXPECT_NEAR(normal, 5.0 * kG * 1e-3, 1e-9 * 5.0 * kG * 1e-3);
}

TEST(TreeContacts, DroppedFloatingTreeBalancesItsEnergyBook) {
  auto w = chassisOnGround(0.4, 0.5, 0.3);
  ASSERT_TRUE(w);
  const auto first = w->momentum().back();
  const double E0 = first.kinetic_energy + first.potential_energy;
  double last_dissipated = 0.0;
  bool touched = false;
  for (int k = 0; k < 2000; ++k) {
    w->step();
    const auto t = w->momentum().back();
    touched = touched || !w->contacts().empty();
    // No inputs: kinetic + potential + dissipated stays the initial energy. The book is exact
    // in contact steps; between them it carries the tree integrator's energy error, which is
    // round-off here (the tree falls without turning its hinge). Measured: 1.2e-13 J of 20 J.
    EXPECT_NEAR(t.kinetic_energy + t.potential_energy + t.dissipated_energy, E0, 1e-11 * E0)
        << "step " << k;
    last_dissipated = t.dissipated_energy;
  }
  EXPECT_TRUE(touched);
  // It fell 0.35 m and came to rest on its base again: the ground took out the energy of the
  // fall (measured to 4e-13 relative; the position correction may leave 5e-5 m of overlap,
  // m g 5e-5 = 3e-6 of it).
  EXPECT_NEAR(last_dissipated, 5.0 * kG * 0.35, 1e-5 * 5.0 * kG * 0.35);
  EXPECT_LT(w->momentum().back().kinetic_energy, 1e-12);
}

// A four-wheeled cart on the ground: a floating chassis with four cylinder wheels on continuous
// joints. Each wheel is driven by the same effort τ; rolling without slipping (μ ample), the
// cart accelerates at a = (4 τ / r) / (m_total + 4 I_w / r²) with I_w = ½ m_w r².
std::string cartUrdf(double M, double mw, double r) {
  const double Iw = 0.5 * mw * r * r, Ie = 0.25 * mw * r * r + mw * 0.04 * 0.04 / 12;
  std::string u =
      "<robot name='cart'>"
      "<link name='chassis'><inertial><mass value='" +
      num(M) +
      "'/><inertia ixx='0.2' iyy='0.3' izz='0.4' ixy='0' ixz='0' iyz='0'/></inertial>"
      "<collision><geometry><box size='0.6 0.3 0.1'/></geometry></collision></link>";
  const double xs[] = {0.25, 0.25, -0.25, -0.25}, ys[] = {0.2, -0.2, 0.2, -0.2};
  for (int k = 0; k < 4; ++k) {
    const std::string w = "wheel" + std::to_string(k);
    u += "<link name='" + w + "'><inertial><mass value='" + num(mw) + "'/><inertia ixx='" +
         num(Ie) + "' iyy='" + num(Iw) + "' izz='" + num(Ie) +
         "' ixy='0' ixz='0' iyz='0'/></inertial>"
         "<collision><origin rpy='1.5707963267948966 0 0'/><geometry><cylinder radius='" +
         num(r) + "' length='0.04'/></geometry></collision></link>" + "<joint name='" + w +
         "_axle' type='continuous'><parent link='chassis'/><child link='" + w + "'/><origin xyz='" +
         num(xs[k]) + " " + num(ys[k]) +
         " -0.05'/><axis xyz='0 1 0'/><limit effort='100' velocity='100'/></joint>";
  }
  return u + "</robot>";
}

TEST(TreeContacts, DrivenCartRollsWithTheAccelerationOfRolling) {
  const double M = 6.0, mw = 0.5, r = 0.1, tau = 0.2;
  scene::ParamValue::Map root, initial;
  // The wheels' centres are 0.05 m below the chassis' origin: the chassis at r + 0.05 puts the
  // wheels on the ground.
  root["position"] = scene::ParamValue(std::vector<scene::ParamValue>{
      scene::ParamValue(0.0), scene::ParamValue(0.0), scene::ParamValue(r + 0.05)});
  initial["chassis"] = scene::ParamValue(root);
  WorldConfig config;
  config.dt = 1e-3;
  GroundPlane plane;
  plane.surface.mu = 1.0;
  config.ground_plane = plane;
  auto w = makeWorld(cartUrdf(M, mw, r), config, scene::ParamValue(initial), {0, 0, -kG});
  ASSERT_TRUE(w);
  JointEffortInput in;
  for (int k = 0; k < 4; ++k) {
    in.names.push_back("wheel" + std::to_string(k) + "_axle");
    in.efforts.push_back(tau);
  }
  ASSERT_TRUE(w->setJointEfforts(in).ok());
  const double T = 1.0;
  for (int k = 0; k < 1000; ++k) w->step();
  const double m_total = M + 4 * mw, Iw = 0.5 * mw * r * r;
  const double a = (4 * tau / r) / (m_total + 4 * Iw / (r * r));
  const auto chassis = w->getBodyState("chassis").value();
  // Rolling: a wheel turning by +θ about y carries its bottom towards −x, so the cart moves +x
  // and ω_wheel = v / r. The contact solve enforces rolling at the velocity level in each step,
  // so the velocity grows by exactly a h per step up to the solver's tolerance, 1e-10 g h per
  // step (measured: 12 digits, also at 3 s).
  EXPECT_NEAR(chassis.linear_velocity.x(), a * T, 1e-9 * a * T);
  EXPECT_NEAR(jointVelocity(*w, "wheel0_axle"), a * T / r, 1e-9 * a * T / r);
  // Level and on the ground: no pitch, no bounce (measured: round-off).
  EXPECT_NEAR(chassis.com.z(), r + 0.05, 1e-9);
  EXPECT_NEAR(chassis.angular_velocity.norm(), 0.0, 1e-9);
  // Rolling dissipates nothing: the kinetic energy is ½ m_eff v² with m_eff = m_total +
  // 4 I_w / r², the height is unchanged, and the book's dissipated energy stays zero.
  const auto t = w->momentum().back();
  const double m_eff = m_total + 4 * Iw / (r * r), v = a * T;
  EXPECT_NEAR(t.kinetic_energy, 0.5 * m_eff * v * v, 1e-9 * 0.5 * m_eff * v * v);
  EXPECT_NEAR(t.dissipated_energy, 0.0, 1e-9 * 0.5 * m_eff * v * v);
  // No slip at the position level either: the chassis moved r θ. (Positions are first order in
  // h while a tree is in contact, as for bodies kicked by the contacts stage: θ = ½ (a/r) T²
  // (1 + h/T) here; the velocities above are exact.)
  const double theta = jointPositionOf(*w, "wheel0_axle");
  EXPECT_NEAR(chassis.com.x(), r * theta, 1e-9);
  EXPECT_NEAR(theta, 0.5 * a / r * T * T * (1 + config.dt / T), 1e-9);
}

// A tree's link never collides with its parent (they overlap at the joint), so a hinge whose
// shapes intersect the parent's still turns freely in the air.
TEST(TreeContacts, LinksJoinedByAJointDoNotCollide) {
  scene::ParamValue::Map root, initial;
  root["angular_velocity"] = scene::ParamValue(std::vector<scene::ParamValue>{
      scene::ParamValue(0.0), scene::ParamValue(0.0), scene::ParamValue(0.0)});
  initial["chassis"] = scene::ParamValue(root);
  scene::ParamValue::Map hinge;
  hinge["velocity"] = scene::ParamValue(1.0);
  initial["flap_hinge"] = scene::ParamValue(hinge);
  auto w = makeWorld(kChassisWithFlap, WorldConfig{}, scene::ParamValue(initial), {0, 0, 0});
  ASSERT_TRUE(w);
  for (int k = 0; k < 100; ++k) w->step();
  EXPECT_TRUE(w->contacts().empty());
  EXPECT_GT(jointPositionOf(*w, "flap_hinge"), 0.05);
}

}  // namespace tree_contacts_test
}  // namespace sim
}  // namespace cga_rigid_sim
