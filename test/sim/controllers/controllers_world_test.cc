// The World's joint controllers (sim/controllers/, doc/control.md#in-the-world) on the 7-DoF arm
// of urdf/arm7.urdf: a group position controller holding the arm against gravity at the
// servo's static equilibrium (against the RNEA's holding torques), a trajectory followed within
// its tolerances to success, commands replayed bit for bit, refused commands leaving the world
// bit-identical, and the bad-input rules.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/world.h"
#include "cga_rigid_sim/tree/articulated_body.h"

namespace cga_rigid_sim {
namespace sim {
namespace controllers_world_test {

using scene::ParamValue;

const std::vector<std::string> kJoints = {"joint1", "joint2", "joint3", "joint4",
                                          "joint5", "joint6", "joint7"};

std::unique_ptr<World> arm() {
  scene::SceneOptions options;
  options.gravity_W = {0, 0, -9.81};
  auto scene =
      scene::loadUrdfFile(std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/arm7.urdf", options);
  EXPECT_TRUE(scene.ok()) << scene.error();
  auto world = World::create(std::move(*scene), WorldConfig{});
  EXPECT_TRUE(world.ok()) << world.error();
  return std::move(*world);
}

ParamValue jointList() {
  ParamValue::List l;
  for (const std::string& j : kJoints) l.emplace_back(j);
  return l;
}

ParamValue controller(const std::string& type) {
  ParamValue::Map c;
  c["type"] = type;
  c["joints"] = jointList();
  return ParamValue(c);
}

ParamValue pidGains(double p, double d) {
  ParamValue::Map m;
  for (const std::string& j : kJoints) {
    ParamValue::Map g;
    g["p"] = p;
    g["d"] = d;
    m[j] = ParamValue(g);
  }
  return ParamValue(m);
}

bool sameBits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

// Held against gravity by PD servos, the arm comes to rest where kp (r − q) equals the torque
// that holds q still — the RNEA's at rest under gravity (an independent algorithm: the servo
// never calls it). Reported efforts are those torques.
TEST(ControllersWorld, GroupPositionServoRestsAtTheStaticEquilibrium) {
  auto world = arm();
  ParamValue::Map yaml;
  yaml["arm_controller"] = controller("position_controllers/JointGroupPositionController");
  const double kp = 4000.0, kd = 150.0;
  auto loaded = world->loadControllers(ParamValue(yaml), {}, pidGains(kp, kd));
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_TRUE(loaded->empty());  // every joint has its gains: no default chosen
  const std::vector<double> r = {0.3, 0.6, -0.2, -1.0, 0.4, 0.5, 0.1};
  ASSERT_TRUE(world->commandGroup("arm_controller", r).ok());
  world->step(8000);  // 8 s: the slowest mode (ζ ≥ 0.5 on the shoulder) has long decayed
  const Model& model = world->model();
  const Data& data = world->data();
  const dynamics::ArticulatedBody& tree = model.trees[0].body;
  const dynamics::TreeState& s = data.trees[0].state;
  dynamics::TreeKinematics kin;
  dynamics::treeKinematics(tree, s, kin);
  dynamics::BodyMoments f;
  dynamics::gravityMoments(tree, kin, {0, 0, -9.81}, f);
  const Eigen::VectorXd hold =
      dynamics::inverseDynamics(tree, s, kin, Eigen::VectorXd::Zero(tree.velocityCount()), f);
  const auto states = world->jointStates();
  for (int k = 0; k < 7; ++k) {
    // At rest to round-off: the residual motion after 8 s is below 1e-9 rad/s; the servo's
    // torque then equals the holding torque to kp·|q̇|·h-level terms and round-off of the
    // RNEA (1e-9 N m on torques up to ~60 N m).
    EXPECT_NEAR(s.v[k], 0.0, 1e-9) << kJoints[k];
    EXPECT_NEAR(kp * (r[k] - s.q[k]), hold[k], 1e-6) << kJoints[k];
    EXPECT_NEAR(states[k].effort, hold[k], 1e-6) << kJoints[k];
  }
}

// <limit velocity> (joint1: 1.71 rad/s) holds a far position command to a ramp at the limit:
// half a second after the command the joint has gone limit·t (less the servo's lag), and it
// never moves faster than the limit by more than the servo's overshoot.
TEST(ControllersWorld, VelocityLimitSaturatesAPositionCommand) {
  auto world = arm();
  ParamValue::Map yaml;
  yaml["arm_controller"] = controller("position_controllers/JointGroupPositionController");
  ASSERT_TRUE(world->loadControllers(ParamValue(yaml), {}, pidGains(4000.0, 150.0)).ok());
  std::vector<double> r(7, 0.0);
  r[0] = 2.5;  // joint1 from 0 to 2.5 rad: 1.46 s at the limit
  ASSERT_TRUE(world->commandGroup("arm_controller", r).ok());
  double fastest = 0.0;
  for (int k = 0; k < 500; ++k) {
    world->step();
    fastest = std::max(fastest, std::abs(world->data().trees[0].state.v[0]));
  }
  const double v_max = 1.71, t = 0.5;
  // The servo follows a ramp with a constant lag ≈ kd·v/kp (0.06 rad here at I ≈ 1 kg m²,
  // less once the transient has passed); 0.1 rad bounds it.
  EXPECT_NEAR(world->data().trees[0].state.q[0], v_max * t, 0.1);
  EXPECT_LT(fastest, 1.05 * v_max);  // ζ ≈ 1: at most a few per cent overshoot
  EXPECT_GT(fastest, 0.9 * v_max);   // and it does reach the limit
}

control::JointTrajectory reach(double start_time) {
  control::JointTrajectory t;
  t.joint_names = kJoints;
  t.start_time = start_time;
  control::TrajectoryPoint mid, end;
  mid.positions = {0.2, 0.3, 0.0, -0.5, 0.2, 0.3, 0.0};
  mid.velocities = {0.2, 0.3, 0.0, -0.5, 0.2, 0.3, 0.0};
  mid.time_from_start = 1.0;
  end.positions = {0.4, 0.6, 0.0, -1.0, 0.4, 0.6, 0.0};
  end.velocities.assign(7, 0.0);
  end.time_from_start = 2.0;
  t.points = {mid, end};
  return t;
}

// A position trajectory controller with stiff default servos (no pid_gains) follows a cubic
// trajectory within its path tolerance and succeeds within its goal tolerance.
TEST(ControllersWorld, TrajectoryIsFollowedWithinItsTolerances) {
  auto world = arm();
  ParamValue::Map c = controller("position_controllers/JointTrajectoryController").asMap();
  ParamValue::Map constraints;
  constraints["goal_time"] = 0.5;
  for (const std::string& j : kJoints) {
    ParamValue::Map tol;
    tol["trajectory"] = 0.01;  // rad while it runs
    tol["goal"] = 0.001;       // rad at the end
    constraints[j] = ParamValue(tol);
  }
  c["constraints"] = ParamValue(constraints);
  ParamValue::Map yaml;
  yaml["arm_controller"] = ParamValue(c);
  auto loaded = world->loadControllers(ParamValue(yaml), {"arm_controller"}, ParamValue());
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(loaded->size(), 7u);  // one default-gains warning per joint
  ASSERT_TRUE(world->commandTrajectory("arm_controller", reach(0.0)).ok());
  double worst = 0.0;
  for (int k = 0; k < 2600; ++k) {
    world->step();
    const auto& st = world->data().controllers.running[0].trajectory->state();
    for (double e : st.error_positions) worst = std::max(worst, std::abs(e));
  }
  const auto& ctrl = *world->data().controllers.running[0].trajectory;
  EXPECT_EQ(ctrl.status(), control::TrajectoryStatus::kSucceeded) << ctrl.reason();
  // The default servo (ω = 500 rad/s) lags a trajectory with accelerations ~1 rad/s² by
  // ~2ζ ṙ/ω + r̈/ω² and gravity by G/(I ω²): well under a milliradian; 0.01 is the tolerance.
  EXPECT_LT(worst, 0.01);
  const Eigen::VectorXd& q = world->data().trees[0].state.q;
  const std::vector<double> last = reach(0.0).points.back().positions;
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(q[k], last[k], 1e-3) << kJoints[k];
}

// The same commands give the same bits; a refused command changes nothing.
TEST(ControllersWorld, CommandsReplayBitForBitAndRefusalsChangeNothing) {
  std::unique_ptr<World> worlds[3] = {arm(), arm(), arm()};
  for (auto& w : worlds) {
    ParamValue::Map yaml;
    yaml["arm_controller"] = controller("effort_controllers/JointTrajectoryController");
    ParamValue::Map gains;
    for (const std::string& j : kJoints) {
      ParamValue::Map g;
      g["p"] = 800.0;
      g["d"] = 40.0;
      g["i"] = 10.0;
      g["i_clamp"] = 5.0;
      gains[j] = ParamValue(g);
    }
    ParamValue::Map c = yaml["arm_controller"].asMap();
    c["gains"] = ParamValue(gains);
    yaml["arm_controller"] = ParamValue(c);
    ASSERT_TRUE(w->loadControllers(ParamValue(yaml), {}, ParamValue()).ok());
    ASSERT_TRUE(w->commandTrajectory("arm_controller", reach(0.2)).ok());
  }
  control::JointTrajectory bad = reach(0.0);
  bad.points[1].positions[3] = std::nan("");
  auto refused = worlds[1]->commandTrajectory("arm_controller", bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.failure().message(),
            "arm_controller/command.points[1].positions[3]: not finite (nan)");
  for (auto& w : worlds) w->step(1500);
  // A replacement half-way (stamped: its step is known, its arrival time does not matter).
  for (auto& w : worlds) ASSERT_TRUE(w->commandTrajectory("arm_controller", reach(1.6)).ok());
  for (auto& w : worlds) w->step(1500);
  const auto& a = worlds[0]->data().trees[0].state;
  for (int i = 1; i < 3; ++i) {
    const auto& b = worlds[i]->data().trees[0].state;
    EXPECT_TRUE(sameBits(a.q, b.q) && sameBits(a.v, b.v)) << i;
  }
}

TEST(ControllersWorld, BadCommandsAndConfigurationsAreRefusedByName) {
  auto world = arm();
  ParamValue::Map yaml;
  yaml["group"] = controller("position_controllers/JointGroupPositionController");
  yaml["traj"] = controller("position_controllers/JointTrajectoryController");
  // Both drive the same joints: the second is refused, and nothing is loaded.
  auto both = world->loadControllers(ParamValue(yaml), {"group", "traj"}, pidGains(100, 10));
  ASSERT_FALSE(both.ok());
  EXPECT_TRUE(world->data().controllers.running.empty());
  ASSERT_TRUE(world->loadControllers(ParamValue(yaml), {"group"}, pidGains(100, 10)).ok());
  EXPECT_EQ(world->commandGroup("nope", {1}).failure().message(),
            "nope/command: no controller 'nope' is running (running: 'group')");
  EXPECT_EQ(world->commandGroup("group", {1, 2}).failure().message(),
            "group/command.data: has 2 values for 7 joints (one per joint, in the order of "
            "group/joints)");
  EXPECT_EQ(world->commandGroup("group", {0, 0, 0, INFINITY, 0, 0, 0}).failure().message(),
            "group/command.data[3]: not finite (inf)");
  EXPECT_FALSE(world->commandTrajectory("group", reach(0)).ok());
  ParamValue::Map unknown;
  unknown["x"] = controller("position_controllers/JointGroupPositionController");
  ParamValue::Map xc = unknown["x"].asMap();
  xc["joints"] = ParamValue(ParamValue::List{ParamValue("elbow_of_nobody")});
  unknown["x"] = ParamValue(xc);
  EXPECT_EQ(world->loadControllers(ParamValue(unknown), {}, ParamValue()).failure().message(),
            "controllers.x.joints[0]: unknown joint 'elbow_of_nobody'");
}

}  // namespace controllers_world_test
}  // namespace sim
}  // namespace cga_rigid_sim
