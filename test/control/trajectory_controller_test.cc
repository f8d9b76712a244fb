// The trajectory controller against joint_trajectory_controller's documented semantics. The
// truths are the commanded points themselves (a linear segment's value is the interpolation of
// its ends), the controller's state at the instants the rules name, and the stop trajectory's
// closed form derived in doc/control.md#holding. Tolerance 1e-12 as in trajectory_spline_test.
#include "cga_rigid_sim/control/trajectory_controller.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cga_rigid_sim {
namespace control {
namespace trajectory_controller_test {

constexpr double kTol = 1e-12;

// Controller joints "a", "b" at indices 2 and 0 of a 3-joint vector.
TrajectoryControllerOptions options() {
  TrajectoryControllerOptions o;
  o.name = "arm";
  o.joint_names = {"a", "b"};
  o.joint_indices = {2, 0};
  return o;
}

TrajectoryPoint point(double t, std::vector<double> q, std::vector<double> v = {}) {
  TrajectoryPoint p;
  p.positions = std::move(q);
  p.velocities = std::move(v);
  p.time_from_start = t;
  return p;
}

JointTrajectory trajectory(std::vector<TrajectoryPoint> points, double stamp = 0,
                           std::vector<std::string> names = {"a", "b"}) {
  JointTrajectory t;
  t.joint_names = std::move(names);
  t.start_time = stamp;
  t.points = std::move(points);
  return t;
}

const std::vector<double> kQ = {0.5, 9.0, -1.0};  // a = −1, b = 0.5
const std::vector<double> kRest = {0, 0, 0};

TrajectoryController make(TrajectoryControllerOptions o = options()) {
  auto c = TrajectoryController::create(std::move(o), 0.0, kQ);
  EXPECT_TRUE(c.ok()) << c.error();
  return *c;
}

TEST(TrajectoryController, StartsHoldingWhereTheJointsAre) {
  TrajectoryController c = make();
  EXPECT_EQ(c.status(), TrajectoryStatus::kHolding);
  EXPECT_EQ(c.update(3.0, kQ, kRest), TrajectoryStatus::kHolding);
  EXPECT_EQ(c.state().desired_positions, (std::vector<double>{-1.0, 0.5}));
  EXPECT_EQ(c.state().error_positions, (std::vector<double>{0.0, 0.0}));
}

TEST(TrajectoryController, StampZeroIsNowAndNamesMayComeInAnyOrder) {
  TrajectoryController c = make();
  // Commanded at now = 2 with stamp 0: points at 3 and 4; names reversed (b, a).
  auto r = c.command(trajectory({point(1, {1, 3}), point(2, {2, 5})}, 0, {"b", "a"}), 2.0, kQ,
                     kRest, false);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(*r, 0);
  c.update(2.5, kQ, kRest);  // linear from (2, a = −1, b = 0.5) to (3, a = 3, b = 1)
  EXPECT_NEAR(c.desired(0).position, 1.0, kTol);
  EXPECT_NEAR(c.desired(1).position, 0.75, kTol);
  c.update(3.5, kQ, kRest);
  EXPECT_NEAR(c.desired(0).position, 4.0, kTol);
  EXPECT_NEAR(c.desired(1).velocity, 1.0, kTol);
  EXPECT_EQ(c.update(4.5, kQ, kRest), TrajectoryStatus::kSucceeded);
  EXPECT_NEAR(c.desired(0).position, 5.0, kTol);
  EXPECT_EQ(c.desired(0).velocity, 0.0);
}

TEST(TrajectoryController, AFutureStartLetsTheCurrentTrajectoryRunUntilThen) {
  TrajectoryController c = make();
  ASSERT_TRUE(c.command(trajectory({point(2, {1, 2.5})}), 0.0, kQ, kRest, false).ok());
  // A second command at now = 0.5 starting at 1.5: until 1.5 the first runs (linear a: −1 → 1,
  // b: 0.5 → 2.5 over [0, 2]); from 1.5 a bridge to the new point at 2.5.
  ASSERT_TRUE(c.command(trajectory({point(1, {0, 0})}, 1.5), 0.5, kQ, kRest, false).ok());
  c.update(1.0, kQ, kRest);
  EXPECT_NEAR(c.desired(0).position, 0.0, kTol);
  EXPECT_NEAR(c.desired(1).position, 1.5, kTol);
  c.update(1.5, kQ, kRest);
  EXPECT_NEAR(c.desired(0).position, 0.5, kTol);
  c.update(2.0, kQ, kRest);  // linear from (1.5, 0.5) to (2.5, 0): 0.25
  EXPECT_NEAR(c.desired(0).position, 0.25, kTol);
  EXPECT_NEAR(c.endTime(), 2.5, kTol);
}

TEST(TrajectoryController, ReplacementStartsFromTheDesiredStateNotTheActual) {
  TrajectoryController c = make();
  ASSERT_TRUE(c.command(trajectory({point(2, {1, 2.5}, {0, 0})}), 0.0, kQ, kRest, false).ok());
  c.update(1.0, kQ, kRest);
  const JointSample before = c.desired(0);
  // Replaced at now = 1 with an actual far away (+10): the new spline starts from `before`.
  const std::vector<double> far = {10.5, 0, 9.0};
  ASSERT_TRUE(c.command(trajectory({point(1, {0, 0}, {0, 0})}), 1.0, far, kRest, false).ok());
  EXPECT_NEAR(c.desired(0).position, before.position, kTol);
  EXPECT_NEAR(c.desired(0).velocity, before.velocity, kTol);
  EXPECT_NE(before.velocity, 0.0);
}

TEST(TrajectoryController, PointsAlreadyPastAreDroppedAndAllPastIsRefused) {
  TrajectoryController c = make();
  // Stamp 1, now 2: points at 1.5 and 2.0 are past (≤ now), the one at 3 is kept.
  auto r = c.command(trajectory({point(0.5, {0, 0}), point(1.0, {1, 1}), point(2.0, {3, 3})}, 1),
                     2.0, kQ, kRest, false);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(*r, 2);
  c.update(2.5, kQ, kRest);  // linear from the hold (a = −1) at 2 to 3 at 3
  EXPECT_NEAR(c.desired(0).position, 1.0, kTol);
  // Every point past: refused naming `points`; the current trajectory runs on.
  auto past = c.command(trajectory({point(0.5, {7, 7})}, 1), 2.5, kQ, kRest, false);
  ASSERT_FALSE(past.ok());
  EXPECT_EQ(past.failure().field, "points");
  c.update(2.75, kQ, kRest);
  EXPECT_NEAR(c.desired(0).position, 2.0, kTol);
}

TEST(TrajectoryController, AnEmptyTrajectoryHoldsTheActualPosition) {
  TrajectoryController c = make();
  ASSERT_TRUE(c.command(trajectory({point(2, {1, 2.5})}), 0.0, kQ, kRest, false).ok());
  const std::vector<double> q = {0.7, 0, 0.3};
  ASSERT_TRUE(c.command(trajectory({}), 1.0, q, kRest).ok());
  EXPECT_EQ(c.status(), TrajectoryStatus::kHolding);
  c.update(5.0, q, kRest);
  EXPECT_EQ(c.desired(0).position, 0.3);
  EXPECT_EQ(c.desired(1).position, 0.7);
  EXPECT_EQ(c.desired(0).velocity, 0.0);
}

TEST(TrajectoryController, AStopTrajectoryComesToRestAsJointTrajectoryControllerDoes) {
  TrajectoryControllerOptions o = options();
  o.stop_trajectory_duration = 0.4;
  TrajectoryController c = make(o);
  ASSERT_TRUE(c.command(trajectory({point(2, {1, 2.5})}), 0.0, kQ, kRest, false).ok());
  c.update(1.0, kQ, kRest);
  const JointSample d = c.desired(0);  // a: q = 0, q̇ = 1
  ASSERT_TRUE(c.command(trajectory({}), 1.0, kQ, kRest).ok());
  // Second method: the midpoint of the quintic from (q, v, 0) to (q, −v, 0) over 2T.
  SplineKnot s, e;
  s.time = 1.0, s.position = d.position, s.velocity = d.velocity;
  e.time = 1.8, e.position = d.position, e.velocity = -d.velocity;
  s.has_velocity = s.has_acceleration = e.has_velocity = e.has_acceleration = true;
  const JointSample mid = SplineSegment::between(s, e).at(1.4);
  c.update(1.4, kQ, kRest);
  EXPECT_NEAR(c.desired(0).position, mid.position, kTol);
  EXPECT_NEAR(c.desired(0).position, d.position + 5.0 / 8.0 * d.velocity * 0.4, kTol);
  EXPECT_NEAR(c.desired(0).velocity, 0.0, kTol);
  c.update(1.2, kQ, kRest);
  EXPECT_GT(c.desired(0).velocity, 0.0);  // still slowing down
}

TEST(TrajectoryController, PathToleranceAbortsAndHoldsTheActualPosition) {
  TrajectoryControllerOptions o = options();
  o.constraints.joints = {{0.1, 0}, {0, 0}};
  TrajectoryController c = make(o);
  ASSERT_TRUE(c.command(trajectory({point(2, {1, 2.5})}), 0.0, kQ, kRest).ok());
  // At t = 1 desired a = 0; an actual of −0.05 is within 0.1, −0.2 is not.
  std::vector<double> q = {1.5, 0, -0.05};
  EXPECT_EQ(c.update(1.0, q, kRest), TrajectoryStatus::kExecuting);
  q[2] = -0.2;
  EXPECT_EQ(c.update(1.0, q, kRest), TrajectoryStatus::kAborted);
  EXPECT_NE(c.reason().find("'a'"), std::string::npos) << c.reason();
  EXPECT_NE(c.reason().find("constraints.a.trajectory"), std::string::npos) << c.reason();
  c.update(1.5, kQ, kRest);
  EXPECT_EQ(c.desired(0).position, -0.2);
  EXPECT_EQ(c.desired(1).position, 1.5);
}

TEST(TrajectoryController, GoalToleranceWaitsGoalTimeThenAborts) {
  TrajectoryControllerOptions o = options();
  o.constraints.goal_time = 0.5;
  o.constraints.joints = {{0, 0.01}, {0, 0}};
  TrajectoryController c = make(o);
  ASSERT_TRUE(c.command(trajectory({point(2, {1, 2.5})}), 0.0, kQ, kRest).ok());
  const std::vector<double> off = {2.5, 0, 1.05};                      // a 0.05 short of its goal
  EXPECT_EQ(c.update(2.2, off, kRest), TrajectoryStatus::kExecuting);  // within goal_time
  EXPECT_EQ(c.update(2.5, off, kRest), TrajectoryStatus::kAborted);    // end + goal_time
  EXPECT_NE(c.reason().find("constraints.a.goal"), std::string::npos) << c.reason();
  // Reached within the grace: succeeded.
  ASSERT_TRUE(c.command(trajectory({point(1, {1, 2.5})}), 3.0, kQ, kRest).ok());
  EXPECT_EQ(c.update(4.1, off, kRest), TrajectoryStatus::kExecuting);
  const std::vector<double> on = {2.5, 0, 1.005};
  EXPECT_EQ(c.update(4.2, on, kRest), TrajectoryStatus::kSucceeded);
}

TEST(TrajectoryController, StoppedVelocityToleranceWithoutGraceAbortsAtTheEnd) {
  TrajectoryController c = make();  // stopped_velocity_tolerance 0.01, goal_time 0
  ASSERT_TRUE(c.command(trajectory({point(1, {1, 2})}), 0.0, kQ, kRest).ok());
  const std::vector<double> q = {2, 0, 1}, moving = {0, 0, 0.05};
  EXPECT_EQ(c.update(1.0, q, moving), TrajectoryStatus::kAborted);
  EXPECT_NE(c.reason().find("stopped_velocity_tolerance"), std::string::npos) << c.reason();
  // Unchecked (the topic interface): the same end succeeds.
  ASSERT_TRUE(c.command(trajectory({point(1, {1, 2})}), 2.0, kQ, kRest, false).ok());
  EXPECT_EQ(c.update(3.0, q, moving), TrajectoryStatus::kSucceeded);
}

TEST(TrajectoryController, JointsAreCheckedAgainstTheController) {
  TrajectoryController c = make();
  auto unknown = c.command(trajectory({point(1, {0, 0})}, 0, {"a", "z"}), 0.0, kQ, kRest);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.failure().field, "joint_names[1]");
  auto partial = c.command(trajectory({point(1, {0})}, 0, {"b"}), 0.0, kQ, kRest);
  ASSERT_FALSE(partial.ok());
  EXPECT_EQ(partial.failure().field, "joint_names");
  EXPECT_NE(partial.failure().rule.find("allow_partial_joints_goal"), std::string::npos);
  // Allowed: the joint left out keeps its trajectory.
  TrajectoryControllerOptions o = options();
  o.allow_partial_joints_goal = true;
  TrajectoryController p = make(o);
  ASSERT_TRUE(p.command(trajectory({point(2, {1, 2.5})}), 0.0, kQ, kRest, false).ok());
  ASSERT_TRUE(p.command(trajectory({point(1, {0})}, 0, {"b"}), 1.0, kQ, kRest, false).ok());
  p.update(1.5, kQ, kRest);
  EXPECT_NEAR(p.desired(0).position, 0.5, kTol);   // a: still −1 → 1 over [0, 2]
  EXPECT_NEAR(p.desired(1).position, 0.75, kTol);  // b: from 1.5 at 1 to 0 at 2
}

TEST(TrajectoryController, BadCommandsAndOptionsAreRefusedNamingTheField) {
  TrajectoryController c = make();
  auto bad = c.command(trajectory({point(1, {0, NAN})}), 0.0, kQ, kRest);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.failure().field, "points[0].positions[1]");
  TrajectoryControllerOptions o = options();
  o.constraints.joints = {{-1, 0}, {0, 0}};
  auto r = TrajectoryController::create(o, 0, kQ);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.failure().field, "arm.constraints.a.trajectory");
  o = options();
  o.joint_indices = {2, 3};
  EXPECT_FALSE(TrajectoryController::create(o, 0, kQ).ok());
}

}  // namespace trajectory_controller_test
}  // namespace control
}  // namespace cga_rigid_sim
