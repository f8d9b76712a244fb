// validate(): each rule of a trajectory command refused with the field and the rule, and a
// command that keeps every rule accepted (the truth is the rule list in joint_trajectory.h).
#include "cga_rigid_sim/control/joint_trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

namespace cga_rigid_sim {
namespace control {
namespace joint_trajectory_test {

JointTrajectory good() {
  JointTrajectory t;
  t.joint_names = {"j1", "j2"};
  t.points.resize(2);
  t.points[0].positions = {0, 1};
  t.points[0].time_from_start = 0;
  t.points[1].positions = {1, 2};
  t.points[1].velocities = {0, 0};
  t.points[1].accelerations = {0, 0};
  t.points[1].effort = {1, 1};
  t.points[1].time_from_start = 0.5;
  return t;
}

TEST(ValidateTrajectory, AcceptsAGoodOneAndAnEmptyOne) {
  EXPECT_TRUE(validate(good()).ok()) << validate(good()).error();
  JointTrajectory empty = good();
  empty.points.clear();
  EXPECT_TRUE(validate(empty).ok());
}

TEST(ValidateTrajectory, RefusesEachBrokenRuleNamingTheField) {
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    const char* field;
    std::function<void(JointTrajectory&)> edit;
  };
  const Case cases[] = {
      {"joint_names", [](JointTrajectory& t) { t.joint_names.clear(); }},
      {"joint_names[1]", [](JointTrajectory& t) { t.joint_names[1] = ""; }},
      {"joint_names[1]", [](JointTrajectory& t) { t.joint_names[1] = "j1"; }},
      {"header.stamp", [](JointTrajectory& t) { t.start_time = -1; }},
      {"header.stamp", [](JointTrajectory& t) { t.start_time = NAN; }},
      {"points[0].positions", [](JointTrajectory& t) { t.points[0].positions = {0}; }},
      {"points[0].positions", [](JointTrajectory& t) { t.points[0].positions.clear(); }},
      {"points[1].velocities",
       [](JointTrajectory& t) {
         t.points[1].velocities = {0, 0, 0};
       }},
      {"points[1].accelerations", [](JointTrajectory& t) { t.points[1].accelerations = {0}; }},
      {"points[1].effort", [](JointTrajectory& t) { t.points[1].effort = {0}; }},
      {"points[0].positions[1]", [](JointTrajectory& t) { t.points[0].positions[1] = NAN; }},
      {"points[1].velocities[0]", [&](JointTrajectory& t) { t.points[1].velocities[0] = inf; }},
      {"points[1].accelerations[1]",
       [](JointTrajectory& t) { t.points[1].accelerations[1] = NAN; }},
      {"points[1].effort[0]", [](JointTrajectory& t) { t.points[1].effort[0] = NAN; }},
      {"points[0].time_from_start", [](JointTrajectory& t) { t.points[0].time_from_start = -0.1; }},
      {"points[1].time_from_start", [&](JointTrajectory& t) { t.points[1].time_from_start = inf; }},
      {"points[1].time_from_start", [](JointTrajectory& t) { t.points[1].time_from_start = 0; }},
  };
  for (const Case& c : cases) {
    JointTrajectory t = good();
    c.edit(t);
    const Result<bool> r = validate(t);
    ASSERT_FALSE(r.ok()) << c.field;
    EXPECT_EQ(r.failure().input, "command");
    EXPECT_EQ(r.failure().field, c.field) << r.error();
    EXPECT_FALSE(r.failure().rule.empty());
  }
}

}  // namespace joint_trajectory_test
}  // namespace control
}  // namespace cga_rigid_sim
