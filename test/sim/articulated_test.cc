// Articulated trees through the World (doc/articulated.md): URDF → scene → tree stage, with the
// reports users read — joint states, link states, momentum and energy — and the inputs users
// send: held and timed efforts, wrenches and impulses on links, the floating root's state.
#include <gtest/gtest.h>

#include <boost/math/special_functions/ellint_1.hpp>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace sim {
namespace articulated_test {

constexpr double kG = 9.81;

// A rod link of mass m, length ℓ along −z from its frame, radius 2 cm.
std::string exactly(double x) {  // all 17 digits: the URDF carries the number itself
  std::ostringstream os;
  os << std::setprecision(17) << x;
  return os.str();
}

std::string rodLink(const std::string& name, double m, double l) {
  const double r = 0.02, J = m * l * l / 12 + m * r * r / 4, Jz = m * r * r / 2;
  return "<link name='" + name + "'><inertial><origin xyz='0 0 " + exactly(-l / 2) +
         "'/><mass value='" + exactly(m) + "'/><inertia ixx='" + exactly(J) + "' iyy='" +
         exactly(J) + "' izz='" + exactly(Jz) + "' ixy='0' ixz='0' iyz='0'/></inertial></link>";
}

const std::string kDoublePendulum =
    "<robot name='dp'><link name='world'/>" + rodLink("upper", 1.0, 1.0) +
    rodLink("lower", 1.0, 1.0) +
    "<joint name='shoulder' type='continuous'><parent link='world'/><child link='upper'/>"
    "<origin xyz='0 0 2'/><axis xyz='0 1 0'/><limit effort='5' velocity='100'/></joint>"
    "<joint name='elbow' type='continuous'><parent link='upper'/><child link='lower'/>"
    "<origin xyz='0 0 -1'/><axis xyz='0 1 0'/><limit effort='100' velocity='100'/></joint>"
    "</robot>";

std::unique_ptr<World> makeWorld(const std::string& urdf, WorldConfig config = {},
                                 scene::ParamValue initial = {}, Eigen::Vector3d g = {0, 0, -kG}) {
  scene::SceneOptions options;
  options.gravity_W = g;
  options.initial_state = initial;
  auto scene = scene::loadUrdfString(urdf, "test", options);
  EXPECT_TRUE(scene.ok()) << scene.error();
  auto world = World::create(std::move(scene.value()), config);
  EXPECT_TRUE(world.ok()) << world.error();
  return std::move(world.value());
}

scene::ParamValue jointPositions(std::initializer_list<std::pair<const char*, double>> q) {
  scene::ParamValue::Map m;
  for (const auto& [name, value] : q) {
    scene::ParamValue::Map entry;
    entry["position"] = scene::ParamValue(value);
    m[name] = scene::ParamValue(entry);
  }
  return scene::ParamValue(m);
}

double totalEnergy(const World& w) {
  const MomentumReport t = w.momentum().back();
  return t.kinetic_energy + t.potential_energy;
}

TEST(Articulated, DoublePendulumLoadsAsATreeAndKeepsItsEnergy) {
  auto w = makeWorld(kDoublePendulum, {}, jointPositions({{"shoulder", 1.0}, {"elbow", 0.5}}));
  const auto js = w->jointStates();
  ASSERT_EQ(js.size(), 2u);
  EXPECT_EQ(js[0].name, "shoulder");
  EXPECT_EQ(js[0].position, 1.0);
  EXPECT_EQ(js[1].position, 0.5);
  // The elbow sits at the end of the upper rod: 1 m from the shoulder at angle 1 rad about +y
  // (a rotation by +θ about y carries −z towards −x).
  const auto lower = w->getBodyState("lower");
  ASSERT_TRUE(lower.ok());
  const Eigen::Vector3d elbow(-std::sin(1.0), 0, 2 - std::cos(1.0));
  EXPECT_LT((lower->pose_root.translation() - elbow).norm(), 1e-12);
  const double E0 = totalEnergy(*w);
  double worst = 0.0;
  for (int k = 0; k < 10000; ++k) {
    w->step();
    worst = std::max(worst, std::abs(totalEnergy(*w) - E0));
  }
  // The reports' energy (links' kinetic + potential) is the tree's: the symplectic band at
  // h = 1 ms, ≈ 4e-4 J (tree_integrator_test), no drift over 10 s.
  EXPECT_LT(worst, 1e-3);
}

// The large-amplitude period through the whole stack: URDF, initial state, World steps.
TEST(Articulated, PendulumPeriodMatchesTheEllipticIntegral) {
  const std::string urdf =
      "<robot name='p'><link name='world'/>" + rodLink("rod", 1.0, 1.0) +
      "<joint name='hinge' type='revolute'><parent link='world'/><child link='rod'/>"
      "<axis xyz='0 1 0'/><limit lower='-4' upper='4' effort='1' velocity='10'/></joint></robot>";
  WorldConfig config;
  config.integrator = "cga4";
  auto w = makeWorld(urdf, config, jointPositions({{"hinge", 2.0}}));
  const double m = 1.0, l = 1.0, r = 0.02;
  const double Ip = m * l * l / 12 + m * r * r / 4 + m * l * l / 4;
  const double exact = 4 * std::sqrt(Ip / (m * kG * l / 2)) * boost::math::ellint_1(std::sin(1.0));
  std::vector<double> crossings;
  double q_prev = 2.0;
  for (int k = 0; k < 20000 && crossings.size() < 3; ++k) {
    w->step();
    const double q = w->jointStates()[0].position;
    if (q_prev > 0 && q <= 0) crossings.push_back((k + q_prev / (q_prev - q)) * config.dt);
    q_prev = q;
  }
  ASSERT_EQ(crossings.size(), 3u);
  // cga4 at h = 1 ms: phase error ≈ (ωh)⁴ ≈ 1e-11; linear interpolation at θ = 0, O(h³).
  EXPECT_NEAR((crossings[2] - crossings[0]) / 2 / exact, 1.0, 1e-8);
}

TEST(Articulated, HeldEffortIsClampedToTheLimitAndReported) {
  auto w = makeWorld(kDoublePendulum, {}, {}, Eigen::Vector3d::Zero());
  JointEffortInput in;
  in.names = {"shoulder", "elbow"};
  in.efforts = {8.0, -0.5};  // shoulder limit 5 N m
  ASSERT_TRUE(w->setJointEfforts(in).ok());
  w->step(100);
  const auto js = w->jointStates();
  EXPECT_EQ(js[0].effort, 5.0);
  EXPECT_EQ(js[0].clamped_steps, 100u);
  EXPECT_EQ(js[1].effort, -0.5);
  EXPECT_EQ(js[1].clamped_steps, 0u);
  // Work of the efforts = kinetic energy (no gravity, no damping): τ Δq for constant τ. The
  // midpoint keeps a modified energy, O(h²) away from the true one: measured 1.9e-6 relative
  // at h = 1 ms; a wrong effort (the unclamped 8 N m, say) would be off by 60 %.
  const double work = 5.0 * js[0].position + (-0.5) * js[1].position;
  EXPECT_NEAR(w->momentum().back().kinetic_energy, work, 1e-5 * work);
}

TEST(Articulated, BadEffortsAreRefusedByNameWithNothingApplied) {
  auto w = makeWorld(kDoublePendulum);
  JointEffortInput in;
  in.names = {"shoulder", "knee"};
  in.efforts = {1.0, 2.0};
  auto r = w->setJointEfforts(in);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "joint_efforts.name[1]: unknown joint 'knee' (joints: 'elbow', 'shoulder')");
  in.names = {"shoulder", "elbow"};
  in.efforts = {1.0, std::nan("")};
  r = w->setJointEfforts(in);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "joint_efforts.effort[1]: not finite (nan)");
  in.efforts = {1.0};
  EXPECT_FALSE(w->setJointEfforts(in).ok());
  EXPECT_EQ(w->queuedInputCount(), 0u);
  w->step();
  EXPECT_EQ(w->jointStates()[0].effort, 0.0);
  TimedJointEffortInput t;
  t.joint = "elbow";
  t.effort = std::numeric_limits<double>::infinity();
  r = w->applyJointEffort(t);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "apply_joint_effort.effort: not finite (inf)");
  // A NaN start time reached the stamp's conversion to a step number (undefined behaviour,
  // found by fuzz/fuzz_world_inputs.cc under UBSan); it is refused like every other number.
  t.effort = 1.0;
  t.start_time = std::nan("");
  r = w->applyJointEffort(t);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "apply_joint_effort.start_time: not finite (nan)");
  EXPECT_EQ(w->queuedInputCount(), 0u);
}

TEST(Articulated, TimedEffortActsForItsDurationOnly) {
  auto w = makeWorld(kDoublePendulum, {}, {}, Eigen::Vector3d::Zero());
  TimedJointEffortInput t;
  t.joint = "elbow";
  t.effort = 0.3;
  t.duration = 0.01;  // 10 steps
  ASSERT_TRUE(w->applyJointEffort(t).ok());
  w->step(10);
  EXPECT_EQ(w->jointStates()[1].effort, 0.3);
  w->step();
  EXPECT_EQ(w->jointStates()[1].effort, 0.0);
}

// The satellite: a floating root with two hinged panels, in zero gravity. An impulse on a panel
// gives the tree exactly that momentum, which it then keeps while the panels swing.
TEST(Articulated, FloatingTreeTakesAnImpulseAndKeepsItsMomentum) {
  const std::string urdf =
      "<robot name='sat'><link name='bus'><inertial><mass value='100'/><inertia ixx='16.7' "
      "iyy='16.7' izz='16.7' ixy='0' ixz='0' iyz='0'/></inertial></link>"
      "<link name='left'><inertial><origin xyz='-1 0 0'/><mass value='10'/><inertia ixx='0.5337' "
      "iyy='3.3337' izz='3.8667' ixy='0' ixz='0' iyz='0'/></inertial></link>"
      "<link name='right'><inertial><origin xyz='1 0 0'/><mass value='10'/><inertia "
      "ixx='0.5337' iyy='3.3337' izz='3.8667' ixy='0' ixz='0' iyz='0'/></inertial></link>"
      "<joint name='hinge_left' type='revolute'><parent link='bus'/><child link='left'/>"
      "<origin xyz='-0.5 0 0'/><axis xyz='0 1 0'/><limit lower='-1.5' upper='1.5' effort='10' "
      "velocity='1'/></joint>"
      "<joint name='hinge_right' type='revolute'><parent link='bus'/><child link='right'/>"
      "<origin xyz='0.5 0 0'/><axis xyz='0 1 0'/><limit lower='-1.5' upper='1.5' effort='10' "
      "velocity='1'/></joint></robot>";
  auto w = makeWorld(urdf, {}, {}, Eigen::Vector3d::Zero());
  ImpulseInput imp;
  imp.body = "right";
  imp.frame = "right";
  imp.J.f = {0, 0, 2.0};
  imp.point = {1.5, 0.1, 0};
  ASSERT_TRUE(w->applyImpulse(imp).ok());
  w->step();
  const MomentumReport P0 = w->momentum().back();
  // The impulse in world axes at the start (the panel's frame is the world's at q = 0).
  EXPECT_LT((P0.linear - Eigen::Vector3d(0, 0, 2.0)).norm(), 1e-12);
  EXPECT_LT((P0.angular_origin - Eigen::Vector3d(0.5 + 1.5, 0.1, 0).cross(Eigen::Vector3d(0, 0, 2)))
                .norm(),
            1e-12);
  double worst = 0.0;
  for (int k = 0; k < 3000; ++k) {
    w->step();
    const MomentumReport P = w->momentum().back();
    worst = std::max(worst,
                     (P.linear - P0.linear).norm() + (P.angular_origin - P0.angular_origin).norm());
  }
  // Π is carried exactly; the reported sum over links differs by round-off only.
  EXPECT_LT(worst, 1e-12);
  EXPECT_NE(w->jointStates()[1].velocity, 0.0);  // the panel does swing
}

// Momentum per tree: a floating satellite and a pendulum hinged to the world share a scene in
// zero gravity. The pendulum's hinge pushes on it, so the scene's total momentum changes as it
// swings; the satellite's own entry (kTreePrefix + its root) is conserved, and every tree entry
// is the sum of its bodies' entries, ordered after the bodies and before the total.
TEST(Articulated, MomentumIsReportedPerTree) {
  const std::string urdf =
      "<robot name='two'><link name='world'/>" + rodLink("upper", 1.0, 1.0) +
      "<joint name='shoulder' type='continuous'><parent link='world'/><child link='upper'/>"
      "<origin xyz='0 0 2'/><axis xyz='0 1 0'/></joint>"
      "<link name='bus'><inertial><mass value='100'/><inertia ixx='16.7' iyy='16.7' izz='16.7' "
      "ixy='0' ixz='0' iyz='0'/></inertial></link>"
      "<joint name='bus_free' type='floating'><parent link='world'/><child link='bus'/>"
      "<origin xyz='5 0 0'/></joint>"
      "<link name='panel'><inertial><origin xyz='1 0 0'/><mass value='10'/><inertia ixx='0.5337' "
      "iyy='3.3337' izz='3.8667' ixy='0' ixz='0' iyz='0'/></inertial></link>"
      "<joint name='hinge' type='continuous'><parent link='bus'/><child link='panel'/>"
      "<origin xyz='0.5 0 0'/><axis xyz='0 1 0'/></joint></robot>";
  scene::ParamValue::Map initial, shoulder, hinge, bus;
  shoulder["velocity"] = scene::ParamValue(2.0);
  hinge["velocity"] = scene::ParamValue(1.0);
  bus["angular_velocity"] = scene::ParamValue(std::vector<scene::ParamValue>{
      scene::ParamValue(0.1), scene::ParamValue(0.0), scene::ParamValue(0.3)});
  initial["shoulder"] = scene::ParamValue(shoulder);
  initial["hinge"] = scene::ParamValue(hinge);
  initial["bus"] = scene::ParamValue(bus);
  auto w = makeWorld(urdf, {}, scene::ParamValue(initial), Eigen::Vector3d::Zero());
  const auto find = [](const std::vector<MomentumReport>& m, const std::string& name) {
    for (const auto& r : m)
      if (r.body == name) return r;
    ADD_FAILURE() << "no entry " << name;
    return MomentumReport();
  };
  const auto m0 = w->momentum();
  // upper, bus, panel, then the trees in model order (the pendulum's joint comes first), total.
  ASSERT_EQ(m0.size(), 6u);
  EXPECT_EQ(m0[3].body, std::string(kTreePrefix) + "upper");
  EXPECT_EQ(m0[4].body, std::string(kTreePrefix) + "bus");
  EXPECT_EQ(m0[3].kind, MomentumReport::Kind::kTree);
  EXPECT_EQ(m0.back().kind, MomentumReport::Kind::kTotal);
  const MomentumReport sat0 = find(m0, "tree:bus");
  double worst_tree = 0.0, total_change = 0.0;
  for (int k = 0; k < 2000; ++k) {
    w->step();
    const auto m = w->momentum();
    const MomentumReport sat = find(m, "tree:bus");
    // The sum of its bodies' entries (the same numbers added in the same order).
    const MomentumReport bus_r = find(m, "bus"), panel_r = find(m, "panel");
    EXPECT_EQ(sat.linear, bus_r.linear + panel_r.linear);
    EXPECT_EQ(sat.kinetic_energy, bus_r.kinetic_energy + panel_r.kinetic_energy);
    worst_tree = std::max(worst_tree, (sat.linear - sat0.linear).norm() +
                                          (sat.angular_origin - sat0.angular_origin).norm());
    total_change = std::max(total_change, (m.back().linear - m0.back().linear).norm());
  }
  // Free in zero gravity: the midpoint carries the satellite's momentum exactly (round-off of
  // the sum over links, as in FloatingTreeTakesAnImpulseAndKeepsItsMomentum).
  EXPECT_LT(worst_tree, 1e-11);
  // The pendulum's hinge changes the total's linear momentum by ~m ω ℓ/2 ≈ 1 kg m/s: the
  // per-tree entry is what shows the satellite's conservation.
  EXPECT_GT(total_change, 0.1);
}

TEST(Articulated, ClearWrenchesEndsTimedEffortsButNotHeldOnes) {
  auto w = makeWorld(kDoublePendulum, {}, {}, Eigen::Vector3d::Zero());
  JointEffortInput held;
  held.names = {"shoulder"};
  held.efforts = {0.2};
  ASSERT_TRUE(w->setJointEfforts(held).ok());
  TimedJointEffortInput t;
  t.joint = "shoulder";
  t.effort = 0.5;
  t.duration = -1.0;  // until cleared
  ASSERT_TRUE(w->applyJointEffort(t).ok());
  w->step(5);
  EXPECT_EQ(w->jointStates()[0].effort, 0.7);
  w->clearWrenches();
  w->step();
  EXPECT_EQ(w->jointStates()[0].effort, 0.2);
  // Larger than max_force: refused like a wrench would be.
  t.effort = 2e6;
  const auto r = w->applyJointEffort(t);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(),
            "apply_joint_effort.effort: |effort| = 2000000 N m (or N) exceeds max_force = 1000000 "
            "N m (or N)");
}

TEST(Articulated, StateEditsRespectTheTree) {
  auto w = makeWorld(kDoublePendulum);
  auto r = w->setBodyState("lower", Eigen::Isometry3d::Identity(), {0, 0, 0}, {0, 0, 0});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("is moved by joint 'elbow'"), std::string::npos) << r.error();
  EXPECT_FALSE(w->deleteBody("upper").ok());
  w->step(500);
  w->reset();
  EXPECT_EQ(w->jointStates()[0].position, 0.0);
  EXPECT_EQ(w->jointStates()[0].velocity, 0.0);
}

TEST(Articulated, ExactIsRefusedForScenesWithJoints) {
  scene::SceneOptions options;
  auto scene = scene::loadUrdfString(kDoublePendulum, "test", options);
  ASSERT_TRUE(scene.ok());
  WorldConfig config;
  config.integrator = "exact";
  auto w = World::create(std::move(scene.value()), config);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.error().find("no form for articulated trees"), std::string::npos) << w.error();
}

}  // namespace articulated_test
}  // namespace sim
}  // namespace cga_rigid_sim
