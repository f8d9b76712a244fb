// Mimic joints through the World (doc/articulated.md#mimic-joints): published-style grippers
// loaded from URDF, driven by joint efforts, pushed by impulses, in contact with the ground. The
// constraint q_f = m q_l + o holds to round-off through every stage of the step; the truths are
// the URDF's limits, the energy book of the contacts and the constraint itself.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace sim {
namespace mimic_world_test {

namespace fs = std::filesystem;
const fs::path kRobots = fs::path(CGA_RIGID_SIM_SOURCE_DIR) / "test/scene/robots";
constexpr double kG = 9.81;

// The World of a loaded scene (null, with the failure reported, if either step fails).
std::unique_ptr<World> worldOf(Result<scene::Scene> scene, const WorldConfig& config) {
  if (!scene.ok()) {
    ADD_FAILURE() << scene.error();
    return nullptr;
  }
  auto world = World::create(std::move(*scene), config);
  if (!world.ok()) ADD_FAILURE() << world.error();
  return world.ok() ? std::move(*world) : nullptr;
}

std::unique_ptr<World> load(const std::string& file, const WorldConfig& config = {}) {
  return worldOf(scene::loadUrdfFile(file, scene::SceneOptions()), config);
}

std::map<std::string, JointStateReport> joints(const World& w) {
  std::map<std::string, JointStateReport> out;
  for (const auto& j : w.jointStates()) out[j.name] = j;
  return out;
}

// |q_f − (m q_l + o)| and |q̇_f − m q̇_l| relative to the scale of m q_l + o: a few ulps.
void expectHeld(const World& w, const std::string& follower, const std::string& leader, double m,
                double o, const std::string& what) {
  const auto js = joints(w);
  const auto& f = js.at(follower);
  const auto& l = js.at(leader);
  const double eps = std::numeric_limits<double>::epsilon();
  EXPECT_LE(std::abs(f.position - (m * l.position + o)),
            2 * eps * std::max(std::abs(m * l.position), std::abs(o)))
      << what << ": " << follower << " " << f.position << " leader " << l.position;
  EXPECT_LE(std::abs(f.velocity - m * l.velocity), 2 * eps * std::abs(m * l.velocity))
      << what << ": " << follower << " rate " << f.velocity << " leader " << l.velocity;
}

// The gripper closes under an effort on its first finger: both fingers move together to their
// upper limit 0.04 m and stay there, in every integrator; the palm's two finger joints (both on
// the static palm) are one tree.
TEST(MimicWorld, AGripperClosesWithBothFingersAndStopsAtTheLimit) {
  for (const char* integrator : {"auto", "cga4", "rk4", "euler"}) {
    WorldConfig config;
    config.integrator = integrator;
    auto w = load((kRobots / "gripper_mimic.urdf").string(), config);
    ASSERT_TRUE(w);
    ASSERT_TRUE(w->setJointEfforts({{"finger_joint1"}, {5.0}, 0.0}).ok());
    double highest = 0.0;
    for (int k = 0; k < 1000; ++k) {
      w->step();
      highest = std::max(highest, joints(*w).at("finger_joint2").position);
      if (k % 50 == 0) expectHeld(*w, "finger_joint2", "finger_joint1", 1.0, 0.0, integrator);
    }
    EXPECT_LE(highest, 0.04) << integrator;
    // At the stop (cga4: within ½ a (γ2 h)² ≈ 2e-4 m, a = 125 m/s² the push: the triple
    // jump's middle substep, γ2 = −1.70, runs backwards from the stop a first substep reached).
    EXPECT_NEAR(joints(*w).at("finger_joint1").position, 0.04,
                std::string(integrator) == "cga4" ? 2.5e-4 : 1e-12)
        << integrator;
    EXPECT_EQ(w->treeFaultCount(), 0u) << integrator;
  }
}

// An effort on the follower acts on the pair through the multiplier, and an impulse on a
// follower's link moves the pair within the constraint.
TEST(MimicWorld, EffortsAndImpulsesOnFollowersMoveThePairWithinTheConstraint) {
  auto w = load((kRobots / "knuckle_gripper.urdf").string());
  ASSERT_TRUE(w);
  // An impulse on a follower's link (the left fingertip, pushed across its hinge) from rest.
  ImpulseInput in;
  in.body = "distal_left";
  in.frame = "distal_left";
  in.point = Eigen::Vector3d(0, 0, -0.02);
  in.J = cga::Force(Eigen::Vector3d(0, 0.02, 0), 0.0);
  ASSERT_TRUE(w->applyImpulse(in).ok());
  w->step();
  EXPECT_NE(joints(*w).at("knuckle_left").velocity, 0.0);
  expectHeld(*w, "tip_left", "knuckle_left", -1.0, 0.1, "impulse");
  expectHeld(*w, "tip_right", "knuckle_left", 1.0, -0.1, "impulse");
  w->reset();
  expectHeld(*w, "tip_left", "knuckle_left", -1.0, 0.1, "reset");
  EXPECT_EQ(joints(*w).at("tip_left").position, 0.1);
  ASSERT_TRUE(w->setJointEfforts({{"tip_right"}, {0.05}, 0.0}).ok());
  for (int k = 0; k < 200; ++k) w->step();
  // tip_right = knuckle_left − 0.1: a positive effort on it turns the leader positive too.
  EXPECT_GT(joints(*w).at("knuckle_left").position, 0.0);
  expectHeld(*w, "tip_right", "knuckle_left", 1.0, -0.1, "effort");
  expectHeld(*w, "knuckle_right", "knuckle_left", -1.0, 0.0, "effort");
  expectHeld(*w, "tip_left", "knuckle_left", -1.0, 0.1, "effort");
}

std::string num(double x) {
  std::ostringstream os;
  os << std::setprecision(17) << x;
  return os.str();
}

// A gear pair of pendulums on the ground plane: the follower's bob (m = −2) swings into the
// ground. The contact goes through the pair's one coordinate; the energy book closes and the
// constraint holds through every contact step.
TEST(MimicWorld, AFollowerInContactKeepsTheConstraintAndTheEnergyBook) {
  const auto bob = [](const std::string& name, double m, double r, double L) {
    const double J = 0.4 * m * r * r;
    return "<link name='" + name + "'><inertial><origin xyz='0 0 " + num(-L) + "'/><mass value='" +
           num(m) + "'/><inertia ixx='" + num(J) + "' iyy='" + num(J) + "' izz='" + num(J) +
           "' ixy='0' ixz='0' iyz='0'/></inertial><collision><origin xyz='0 0 " + num(-L) +
           "'/><geometry><sphere radius='" + num(r) + "'/></geometry></collision></link>";
  };
  const std::string urdf =
      "<robot name='gears'><link name='world'/>" + bob("leader_arm", 1.0, 0.05, 0.5) +
      bob("follower_arm", 0.5, 0.05, 0.55) +
      "<joint name='lead' type='continuous'><parent link='world'/><child link='leader_arm'/>"
      "<origin xyz='0 0 1'/><axis xyz='0 1 0'/></joint>"
      "<joint name='follow' type='continuous'><parent link='world'/><child link='follower_arm'/>"
      "<origin xyz='0 0.5 0.6'/><axis xyz='0 1 0'/><mimic joint='lead' multiplier='-2' "
      "offset='0.4'/></joint></robot>";
  WorldConfig config;
  config.ground_plane = GroundPlane{};
  auto w = worldOf(scene::loadUrdfString(urdf, "test", scene::SceneOptions()), config);
  ASSERT_TRUE(w);
  const auto first = w->momentum().back();
  const double E0 = first.kinetic_energy + first.potential_energy;
  int contact_steps = 0;
  for (int k = 0; k < 2000; ++k) {
    w->step();
    contact_steps += w->contacts().empty() ? 0 : 1;
    expectHeld(*w, "follow", "lead", -2.0, 0.4, "step " + std::to_string(k));
    const auto t = w->momentum().back();
    // No inputs: kinetic + potential + dissipated stays E0, up to the integrator's band between
    // contacts (the symplectic band of this swing, ≈ 1e-4 J at h = 1 ms, of 5 J).
    EXPECT_NEAR(t.kinetic_energy + t.potential_energy + t.dissipated_energy, E0, 1e-3)
        << "step " << k;
  }
  EXPECT_GT(contact_steps, 0);
  EXPECT_GT(w->momentum().back().dissipated_energy, 0.0);
  EXPECT_EQ(w->treeFaultCount(), 0u);
}

}  // namespace mimic_world_test
}  // namespace sim
}  // namespace cga_rigid_sim
