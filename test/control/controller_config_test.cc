// The ros_control YAML reader on the structure of a real arm's gazebo controllers file (a UR-style
// setup: joint_state_controller, an effort trajectory controller with gains and constraints, a
// position group controller with gazebo_ros_control pid_gains), every bad-input rule, the
// mapping onto the servo law (each coefficient derived by hand in controller_config.h), and
// control_toolbox's integral clamp. Values are exact decimals read back, so equality is exact
// unless a product is formed (then 1e-12, a few ulps of ≤ 1e4).
#include "cga_rigid_sim/control/controller_config.h"

#include <gtest/gtest.h>

#include <functional>

namespace cga_rigid_sim {
namespace control {
namespace controller_config_test {

using scene::ParamValue;
using Map = ParamValue::Map;
using List = ParamValue::List;

const List kArm = {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint"};

// As rosparam loads a controllers YAML of an arm in Gazebo (our own values).
ParamValue armNamespace() {
  return Map{
      {"joint_state_controller",
       Map{{"type", "joint_state_controller/JointStateController"}, {"publish_rate", 125}}},
      {"eff_joint_traj_controller",
       Map{{"type", "effort_controllers/JointTrajectoryController"},
           {"joints", kArm},
           {"gains",
            Map{{"shoulder_pan_joint", Map{{"p", 3000}, {"d", 150}, {"i", 2}, {"i_clamp", 5}}},
                {"shoulder_lift_joint", Map{{"p", 8000}, {"d", 150}, {"i", 1}, {"i_clamp", 1}}},
                {"elbow_joint", Map{{"p", 2500},
                                    {"d", 25},
                                    {"i", 1},
                                    {"i_clamp_min", -2},
                                    {"i_clamp_max", 3},
                                    {"antiwindup", true}}}}},
           {"velocity_ff", Map{{"shoulder_pan_joint", 1.0}}},
           {"constraints", Map{{"goal_time", 0.6},
                               {"stopped_velocity_tolerance", 0.05},
                               {"shoulder_pan_joint", Map{{"trajectory", 0.2}, {"goal", 0.1}}},
                               {"elbow_joint", Map{{"goal", 0.05}}}}},
           {"stop_trajectory_duration", 0.5},
           {"state_publish_rate", 125},
           {"action_monitor_rate", 10}}},
      {"gripper_controller", Map{{"type", "position_controllers/JointGroupPositionController"},
                                 {"joints", List{"finger_joint"}}}},
      {"gazebo_ros_control", Map{{"pid_gains", Map{{"finger_joint", Map{{"p", 200}, {"d", 4}}}}}}},
  };
}

TEST(ControllerConfig, ReadsARealArmSetup) {
  auto set = parseControllers(armNamespace());
  ASSERT_TRUE(set.ok()) << set.error();
  EXPECT_TRUE(set->warnings.empty()) << set->warnings.front();
  ASSERT_EQ(set->controllers.size(), 3u);             // gazebo_ros_control is not a controller
  const ControllerConfig& arm = set->controllers[0];  // by name: eff_… < gripper_… < joint_…
  EXPECT_EQ(arm.name, "eff_joint_traj_controller");
  EXPECT_EQ(arm.type, ControllerType::kEffortTrajectory);
  EXPECT_EQ(arm.joints.size(), 3u);
  EXPECT_EQ(arm.joints[2], "elbow_joint");
  EXPECT_EQ(arm.gains.at("shoulder_pan_joint").p, 3000);
  EXPECT_EQ(arm.gains.at("shoulder_pan_joint").i_clamp_min, -5);
  EXPECT_EQ(arm.gains.at("shoulder_pan_joint").i_clamp_max, 5);
  EXPECT_EQ(arm.gains.at("elbow_joint").i_clamp_min, -2);
  EXPECT_EQ(arm.gains.at("elbow_joint").i_clamp_max, 3);
  EXPECT_TRUE(arm.gains.at("elbow_joint").antiwindup);
  EXPECT_EQ(arm.constraints.goal_time, 0.6);
  EXPECT_EQ(arm.constraints.stopped_velocity_tolerance, 0.05);
  EXPECT_EQ(arm.constraints.joints.at("shoulder_pan_joint").trajectory, 0.2);
  EXPECT_EQ(arm.constraints.joints.at("elbow_joint").goal, 0.05);
  EXPECT_EQ(arm.constraints.joints.count("shoulder_lift_joint"), 0u);
  EXPECT_EQ(arm.stop_trajectory_duration, 0.5);
  EXPECT_EQ(arm.publish_rate, 125);
  EXPECT_EQ(arm.action_monitor_rate, 10);
  EXPECT_EQ(set->controllers[2].type, ControllerType::kJointState);
  EXPECT_EQ(set->controllers[2].publish_rate, 125);

  // The `~controllers` list picks and orders.
  auto some = parseControllers(armNamespace(), {"joint_state_controller", "gripper_controller"});
  ASSERT_TRUE(some.ok()) << some.error();
  ASSERT_EQ(some->controllers.size(), 2u);
  EXPECT_EQ(some->controllers[1].type, ControllerType::kGroupPosition);
}

TEST(ControllerConfig, MapsEveryTypeOntoTheServoLaw) {
  auto set = parseControllers(armNamespace());
  ASSERT_TRUE(set.ok());
  auto pid = parsePidGains(armNamespace().asMap().at("gazebo_ros_control").asMap().at("pid_gains"));
  ASSERT_TRUE(pid.ok()) << pid.error();
  // Effort trajectory: the PID of `gains`, velocity_ff as the feedforward on ṙ.
  auto e = servoGains(set->controllers[0], "shoulder_pan_joint", pid->gains);
  ASSERT_TRUE(e.ok()) << e.error();
  EXPECT_EQ(e->interface, JointInterface::kEffort);
  EXPECT_EQ(e->kp, 3000);
  EXPECT_EQ(e->kd, 150);
  EXPECT_EQ(e->ki, 2);
  EXPECT_EQ(e->kff_velocity, 1.0);
  // Group position: pid_gains.
  auto g = servoGains(set->controllers[1], "finger_joint", pid->gains);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_EQ(g->interface, JointInterface::kPosition);
  EXPECT_EQ(g->kp, 200);
  EXPECT_EQ(g->kd, 4);
  // A position joint without pid_gains is refused naming where its gains go.
  auto none = servoGains(set->controllers[1], "finger_joint", {});
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.failure().rule.find("gazebo_ros_control/pid_gains/finger_joint"),
            std::string::npos);
  // Velocity trajectory: v = ff ṙ + p e + d ė + i∫e on τ = P (v − q̇), P = 20, p = 5, d = 0.5,
  // i = 0.25, ff = 0 (the default): kp = 100, kd = 30, ki = 5, kff = −20.
  ControllerConfig v;
  v.name = "vel";
  v.type = ControllerType::kVelocityTrajectory;
  v.joints = {"w"};
  v.gains["w"] = PidGains{5, 0.25, 0.5, -1, 1, false};
  std::map<std::string, PidGains> servo = {{"w", PidGains{20, 0, 0, 0, 0, false}}};
  auto vs = servoGains(v, "w", servo);
  ASSERT_TRUE(vs.ok()) << vs.error();
  EXPECT_NEAR(vs->kp, 100, 1e-12);
  EXPECT_NEAR(vs->kd, 30, 1e-12);
  EXPECT_NEAR(vs->ki, 5, 1e-12);
  EXPECT_NEAR(vs->kff_velocity, -20, 1e-12);
  EXPECT_NEAR(vs->i_clamp_max, 20, 1e-12);
  // Check by substitution: τ = P (v − q̇) at e = 0.1, ė = −0.2, ṙ = 0.3 (so q̇ = 0.5), no ∫.
  const double e0 = 0.1, ed = -0.2, rd = 0.3, qd = rd - ed;
  const double tau_truth = 20 * (0 * rd + 5 * e0 + 0.5 * ed - qd);
  EXPECT_NEAR(vs->kp * e0 + vs->kd * ed + vs->kff_velocity * rd, tau_truth, 1e-12);
  // Group velocity: τ = P (v − q̇); a velocity servo with i is refused.
  v.type = ControllerType::kGroupVelocity;
  EXPECT_EQ(servoGains(v, "w", servo)->kd, 20);
  EXPECT_EQ(servoGains(v, "w", servo)->kp, 0);
  servo["w"].i = 1;
  EXPECT_FALSE(servoGains(v, "w", servo).ok());
  // Group effort: nothing but the commanded effort.
  v.type = ControllerType::kGroupEffort;
  EXPECT_EQ(servoGains(v, "w", {})->kp, 0);
}

TEST(ControllerConfig, RefusesEachBadInputNamingControllerFieldAndRule) {
  struct Case {
    const char* field;
    std::function<void(Map&)> edit;
  };
  // Sets one key of the arm controller (ParamValue shares its maps: edit a copy, put it back).
  auto setArm = [](Map& ns, const std::string& key, ParamValue value) {
    Map a = ns.at("eff_joint_traj_controller").asMap();
    a[key] = std::move(value);
    ns["eff_joint_traj_controller"] = a;
  };
  const Case cases[] = {
      {"eff_joint_traj_controller.type",
       [&](Map& ns) {
         ns["eff_joint_traj_controller"] = Map{{"type", "foo/Bar"}, {"joints", kArm}};
       }},
      {"joint_state_controller.publish_rate",
       [](Map& ns) {
         ns["joint_state_controller"] =
             Map{{"type", "joint_state_controller/JointStateController"}};
       }},
      {"joint_state_controller.publish_rate",
       [](Map& ns) {
         ns["joint_state_controller"] =
             Map{{"type", "joint_state_controller/JointStateController"}, {"publish_rate", -5}};
       }},
      {"gripper_controller.joints",
       [](Map& ns) {
         ns["gripper_controller"] =
             Map{{"type", "position_controllers/JointGroupPositionController"}};
       }},
      {"gripper_controller.joints",
       [](Map& ns) {
         ns["gripper_controller"] =
             Map{{"type", "position_controllers/JointGroupPositionController"}, {"joints", List{}}};
       }},
      {"gripper_controller.joints[1]",
       [](Map& ns) {
         ns["gripper_controller"] =
             Map{{"type", "position_controllers/JointGroupPositionController"},
                 {"joints", List{"f", "f"}}};
       }},
      {"gripper_controller.joints[0]",
       [](Map& ns) {
         ns["gripper_controller"] =
             Map{{"type", "position_controllers/JointGroupPositionController"},
                 {"joints", List{"elbow_joint"}}};
       }},
      {"eff_joint_traj_controller.gains.elbow_joint.p",
       [&](Map& ns) {
         setArm(ns, "gains",
                Map{{"shoulder_pan_joint", Map{{"p", 1}}}, {"shoulder_lift_joint", Map{{"p", 1}}}});
       }},
      {"eff_joint_traj_controller.gains.elbow_joint.d",
       [&](Map& ns) {
         setArm(ns, "gains", Map{{"elbow_joint", Map{{"p", 1}, {"d", -3}}}});
       }},
      {"eff_joint_traj_controller.gains.elbow_joint.p",
       [&](Map& ns) {
         setArm(ns, "gains", Map{{"elbow_joint", Map{{"p", "high"}}}});
       }},
      {"eff_joint_traj_controller.constraints.goal_time",
       [&](Map& ns) {
         setArm(ns, "constraints", Map{{"goal_time", -1}});
       }},
      {"eff_joint_traj_controller.constraints.elbow_joint.trajectory",
       [&](Map& ns) {
         setArm(ns, "constraints", Map{{"elbow_joint", Map{{"trajectory", -0.1}}}});
       }},
      {"eff_joint_traj_controller.state_publish_rate",
       [&](Map& ns) { setArm(ns, "state_publish_rate", 0); }},
      {"eff_joint_traj_controller.allow_partial_joints_goal",
       [&](Map& ns) { setArm(ns, "allow_partial_joints_goal", 1); }},
  };
  for (const Case& c : cases) {
    Map ns = armNamespace().asMap();  // a new tree of maps each time
    c.edit(ns);
    auto r = parseControllers(ns);
    ASSERT_FALSE(r.ok()) << c.field;
    EXPECT_EQ(r.failure().input, "controllers");
    EXPECT_EQ(r.failure().field, c.field) << r.error();
  }
  // A controller named in ~controllers but absent; a type list in the refusal.
  auto absent = parseControllers(armNamespace(), {"arm_controller"});
  ASSERT_FALSE(absent.ok());
  EXPECT_EQ(absent.failure().field, "arm_controller");
  Map ns = armNamespace().asMap();
  ns["eff_joint_traj_controller"] = Map{{"type", "foo/Bar"}, {"joints", kArm}};
  auto unsupported = parseControllers(ns);
  ASSERT_FALSE(unsupported.ok());
  EXPECT_NE(unsupported.failure().rule.find("velocity_controllers/JointGroupVelocityController"),
            std::string::npos);
}

TEST(ControllerConfig, WarnsOfKeysItDoesNotRead) {
  Map ns = armNamespace().asMap();
  Map a = ns.at("eff_joint_traj_controller").asMap();
  a["hold_tolerance"] = 0.1;
  ns["eff_joint_traj_controller"] = a;
  ns["robot_hw"] = Map{{"loop_hz", 500}};
  auto set = parseControllers(ns);
  ASSERT_TRUE(set.ok()) << set.error();
  ASSERT_EQ(set->warnings.size(), 2u);
  // Entries that are not controllers first, then each controller's keys.
  EXPECT_NE(set->warnings[0].find("robot_hw"), std::string::npos) << set->warnings[0];
  EXPECT_NE(set->warnings[1].find("hold_tolerance"), std::string::npos) << set->warnings[1];
}

TEST(PidIntegral, ClampsTheTermAndWithAntiwindupTheIntegral) {
  // i = 2, clamp ±1: after 1 s of e = 1 at dt = 0.1, ∫e = 1 and i∫e = 2 → term clamped to 1.
  PidGains g{0, 2, 0, -1, 1, false};
  PidIntegral w;
  for (int k = 0; k < 10; ++k) w.accumulate(1.0, 0.1, g);
  EXPECT_EQ(w.term(g), 1.0);
  EXPECT_NEAR(w.integral(), 1.0, 1e-15);  // wound up past the clamp (0.5)
  // Then e = −1 for 0.5 s: without antiwindup ∫e = 0.5, term still at the clamp 1; with
  // antiwindup ∫e was held at 0.5, now 0, term 0.
  for (int k = 0; k < 5; ++k) w.accumulate(-1.0, 0.1, g);
  EXPECT_EQ(w.term(g), 1.0);
  g.antiwindup = true;
  PidIntegral a;
  for (int k = 0; k < 10; ++k) a.accumulate(1.0, 0.1, g);
  EXPECT_NEAR(a.integral(), 0.5, 1e-15);
  for (int k = 0; k < 5; ++k) a.accumulate(-1.0, 0.1, g);
  EXPECT_NEAR(a.term(g), 0.0, 1e-15);
}

}  // namespace controller_config_test
}  // namespace control
}  // namespace cga_rigid_sim
