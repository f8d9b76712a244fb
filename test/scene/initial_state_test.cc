// The initial-state dictionary (doc/initial_state.md): each key form sets what it says, read back
// through the stored state (M_WB0, Ω_B0) with the relations of doc/conventions.md — root link pose
// M_WR = M_WB0 M_BR, centre-of-mass velocity v_W = R_WB v_B, w_W = R_WB w_B — and each error names
// the body and the key and leaves the scene unchanged.
//
// Test body: urdf/t_handle.urdf, whose body frame B is neither at the root link's origin
// (centre of mass at z = 0.15) nor along its axes (principal axes permuted), so every
// conversion between root link, body and world frames is exercised. Tolerance 1e-14: a few
// rotations of numbers ≤ 10 (ε ≈ 2e-16 each).
#include "cga_rigid_sim/scene/initial_state.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace initial_state_test {

constexpr double kTol = 1e-14;
const std::string kFile = std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/t_handle.urdf";

using Map = ParamValue::Map;
using List = ParamValue::List;

Scene loadTHandle(double lambda = 1.0) {
  SceneOptions o;
  o.lambda = lambda;
  auto s = loadUrdfFile(kFile, o);
  EXPECT_TRUE(s.ok()) << s.error();
  return *s;
}

ParamValue vec(double x, double y, double z) { return List{x, y, z}; }
ParamValue state(const std::string& key, ParamValue v) {
  return Map{{"shaft", Map{{key, std::move(v)}}}};
}

struct Readback {
  Eigen::Vector3d x_WR;
  Eigen::Quaterniond q_WR;
  Eigen::Vector3d v_W, w_W;
};

Readback readBack(const Scene& s) {
  const BodyModel& b = s.bodies.at(0);
  const cga::Motor M_WR = b.M_WB0 * b.links.at(0).M_BL;
  const Eigen::Quaterniond q_WB = b.M_WB0.rotation();
  return {M_WR.translation(s.lambda), M_WR.rotation(), q_WB * b.omega_B0.linear(s.lambda),
          q_WB * b.omega_B0.angular()};
}

void expectNear(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), kTol) << a.transpose() << " vs " << b.transpose();
}
void expectSameRotation(Eigen::Quaterniond a, const Eigen::Quaterniond& b) {
  if (a.coeffs().dot(b.coeffs()) < 0) a.coeffs() = -a.coeffs();  // double cover
  EXPECT_LT((a.coeffs() - b.coeffs()).cwiseAbs().maxCoeff(), kTol);
}

TEST(InitialState, NoneKeepsTheUrdfPoseAtRest) {
  Scene s = loadTHandle();
  ASSERT_TRUE(applyInitialState(s, ParamValue()).ok());
  const Readback r = readBack(s);
  expectNear(r.x_WR, Eigen::Vector3d(0, 0, 1));  // the floating joint's origin
  expectSameRotation(r.q_WR, Eigen::Quaterniond::Identity());
  expectNear(r.v_W, Eigen::Vector3d::Zero());
  expectNear(r.w_W, Eigen::Vector3d::Zero());
  ASSERT_TRUE(applyInitialState(s, Map{}).ok());  // an empty map too
}

TEST(InitialState, PositionMovesTheRootLinkOrigin) {
  Scene s = loadTHandle();
  ASSERT_TRUE(applyInitialState(s, state("position", vec(1, -2, 3))).ok());
  const Readback r = readBack(s);
  expectNear(r.x_WR, Eigen::Vector3d(1, -2, 3));
  expectSameRotation(r.q_WR, Eigen::Quaterniond::Identity());
  // The centre of mass is 0.15 above the root link origin along the root link's z.
  expectNear(s.bodies[0].M_WB0.translation(s.lambda), Eigen::Vector3d(1, -2, 3.15));
}

TEST(InitialState, OrientationQuaternionXyzw) {
  Scene s = loadTHandle();
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -1, 2).normalized()));
  ASSERT_TRUE(applyInitialState(s, state("orientation", List{q.x(), q.y(), q.z(), q.w()})).ok());
  const Readback r = readBack(s);
  expectSameRotation(r.q_WR, q);
  expectNear(r.x_WR, Eigen::Vector3d(0, 0, 1));  // position kept
}

TEST(InitialState, NearlyUnitQuaternionIsNormalised) {
  Scene s = loadTHandle();
  const double k = 1.0 + 5e-7;  // within 1e-6 of unit
  ASSERT_TRUE(applyInitialState(
                  s, state("orientation", List{0.0, 0.0, k * std::sqrt(0.5), k * std::sqrt(0.5)}))
                  .ok());
  expectSameRotation(readBack(s).q_WR, Eigen::Quaterniond(Eigen::AngleAxisd(
                                           std::acos(-1.0) / 2, Eigen::Vector3d::UnitZ())));
}

TEST(InitialState, RpyIsFixedAxisRollPitchYaw) {
  Scene s = loadTHandle();
  ASSERT_TRUE(applyInitialState(s, state("rpy", vec(0.1, -0.2, 0.3))).ok());
  const Eigen::Quaterniond expected = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX());
  expectSameRotation(readBack(s).q_WR, expected);
}

TEST(InitialState, WorldAxisVelocities) {
  for (double lambda : {1.0, 7.3}) {
    Scene s = loadTHandle(lambda);
    const ParamValue init = Map{{"shaft", Map{{"rpy", vec(0.4, 0.5, 0.6)},
                                              {"linear_velocity", vec(1, 2, 3)},
                                              {"angular_velocity", vec(-4, 5, 6)}}}};
    ASSERT_TRUE(applyInitialState(s, init).ok());
    const Readback r = readBack(s);
    expectNear(r.v_W, Eigen::Vector3d(1, 2, 3));
    expectNear(r.w_W, Eigen::Vector3d(-4, 5, 6));
    // Ω_B stores v/λ: the same motion for every λ.
    EXPECT_NEAR(s.bodies[0].omega_B0.trans.norm() * lambda, std::sqrt(14.0), kTol);
  }
}

TEST(InitialState, BodyAxisVelocitiesAreInRootLinkAxes) {
  Scene s = loadTHandle();
  const Eigen::Quaterniond q_WR(Eigen::AngleAxisd(1.1, Eigen::Vector3d(0, 1, 1).normalized()));
  const ParamValue init =
      Map{{"shaft", Map{{"orientation", List{q_WR.x(), q_WR.y(), q_WR.z(), q_WR.w()}},
                        {"linear_velocity_body", vec(1, 0, 0)},
                        {"angular_velocity_body", vec(0, 0, 8)}}}};
  ASSERT_TRUE(applyInitialState(s, init).ok());
  const Readback r = readBack(s);
  expectNear(r.v_W, q_WR * Eigen::Vector3d(1, 0, 0));
  expectNear(r.w_W, q_WR * Eigen::Vector3d(0, 0, 8));
  // The shaft axis z is the intermediate principal axis, B's e2 (J = 0.00302, 0.00442, 0.0074):
  // the spin shows up on that axis of Ω_B alone.
  expectNear(s.bodies[0].omega_B0.angular().cwiseAbs(), Eigen::Vector3d(0, 8, 0));
}

TEST(InitialState, ThroughTheLoaderOptions) {
  SceneOptions o;
  o.initial_state = Map{{"shaft", Map{{"angular_velocity_body", vec(0, 0.01, 8)}}}};
  const auto s = loadUrdfFile(kFile, o);
  ASSERT_TRUE(s.ok()) << s.error();
  expectNear(readBack(*s).w_W, Eigen::Vector3d(0, 0.01, 8));
}

// Each error: the message (prefix "<file>: initial_state.<body>[.<key>]") and no change.
TEST(InitialState, ErrorsNameBodyAndKeyAndChangeNothing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::string p = kFile + ": initial_state";
  struct Case {
    ParamValue init;
    std::string expected;
  };
  const Case cases[] = {
      {List{1.0}, p + ": expected a map from body name to its initial state, got a list"},
      {Map{{"racket", Map{}}}, p + ".racket: no body named 'racket' (bodies: shaft)"},
      {Map{{"shaft", 3.0}}, p + ".shaft: expected a map with keys among position"},
      {state("velocity", vec(1, 2, 3)), p + ".shaft.velocity: unknown key (allowed: position"},
      {state("position", "up"), p + ".shaft.position: expected a list of 3 numbers, got a string"},
      {state("position", List{1.0, 2.0}),
       p + ".shaft.position: expected a list of 3 numbers, got 2"},
      {state("rpy", List{1.0, true, 2.0}), p + ".shaft.rpy[1]: expected a number, got a bool"},
      {state("linear_velocity", vec(1, nan, 0)), p + ".shaft.linear_velocity[1]: must be finite"},
      {state("angular_velocity_body", vec(inf, 0, 0)),
       p + ".shaft.angular_velocity_body[0]: must be finite"},
      {state("orientation", vec(0, 0, 1)),
       p + ".shaft.orientation: expected a list of 4 numbers, got 3"},
      {state("orientation", List{0.0, 0.0, 0.0, 1.1}),
       p + ".shaft.orientation: [x, y, z, w] must be a unit quaternion (norm 1.1"},
      {state("orientation", List{0.0, 0.0, 0.0, 0.0}),
       p + ".shaft.orientation: [x, y, z, w] must be a unit quaternion (norm 0"},
      {Map{{"shaft", Map{{"rpy", vec(0, 0, 0)}, {"orientation", List{0.0, 0.0, 0.0, 1.0}}}}},
       p + ".shaft: give either 'orientation' or 'rpy', not both"},
      {Map{{"shaft",
            Map{{"linear_velocity", vec(0, 0, 0)}, {"linear_velocity_body", vec(0, 0, 0)}}}},
       p + ".shaft: give either 'linear_velocity' or 'linear_velocity_body', not both"},
      {Map{{"shaft",
            Map{{"angular_velocity", vec(0, 0, 0)}, {"angular_velocity_body", vec(0, 0, 0)}}}},
       p + ".shaft: give either 'angular_velocity' or 'angular_velocity_body', not both"},
  };
  for (const Case& c : cases) {
    Scene s = loadTHandle();
    // A valid first change in the same call must not survive the error either.
    Scene before = s;
    const auto r = applyInitialState(s, c.init);
    ASSERT_FALSE(r.ok()) << c.expected;
    EXPECT_EQ(r.error().rfind(c.expected, 0), 0u)
        << "got:      " << r.error() << "\nexpected: " << c.expected;
    const auto& a = s.bodies[0];
    const auto& b = before.bodies[0];
    EXPECT_EQ(a.M_WB0.coefficients(), b.M_WB0.coefficients());
    EXPECT_EQ(a.omega_B0.coefficients(), b.omega_B0.coefficients());
  }
}

TEST(InitialState, StaticBodiesTakeNoInitialState) {
  const std::string urdf = R"(<robot name="r"><link name="world"/>
    <joint name="fix" type="fixed"><parent link="world"/><child link="table"/></joint>
    <link name="table"/></robot>)";
  SceneOptions o;
  o.initial_state = Map{{"table", Map{{"position", vec(0, 0, 1)}}}};
  const auto s = loadUrdfString(urdf, "robot_description", o);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("robot_description: initial_state.table: body 'table' is static"),
            std::string::npos)
      << s.error();
}

TEST(InitialState, AllOrNothingAcrossBodies) {
  // The first body's entry is valid, the second's is not: neither is applied.
  const std::string two = R"(<robot name="r"><link name="world"/>
    <joint name="a_f" type="floating"><parent link="world"/><child link="a"/></joint>
    <link name="a"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
    <joint name="b_f" type="floating"><parent link="world"/><child link="b"/></joint>
    <link name="b"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link></robot>)";
  auto s = loadUrdfString(two, "two", SceneOptions());
  ASSERT_TRUE(s.ok()) << s.error();
  const ParamValue init =
      Map{{"a", Map{{"position", vec(5, 5, 5)}}}, {"b", Map{{"position", List{1.0, 2.0}}}}};
  ASSERT_FALSE(applyInitialState(*s, init).ok());
  EXPECT_EQ(s->bodies[0].M_WB0.translation(1.0), Eigen::Vector3d::Zero());
}

}  // namespace initial_state_test
}  // namespace scene
}  // namespace cga_rigid_sim
