// Contacts inside an articulated tree keep the physics (doc/contacts.md#trees,
// doc/articulated.md#faults): a contact between two links of one tree is an equal and opposite
// impulse pair through the tree's mass matrix, so a floating tree's momentum changes only by
// gravity and its inputs; the energy never rises beyond their work; no joint passes its limits;
// positions keep integrating. The robots are of this repository's own (test/common/
// real_like_robots.h): a humanoid-like floating tree of mesh links whose limbs swing into each
// other, an arm whose links two joints apart overlap at the zero pose, a gripper closing on its
// own fingers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"
#include "common/real_like_robots.h"

namespace cga_rigid_sim {
namespace sim {
namespace tree_self_contact_test {

std::unique_ptr<World> makeWorld(const std::string& urdf, const Eigen::Vector3d& g,
                                 scene::ParamValue initial = {}, WorldConfig config = {}) {
  scene::SceneOptions options;
  options.gravity_W = g;
  options.initial_state = std::move(initial);
  auto scene = scene::loadUrdfString(urdf, "robot", options);
  EXPECT_TRUE(scene.ok()) << scene.error();
  if (!scene.ok()) return nullptr;
  auto w = World::create(std::move(scene.value()), config);
  EXPECT_TRUE(w.ok()) << w.error();
  return w.ok() ? std::move(w.value()) : nullptr;
}

scene::ParamValue jointRates(const std::vector<std::pair<std::string, double>>& rates) {
  scene::ParamValue::Map m;
  for (const auto& [joint, v] : rates) {
    scene::ParamValue::Map entry;
    entry["velocity"] = scene::ParamValue(v);
    m[joint] = scene::ParamValue(entry);
  }
  return scene::ParamValue(m);
}

const MomentumReport& total(const std::vector<MomentumReport>& m) { return m.back(); }

int selfContacts(const World& w, const std::string& ground = "ground_plane") {
  int n = 0;
  for (const ContactReport& c : w.contacts()) n += c.body_b != ground ? 1 : 0;
  return n;
}

// Zero gravity: the humanoid's arms and thighs swing into its torso and each other at 3 rad/s.
// Its contacts with itself are its only contacts, so its linear momentum (zero) and its angular
// momentum about the world origin stay as they were, to round-off of the links' momenta (the
// kick's solve, the carried momentum): 1e-12 of their scale, ~kg m/s. Its energy never rises
// (e = 0: every impact dissipates) and the book balances to the midpoint's own energy error,
// measured by a second run of the same tree with its self-contacts off (none: it swings through
// itself), ten times that.
TEST(TreeSelfContact, FloatingTreeKeepsItsMomentumThroughSelfContacts) {
  const std::string dir = test::meshFolder("humanoid_zero_g");
  const auto rates = jointRates({{"l_upper_arm_joint", 3.0},
                                 {"r_upper_arm_joint", -3.0},
                                 {"l_thigh_joint", 2.0},
                                 {"r_thigh_joint", -2.0},
                                 {"l_fore_arm_joint", 4.0},
                                 {"torso_joint", -1.0}});
  WorldConfig none;
  none.self_collision = scene::SelfCollisionMode::kNone;
  auto free = makeWorld(test::humanoidUrdf(dir), Eigen::Vector3d::Zero(), rates, none);
  ASSERT_TRUE(free);
  const double T0 = total(free->momentum()).kinetic_energy;
  double integrator_error = 0.0;
  for (int k = 0; k < 10000; ++k) {
    free->step();
    const auto m = total(free->momentum());
    integrator_error =
        std::max(integrator_error, std::abs(m.kinetic_energy + m.dissipated_energy - T0));
  }
  auto w = makeWorld(test::humanoidUrdf(dir), Eigen::Vector3d::Zero(), rates);
  ASSERT_TRUE(w);
  const auto m0 = total(w->momentum());
  double scale = 0.0;  // the links' momenta
  for (const auto& m : w->momentum())
    if (m.body != "total" && m.body.rfind("tree:", 0) != 0) scale += m.linear.norm();
  ASSERT_GT(scale, 1.0);
  double E_prev = m0.kinetic_energy;
  int contact_steps = 0;
  double worst_P = 0.0, worst_L = 0.0, worst_rise = 0.0;
  for (int k = 0; k < 10000; ++k) {
    w->step();
    contact_steps += selfContacts(*w) > 0 ? 1 : 0;
    const auto m = total(w->momentum());
    worst_P = std::max(worst_P, (m.linear - m0.linear).norm());
    worst_L = std::max(worst_L, (m.angular_origin - m0.angular_origin).norm());
    worst_rise = std::max(worst_rise, m.kinetic_energy - E_prev);
    E_prev = m.kinetic_energy;
  }
  EXPECT_GT(contact_steps, 50) << "the limbs must meet";
  EXPECT_LT(worst_P, 1e-12 * scale);
  EXPECT_LT(worst_L, 1e-12 * scale);
  // Between contacts the midpoint keeps the energy to its own oscillation (~1e-9 of it at these
  // rates); contacts only take.
  EXPECT_LT(worst_rise, 1e-7 * m0.kinetic_energy);
  const auto m = total(w->momentum());
  EXPECT_NEAR(m.kinetic_energy + m.dissipated_energy, m0.kinetic_energy,
              10 * integrator_error + 1e-12 * m0.kinetic_energy);
  EXPECT_LT(m.kinetic_energy, m0.kinetic_energy);
  EXPECT_EQ(w->treeFaultCount(), 0u) << (w->lastTreeFault() ? w->lastTreeFault()->message() : "");
  std::printf(
      "[ info ] humanoid, zero g, 10 s: %d steps with self-contacts, |dP| %.1e, |dL| %.1e "
      "(scale %.1f kg m/s), largest one-step energy rise %.1e J of %.2f J, book %.1e J "
      "(the midpoint's own error %.1e J)\n",
      contact_steps, worst_P, worst_L, scale, worst_rise, m0.kinetic_energy,
      std::abs(m.kinetic_energy + m.dissipated_energy - m0.kinetic_energy), integrator_error);
}

// The arm whose palm overlaps its upper arm at the zero pose, under gravity, kicked at random
// three times, with every pair of its links colliding (`all`: the overlapping pair too, the
// hardest case — an overlap its joints may not be able to resolve): over 10 s no joint passes
// its limits (every integrator and the contact stage keep it within, to round-off: 1e-9 rad),
// a joint that moves moves (no step leaves a moving joint where it was), and the energy book
// balances: kinetic + potential + dissipated stays the initial energy to the midpoint's own
// energy error (measured on the same arm without contacts: up to 1.4e-4 J of ~20 J swings;
// bound 1e-3 J), faults none.
TEST(TreeSelfContact, RandomlyKickedArmKeepsLimitsAndBalancesItsEnergy) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  const double limit = 2.0;
  for (int run = 0; run < 3; ++run) {
    WorldConfig all;
    all.self_collision = scene::SelfCollisionMode::kAll;
    auto w = makeWorld(test::overlappingArmUrdf(0.01, limit), {0, 0, -9.81},
                       jointRates({{"j1", u(rng)}, {"j2", u(rng)}, {"j3", u(rng)}, {"j4", u(rng)}}),
                       all);
    ASSERT_TRUE(w);
    const auto m0 = total(w->momentum());
    const double E0 = m0.kinetic_energy + m0.potential_energy;
    std::vector<JointStateReport> last = w->jointStates();
    double worst_balance = 0.0, worst_past = 0.0;
    int contact_steps = 0, frozen = 0;
    for (int k = 0; k < 10000; ++k) {
      w->step();
      contact_steps += selfContacts(*w) > 0 ? 1 : 0;
      const auto m = total(w->momentum());
      worst_balance = std::max(worst_balance, std::abs(m.kinetic_energy + m.potential_energy +
                                                       m.dissipated_energy - E0));
      const auto joints = w->jointStates();
      for (std::size_t j = 0; j < joints.size(); ++j) {
        worst_past = std::max(worst_past, std::abs(joints[j].position) - limit);
        const bool at_limit = limit - std::abs(joints[j].position) < 1e-9;
        if (!at_limit && std::abs(last[j].velocity) > 1e-3 && std::abs(joints[j].velocity) > 1e-3 &&
            joints[j].position == last[j].position)
          ++frozen;
      }
      last = joints;
    }
    EXPECT_GT(contact_steps, 0) << "run " << run << ": its links must meet";
    EXPECT_LE(worst_past, 1e-9) << "run " << run;
    EXPECT_EQ(frozen, 0) << "run " << run;
    EXPECT_LT(worst_balance, 1e-3) << "run " << run;
    EXPECT_EQ(w->treeFaultCount(), 0u) << (w->lastTreeFault() ? w->lastTreeFault()->message() : "");
    std::printf(
        "[ info ] arm run %d: %d contact steps, energy book within %.1e J, limits within "
        "%.1e rad\n",
        run, contact_steps, worst_balance, std::max(0.0, worst_past));
  }
}

// A gripper closes on its own fingers with 5 N on each: they meet in the middle (their inner
// faces 6 cm apart, 3 cm of travel each) and stay there, touching, without passing through each
// other or their limits (4 cm), at rest. Energy: the efforts' work, 5 N × Δq on each finger, is
// the kinetic energy left plus what the contact dissipated; and while the fingers hold, nothing
// more is dissipated (their efforts do no work).
TEST(TreeSelfContact, GripperClosesOnItsOwnFingers) {
  auto w = makeWorld(test::gripperUrdf(), {0, 0, -9.81});
  ASSERT_TRUE(w);
  JointEffortInput close;
  close.names = {"left_finger_joint", "right_finger_joint"};
  close.efforts = {5.0, 5.0};
  ASSERT_TRUE(w->setJointEfforts(close).ok());
  w->step(1000);
  const double held_from = total(w->momentum()).dissipated_energy;
  w->step(1000);
  const auto joints = w->jointStates();
  ASSERT_EQ(joints.size(), 2u);
  for (const auto& j : joints) {
    // The fingers meet at 3 cm of travel; the contact's slop (50 µm) and speculative margin
    // leave them within 0.1 mm of it.
    EXPECT_NEAR(j.position, 0.03, 1e-4) << j.name;
    EXPECT_LT(std::abs(j.velocity), 1e-6) << j.name;
  }
  int finger_contacts = 0;
  for (const ContactReport& c : w->contacts())
    finger_contacts += (c.body_a == "left_finger" && c.body_b == "right_finger") ||
                       (c.body_a == "right_finger" && c.body_b == "left_finger");
  EXPECT_GT(finger_contacts, 0);
  const auto m = total(w->momentum());
  const double work = 5.0 * (joints[0].position + joints[1].position);
  // The book's work is trapezoidal in the rates, ½ h τ (ν + ν') a step, while a contact step's
  // positions are first order (q' = q + h ν'): the two differ by ½ h τ Σ|Δν| ≤ ½ h τ (2 v_max)
  // per finger over the closing, with v_max < 1.5 m/s (the fingers reach ~1.2 m/s), so 1.5e-2 J
  // for the pair bounds it; a phantom input while holding would exceed it within 200 steps.
  EXPECT_NEAR(m.kinetic_energy + m.dissipated_energy, work, 2 * 0.5 * 1e-3 * 5.0 * 2 * 1.5);
  // Holding: 1000 steps pressed together dissipate nothing (the solver's round-off).
  EXPECT_NEAR(m.dissipated_energy, held_from, 1e-12);
  EXPECT_EQ(w->treeFaultCount(), 0u) << (w->lastTreeFault() ? w->lastTreeFault()->message() : "");
}

// The explicit integrators conserve a floating tree's momentum only to their truncation, in a
// contact step's drift as anywhere: their self-contact steps must not be refused for it (on a
// published humanoid every contact step of `euler` was, freezing it). The impulses still cancel:
// the momentum wanders only as far as the same integrator takes it with self-collision off
// (measured in a second run; twice that, plus round-off).
TEST(TreeSelfContact, ExplicitIntegratorsStepSelfContactsWithoutFaults) {
  const std::string dir = test::meshFolder("humanoid_explicit");
  const auto rates = jointRates({{"l_upper_arm_joint", 3.0},
                                 {"r_upper_arm_joint", -3.0},
                                 {"l_thigh_joint", 2.0},
                                 {"r_thigh_joint", -2.0}});
  for (const char* integrator : {"euler", "rk4"}) {
    const auto drift = [&](scene::SelfCollisionMode mode, int* contact_steps) {
      WorldConfig config;
      config.integrator = integrator;
      config.self_collision = mode;
      auto w = makeWorld(test::humanoidUrdf(dir), Eigen::Vector3d::Zero(), rates, config);
      EXPECT_TRUE(w);
      if (!w) return 0.0;
      const auto m0 = total(w->momentum());
      double worst = 0.0;
      for (int k = 0; k < 3000; ++k) {
        w->step();
        if (contact_steps) *contact_steps += selfContacts(*w) > 0 ? 1 : 0;
        const auto m = total(w->momentum());
        worst = std::max(
            {worst, (m.linear - m0.linear).norm(), (m.angular_origin - m0.angular_origin).norm()});
      }
      EXPECT_EQ(w->treeFaultCount(), 0u)
          << integrator << ": " << (w->lastTreeFault() ? w->lastTreeFault()->message() : "");
      return worst;
    };
    int contact_steps = 0;
    const double with = drift(scene::SelfCollisionMode::kAuto, &contact_steps);
    const double without = drift(scene::SelfCollisionMode::kNone, nullptr);
    EXPECT_GT(contact_steps, 50) << integrator << ": the limbs must meet";
    EXPECT_LT(with, 2 * without + 1e-10) << integrator;
    std::printf("[ info ] %s: %d self-contact steps, momentum drift %.1e (without contacts %.1e)\n",
                integrator, contact_steps, with, without);
  }
}

// 300 boxes placed overlapping on the ground plane: the World starts with a summary of the
// overlaps (a count and the five deepest, not a line per pair: 44 850 lines and 68 s of start
// before), and the heap settles without ever gaining energy.
TEST(TreeSelfContact, OverlappingHeapStartsWithASummaryAndSettles) {
  std::string urdf = "<robot name='heap'><link name='world'/>";
  for (int i = 0; i < 300; ++i) {
    const std::string name = "box" + std::to_string(i);
    urdf += "<link name='" + name + "'>" + test::boxInertial(1.0, {0.2, 0.2, 0.2}) +
            test::boxCollision({0.2, 0.2, 0.2}) + "</link><joint name='" + name +
            "_free' type='floating'><parent link='world'/><child link='" + name + "'/></joint>";
  }
  urdf += "</robot>";
  scene::ParamValue::Map initial;
  for (int i = 0; i < 300; ++i) {
    scene::ParamValue::Map entry;
    // A 10 × 10 grid of columns of three, 0.15 m apart: each box overlaps its neighbours by 5 cm.
    entry["position"] = scene::ParamValue(std::vector<scene::ParamValue>{
        scene::ParamValue(0.15 * (i % 10)), scene::ParamValue(0.15 * ((i / 10) % 10)),
        scene::ParamValue(0.1 + 0.15 * (i / 100))});
    initial["box" + std::to_string(i)] = scene::ParamValue(entry);
  }
  WorldConfig config;
  config.ground_plane = GroundPlane{};
  auto w = makeWorld(urdf, {0, 0, -9.81}, scene::ParamValue(initial), config);
  ASSERT_TRUE(w);
  int overlap_lines = 0;
  for (const auto& line : w->scene().warnings)
    overlap_lines += line.find("overlap") != std::string::npos;
  EXPECT_EQ(overlap_lines, 6);  // the count, then the five deepest
  EXPECT_NE(w->scene().warnings.front().find("pairs of bodies overlap by more than"),
            std::string::npos)
      << w->scene().warnings.front();
  const auto m0 = total(w->momentum());
  double E_prev = m0.kinetic_energy + m0.potential_energy;
  for (int k = 0; k < 200; ++k) {
    w->step();
    const auto m = total(w->momentum());
    // A contact solve never adds energy; the overlap's separation is paid from kinetic energy.
    EXPECT_LE(m.kinetic_energy + m.potential_energy, E_prev + 1e-9 * std::abs(E_prev)) << k;
    E_prev = m.kinetic_energy + m.potential_energy;
  }
}

}  // namespace tree_self_contact_test
}  // namespace sim
}  // namespace cga_rigid_sim
