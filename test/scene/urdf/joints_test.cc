// Revolute, continuous and prismatic joints out of the loader (doc/urdf.md#joints) and their
// initial positions (doc/initial_state.md#joints).
//
// Truths:
//  - frames: a child body's pose from the contract of joint.h,
//    M_WBc = M_WBp M_PJ exp(−½ q S) M_JC, written out here from the JointModel's fields, carries
//    each link to the pose the URDF's own composition gives — joint origins and joint motions
//    (Eigen::AngleAxisd about, or a shift along, the unit axis) composed as isometries from the
//    world down, computed here without the loader. The body frame B is checked through what does
//    not depend on the choice of principal axes: its origin is the link's centre of mass, and
//    R_WB J_B R_WBᵀ is the link's inertia tensor turned into the world.
//  - a planar double pendulum's centre of mass, by hand-written trigonometry.
//  - the rules of doc/urdf.md (order, limits, dynamics) and doc/initial_state.md (clamping,
//    messages, all or nothing).
// Tolerance 1e-12: each side is a chain of a few rotations and additions of numbers ≤ 3 m (a few
// ε each); a frame error (a wrong side of a product, a transposed rotation, a sign of q) shows
// at 1e-2 or more.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "cga_rigid_sim/scene/initial_state.h"
#include "cga_rigid_sim/scene/scene_summary.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace joints_test {

constexpr double kTol = 1e-12;
using Map = ParamValue::Map;
using List = ParamValue::List;
using Eigen::Isometry3d;
using Eigen::Vector3d;

// ---------------------------------------------------------------------------------------------
// Helpers: the independent side (Eigen isometries) and the contract's formula.

Isometry3d origin(const Vector3d& xyz, const Vector3d& rpy) {
  Isometry3d X = Isometry3d::Identity();
  X.linear() = (Eigen::AngleAxisd(rpy.z(), Vector3d::UnitZ()) *
                Eigen::AngleAxisd(rpy.y(), Vector3d::UnitY()) *
                Eigen::AngleAxisd(rpy.x(), Vector3d::UnitX()))
                   .toRotationMatrix();
  X.translation() = xyz;
  return X;
}
// The joint's motion of its child: a turn by q about the unit axis, or a shift by q along it.
Isometry3d turn(const Vector3d& axis, double q) {
  Isometry3d X = Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(q, axis.normalized()).toRotationMatrix();
  return X;
}
Isometry3d shift(const Vector3d& axis, double q) {
  Isometry3d X = Isometry3d::Identity();
  X.translation() = q * axis.normalized();
  return X;
}

// joint.h: M_WBc = M_WBp M_PJ exp(−½ q S) M_JC with S = (axis, 0) or (0, axis/λ).
cga::Motor childPose(const Scene& s, const JointModel& j, double q) {
  const cga::Motor M_WP =
      j.parent_body < 0 ? cga::Motor::identity() : s.bodies.at(j.parent_body).M_WB0;
  const cga::Bivelocity S = j.type == JointType::kPrismatic
                                ? cga::Bivelocity(Vector3d::Zero(), j.axis / s.lambda)
                                : cga::Bivelocity(j.axis, Vector3d::Zero());
  return M_WP * j.M_PJ * cga::exp(S * (-0.5 * q)) * j.M_JC;
}

void expectSamePose(const cga::Motor& M, const Isometry3d& X, double lambda,
                    const std::string& what) {
  const Isometry3d got = M.toIsometry(lambda);
  EXPECT_LT((got.translation() - X.translation()).cwiseAbs().maxCoeff(), kTol)
      << what << ": " << got.translation().transpose() << " vs " << X.translation().transpose();
  EXPECT_LT((got.linear() - X.linear()).cwiseAbs().maxCoeff(), kTol) << what;
}

// The link `link` of the scene at the world pose X_WL: its frame, its centre of mass com_L (in
// the link frame) and its body's world inertia tensor equal to R_WL J_L R_WLᵀ (a one-link body).
void expectLinkAt(const Scene& s, const std::string& link, const Isometry3d& X_WL,
                  const Vector3d& com_L, const Eigen::Matrix3d& J_L) {
  SCOPED_TRACE("link " + link);
  int i = -1;
  const int b = s.findLink(link, &i);
  ASSERT_GE(b, 0);
  const BodyModel& body = s.bodies[b];
  expectSamePose(body.M_WB0 * body.links[i].M_BL, X_WL, s.lambda, "M_WL");
  const Vector3d com_W = X_WL * com_L;
  EXPECT_LT((body.M_WB0.translation(s.lambda) - com_W).cwiseAbs().maxCoeff(), kTol);
  const Eigen::Matrix3d R_WB = body.M_WB0.rotation().toRotationMatrix();
  const Eigen::Matrix3d J_W =
      R_WB * body.inertia->principalMoments().asDiagonal() * R_WB.transpose();
  const Eigen::Matrix3d expected = X_WL.linear() * J_L * X_WL.linear().transpose();
  EXPECT_LT((J_W - expected).cwiseAbs().maxCoeff(), kTol);
}

Eigen::Matrix3d tensor(double ixx, double iyy, double izz) {
  return Vector3d(ixx, iyy, izz).asDiagonal();
}
// J_L of a link whose inertial frame I is at `X_LI`, with the diagonal tensor J_I in it.
Eigen::Matrix3d inLink(const Isometry3d& X_LI, const Eigen::Matrix3d& J_I) {
  return X_LI.linear() * J_I * X_LI.linear().transpose();
}

Scene load(const std::string& urdf, const ParamValue& initial_state = ParamValue(),
           double lambda = 1.0) {
  SceneOptions o;
  o.lambda = lambda;
  o.initial_state = initial_state;
  auto s = loadUrdfString(urdf, "test", o);
  EXPECT_TRUE(s.ok()) << s.error();
  return s.ok() ? *s : Scene();
}

ParamValue jointState(const std::string& joint, double q) {
  return Map{{joint, Map{{"position", q}}}};
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// ---------------------------------------------------------------------------------------------
// A double pendulum hinged to the world: a revolute shoulder with an oblique axis, a continuous
// elbow. The links' inertial frames are off their link frames and turned, the joint origins
// turned, so that B, L and J differ everywhere.

const char* const kDoublePendulum = R"(<robot name="double_pendulum">
  <link name="world"/>
  <joint name="shoulder" type="revolute">
    <origin xyz="0.1 -0.2 2" rpy="0.3 -0.2 0.5"/>
    <parent link="world"/><child link="upper"/>
    <axis xyz="1 2 2"/>
    <limit lower="-3" upper="3" effort="50" velocity="4"/>
    <dynamics damping="0.05" friction="0.1"/>
  </joint>
  <link name="upper">
    <inertial><origin xyz="0.02 0.01 -0.5" rpy="0.1 0.2 0.3"/><mass value="2"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.12" iyz="0" izz="0.05"/></inertial>
  </link>
  <joint name="elbow" type="continuous">
    <origin xyz="0 0.05 -1" rpy="0 0.4 0"/>
    <parent link="upper"/><child link="lower"/>
    <axis xyz="0 1 1"/>
  </joint>
  <link name="lower">
    <inertial><origin xyz="0.01 0 -0.4" rpy="-0.2 0 0.1"/><mass value="1"/>
      <inertia ixx="0.03" ixy="0" ixz="0" iyy="0.035" iyz="0" izz="0.01"/></inertial>
  </link>
</robot>)";

const Isometry3d kShoulderOrigin = origin({0.1, -0.2, 2}, {0.3, -0.2, 0.5});
const Isometry3d kElbowOrigin = origin({0, 0.05, -1}, {0, 0.4, 0});
const Vector3d kShoulderAxis(1, 2, 2);
const Vector3d kElbowAxis(0, 1, 1);
const Isometry3d kUpperInertial = origin({0.02, 0.01, -0.5}, {0.1, 0.2, 0.3});
const Isometry3d kLowerInertial = origin({0.01, 0, -0.4}, {-0.2, 0, 0.1});

TEST(Joints, DoublePendulumIsTwoMovingBodiesAndTwoJoints) {
  const Scene s = load(kDoublePendulum);
  ASSERT_EQ(s.bodies.size(), 2u);
  ASSERT_EQ(s.joints.size(), 2u);
  EXPECT_EQ(s.bodies[0].name, "upper");
  EXPECT_EQ(s.bodies[1].name, "lower");
  for (const BodyModel& b : s.bodies) {
    EXPECT_FALSE(b.is_static);
    EXPECT_TRUE(b.inertia.has_value());
    EXPECT_EQ(b.omega_B0.coefficients(), cga::Bivelocity().coefficients());
  }
  const JointModel& shoulder = s.joints[0];
  EXPECT_EQ(shoulder.name, "shoulder");
  EXPECT_EQ(shoulder.type, JointType::kRevolute);
  EXPECT_EQ(shoulder.parent_body, -1);
  EXPECT_EQ(shoulder.child_body, 0);
  EXPECT_EQ(shoulder.parent_link, "world");
  EXPECT_EQ(shoulder.child_link, "upper");
  // <axis xyz="1 2 2"> has length 3: normalised.
  EXPECT_LT((shoulder.axis - Vector3d(1, 2, 2) / 3).cwiseAbs().maxCoeff(), 1e-16);
  EXPECT_TRUE(shoulder.limits.has_position);
  EXPECT_EQ(shoulder.limits.lower, -3);
  EXPECT_EQ(shoulder.limits.upper, 3);
  EXPECT_EQ(shoulder.limits.effort, 50);
  EXPECT_EQ(shoulder.limits.velocity, 4);
  EXPECT_EQ(shoulder.damping, 0.05);
  EXPECT_EQ(shoulder.friction, 0.1);
  EXPECT_EQ(shoulder.initial_position, 0);

  const JointModel& elbow = s.joints[1];
  EXPECT_EQ(elbow.name, "elbow");
  EXPECT_EQ(elbow.type, JointType::kContinuous);
  EXPECT_EQ(elbow.parent_body, 0);
  EXPECT_EQ(elbow.child_body, 1);
  EXPECT_EQ(elbow.parent_link, "upper");
  EXPECT_EQ(elbow.child_link, "lower");
  EXPECT_LT((elbow.axis - Vector3d(0, 1, 1) / std::sqrt(2.0)).cwiseAbs().maxCoeff(), 1e-16);
  // A continuous joint has no position limits and, without <limit>, no effort or velocity bound.
  EXPECT_FALSE(elbow.limits.has_position);
  EXPECT_TRUE(std::isinf(elbow.limits.lower) && elbow.limits.lower < 0);
  EXPECT_TRUE(std::isinf(elbow.limits.upper) && elbow.limits.upper > 0);
  EXPECT_TRUE(std::isinf(elbow.limits.effort));
  EXPECT_TRUE(std::isinf(elbow.limits.velocity));
  EXPECT_EQ(elbow.damping, 0);
  EXPECT_EQ(elbow.friction, 0);

  // The frames. The world-hinged joint's J is its origin in the world; the elbow's J sits in
  // the upper body's B where the upper link's frame and the origin put it: M_WB M_PJ is the
  // elbow's frame in the world at q = 0. M_JC is the child link's M_BL reversed.
  expectSamePose(shoulder.M_PJ, kShoulderOrigin, s.lambda, "shoulder M_PJ");
  expectSamePose(s.bodies[0].M_WB0 * elbow.M_PJ, kShoulderOrigin * kElbowOrigin, s.lambda,
                 "elbow J in the world at q = 0");
  for (const JointModel* j : {&shoulder, &elbow})
    expectSamePose(j->M_JC * s.bodies[j->child_body].links.front().M_BL, Isometry3d::Identity(),
                   s.lambda, j->name + " M_JC M_BL");
}

TEST(Joints, ChildPoseFromTheContractEqualsTheUrdfChain) {
  // Fixed seed: the joint positions are arbitrary; λ must change nothing a user sees.
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  for (const double lambda : {1.0, 7.3}) {
    for (int trial = 0; trial < 5; ++trial) {
      const double q1 = trial == 0 ? 0.0 : angle(rng), q2 = trial == 0 ? 0.0 : 3 * angle(rng);
      SCOPED_TRACE("lambda " + std::to_string(lambda) + ", q = " + std::to_string(q1) + ", " +
                   std::to_string(q2));
      const Scene s =
          load(kDoublePendulum,
               Map{{"shoulder", Map{{"position", q1}}}, {"elbow", Map{{"position", q2}}}}, lambda);
      ASSERT_EQ(s.joints.size(), 2u);
      EXPECT_EQ(s.joints[0].initial_position, q1);
      EXPECT_EQ(s.joints[1].initial_position, q2);  // continuous: |q2| up to 9 rad, unclamped
      // The loader's M_WB0 is the contract's formula, body by body from the world down.
      for (const JointModel& j : s.joints) {
        const cga::Motor expected = childPose(s, j, j.initial_position);
        expectSamePose(s.bodies[j.child_body].M_WB0, expected.toIsometry(lambda), lambda,
                       j.name + ": M_WB0 vs the formula");
        EXPECT_LT(s.bodies[j.child_body].M_WB0.normDrift(), kTol);
      }
      // And the formula is the URDF's chain of origins and joint motions.
      const Isometry3d X_W_upper = kShoulderOrigin * turn(kShoulderAxis, q1);
      const Isometry3d X_W_lower = X_W_upper * kElbowOrigin * turn(kElbowAxis, q2);
      expectLinkAt(s, "upper", X_W_upper, kUpperInertial.translation(),
                   inLink(kUpperInertial, tensor(0.1, 0.12, 0.05)));
      expectLinkAt(s, "lower", X_W_lower, kLowerInertial.translation(),
                   inLink(kLowerInertial, tensor(0.03, 0.035, 0.01)));
    }
  }
}

// A planar double pendulum in the x-z plane, both axes along +y: the centre of mass of the
// second link by trigonometry. A turn by q about +y takes −e3 to (−sin q, 0, −cos q).
TEST(Joints, InitialStateByJointNameMovesTheChildBodies) {
  const std::string urdf = R"(<robot name="planar_pendulum">
    <link name="world"/>
    <joint name="shoulder" type="revolute"><origin xyz="0 0 2"/>
      <parent link="world"/><child link="upper"/><axis xyz="0 1 0"/>
      <limit lower="-3.2" upper="3.2" effort="10" velocity="5"/></joint>
    <link name="upper"><inertial><origin xyz="0 0 -0.5"/><mass value="1"/>
      <inertia ixx="0.09" ixy="0" ixz="0" iyy="0.095" iyz="0" izz="0.01"/></inertial></link>
    <joint name="elbow" type="revolute"><origin xyz="0 0 -1"/>
      <parent link="upper"/><child link="lower"/><axis xyz="0 1 0"/>
      <limit lower="-3.2" upper="3.2" effort="10" velocity="5"/></joint>
    <link name="lower"><inertial><origin xyz="0 0 -0.5"/><mass value="1"/>
      <inertia ixx="0.09" ixy="0" ixz="0" iyy="0.095" iyz="0" izz="0.01"/></inertial></link>
  </robot>)";
  const double q1 = 0.7, q2 = -1.9;
  const Scene s = load(urdf, Map{{"shoulder", Map{{"position", q1}, {"velocity", 0.5}}},
                                 {"elbow", Map{{"position", q2}}}});
  ASSERT_EQ(s.joints.size(), 2u);
  const Vector3d com_upper(-0.5 * std::sin(q1), 0, 2 - 0.5 * std::cos(q1));
  const Vector3d com_lower(-std::sin(q1) - 0.5 * std::sin(q1 + q2), 0,
                           2 - std::cos(q1) - 0.5 * std::cos(q1 + q2));
  EXPECT_LT((s.bodies[0].M_WB0.translation(1.0) - com_upper).cwiseAbs().maxCoeff(), kTol);
  EXPECT_LT((s.bodies[1].M_WB0.translation(1.0) - com_lower).cwiseAbs().maxCoeff(), kTol);
  EXPECT_EQ(s.joints[0].initial_velocity, 0.5);
  EXPECT_EQ(s.joints[1].initial_velocity, 0.0);
  // The child bodies' own velocities stay zero: the joint velocities carry the motion.
  EXPECT_EQ(s.bodies[0].omega_B0.coefficients(), cga::Bivelocity().coefficients());

  // applyInitialState on the loaded scene does the same, and again from there.
  Scene again = load(urdf);
  ASSERT_TRUE(applyInitialState(again, Map{{"elbow", Map{{"position", q2}}}}).ok());
  ASSERT_TRUE(applyInitialState(again, Map{{"shoulder", Map{{"position", q1}}}}).ok());
  EXPECT_LT((again.bodies[1].M_WB0.translation(1.0) - com_lower).cwiseAbs().maxCoeff(), kTol);
}

// A prismatic joint: the child shifts by q along the unit axis, turned into the world by the
// joint origin. The <axis xyz="2 0 0"> is normalised.
TEST(Joints, PrismaticJointShiftsAlongItsAxis) {
  const std::string urdf = R"(<robot name="slide">
    <link name="world"/>
    <joint name="slider" type="prismatic"><origin xyz="1 0 0.5" rpy="0 0 1.5707963267948966"/>
      <parent link="world"/><child link="carriage"/><axis xyz="2 0 0"/>
      <limit lower="-0.2" upper="0.8" effort="100" velocity="0.5"/>
      <dynamics damping="3"/></joint>
    <link name="carriage"><inertial><origin xyz="0 0 0.1"/><mass value="4"/>
      <inertia ixx="0.15" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial></link>
  </robot>)";
  const Scene s = load(urdf, jointState("slider", 0.3));
  ASSERT_EQ(s.joints.size(), 1u);
  const JointModel& j = s.joints[0];
  EXPECT_EQ(j.type, JointType::kPrismatic);
  EXPECT_EQ(j.axis, Vector3d(1, 0, 0));
  EXPECT_EQ(j.limits.lower, -0.2);
  EXPECT_EQ(j.limits.upper, 0.8);
  EXPECT_EQ(j.limits.effort, 100);
  EXPECT_EQ(j.damping, 3);
  EXPECT_EQ(j.friction, 0);  // <dynamics> without friction: 0
  // The origin turns x into y: the carriage's link origin is at (1, 0.3, 0.5), its centre of
  // mass 0.1 above.
  const Isometry3d X_O = origin({1, 0, 0.5}, {0, 0, 1.5707963267948966});
  expectLinkAt(s, "carriage", X_O * shift({2, 0, 0}, 0.3), {0, 0, 0.1}, tensor(0.15, 0.2, 0.3));
  EXPECT_LT((s.bodies[0].M_WB0.translation(1.0) - Vector3d(1, 0.3, 0.6)).cwiseAbs().maxCoeff(),
            kTol);
  // With λ = 7.3 the shift S = (0, axis/λ) gives the same pose.
  const Scene s7 = load(urdf, jointState("slider", 0.3), 7.3);
  EXPECT_LT((s7.bodies[0].M_WB0.translation(7.3) - Vector3d(1, 0.3, 0.6)).cwiseAbs().maxCoeff(),
            kTol);
}

// A lid hinged to a static table. The hinge hangs off table_top, a link merged into the static
// body 'table' (whose B is its root link's frame): M_PJ = M_BL(table_top) (joint origin).
TEST(Joints, JointOffAStaticBody) {
  const std::string urdf = R"(<robot name="table_with_lid">
    <link name="world"/>
    <joint name="table_fix" type="fixed"><origin xyz="0 0 0.75" rpy="0 0 0.3"/>
      <parent link="world"/><child link="table"/></joint>
    <link name="table"/>
    <joint name="top_weld" type="fixed"><origin xyz="0.3 0 0.05" rpy="0.1 0 0"/>
      <parent link="table"/><child link="table_top"/></joint>
    <link name="table_top"/>
    <joint name="lid_hinge" type="revolute"><origin xyz="0 0.2 0.02" rpy="0 0 -0.4"/>
      <parent link="table_top"/><child link="lid"/><axis xyz="1 0 0"/>
      <limit lower="0" upper="2" effort="5" velocity="1"/></joint>
    <link name="lid"><inertial><origin xyz="0 -0.2 0.01" rpy="0 0.2 0"/><mass value="0.5"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.025"/></inertial></link>
  </robot>)";
  const double q = 0.7;
  const Scene s = load(urdf, jointState("lid_hinge", q));
  ASSERT_EQ(s.bodies.size(), 2u);
  ASSERT_EQ(s.joints.size(), 1u);
  EXPECT_EQ(s.bodies[0].name, "table");
  EXPECT_TRUE(s.bodies[0].is_static);
  const JointModel& j = s.joints[0];
  EXPECT_EQ(j.parent_body, 0);
  EXPECT_EQ(j.child_body, 1);
  EXPECT_EQ(j.parent_link, "table_top");
  const Isometry3d X_RJ =
      origin({0.3, 0, 0.05}, {0.1, 0, 0}) * origin({0, 0.2, 0.02}, {0, 0, -0.4});
  expectSamePose(j.M_PJ, X_RJ, s.lambda, "M_PJ in the static body's frame");
  const Isometry3d X_W_table = origin({0, 0, 0.75}, {0, 0, 0.3});
  const Isometry3d X_W_lid = X_W_table * X_RJ * turn({1, 0, 0}, q);
  const Isometry3d X_LI = origin({0, -0.2, 0.01}, {0, 0.2, 0});
  expectLinkAt(s, "lid", X_W_lid, X_LI.translation(), inLink(X_LI, tensor(0.01, 0.02, 0.025)));
  // The static body takes no initial state; the lid neither: its joint does.
  SceneOptions o;
  o.initial_state = Map{{"lid", Map{{"position", List{0.0, 0.0, 1.0}}}}};
  const auto refused = loadUrdfString(urdf, "test", o);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(contains(refused.error(),
                       "test: initial_state.lid: body 'lid' is moved by joint "
                       "'lid_hinge': give the joint's position instead"))
      << refused.error();
}

// A floating-base tree: the root link 'hub' is not the world, so it is a free body, and two
// panels hang from it on revolute joints. A body entry that moves the hub moves the panels.
const char* const kSatellite = R"(<robot name="satellite">
  <link name="hub"><inertial><origin xyz="0 0 0.05"/><mass value="10"/>
    <inertia ixx="1" ixy="0" ixz="0" iyy="1.2" iyz="0" izz="1.5"/></inertial></link>
  <joint name="left_hinge" type="revolute"><origin xyz="0 0.5 0" rpy="0 0 0"/>
    <parent link="hub"/><child link="left_panel"/><axis xyz="0 1 0"/>
    <limit lower="-1.6" upper="1.6" effort="1" velocity="1"/></joint>
  <link name="left_panel"><inertial><origin xyz="0 0.6 0"/><mass value="1"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.105"/></inertial></link>
  <joint name="right_hinge" type="revolute"><origin xyz="0 -0.5 0" rpy="0 0 3.141592653589793"/>
    <parent link="hub"/><child link="right_panel"/><axis xyz="0 1 0"/>
    <limit lower="-1.6" upper="1.6" effort="1" velocity="1"/></joint>
  <link name="right_panel"><inertial><origin xyz="0 0.6 0"/><mass value="1"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.105"/></inertial></link>
</robot>)";

TEST(Joints, FloatingBaseTreeHasAFreeRoot) {
  const Vector3d rpy(0.1, -0.3, 0.5), x(1, 2, 3);
  const Scene s = load(kSatellite, Map{{"hub", Map{{"position", List{x.x(), x.y(), x.z()}},
                                                   {"rpy", List{rpy.x(), rpy.y(), rpy.z()}},
                                                   {"angular_velocity", List{0.0, 0.0, 0.2}}}},
                                       {"left_hinge", Map{{"position", 0.4}}},
                                       {"right_hinge", Map{{"position", -1.1}}}});
  ASSERT_EQ(s.bodies.size(), 3u);
  ASSERT_EQ(s.joints.size(), 2u);
  EXPECT_EQ(s.bodies[0].name, "hub");
  EXPECT_FALSE(s.bodies[0].is_static);
  for (const JointModel& j : s.joints) EXPECT_EQ(j.parent_body, 0) << j.name;
  EXPECT_EQ(s.joints[0].name, "left_hinge");
  EXPECT_EQ(s.joints[1].name, "right_hinge");
  const Isometry3d X_W_hub = origin(x, rpy);
  expectLinkAt(s, "hub", X_W_hub, {0, 0, 0.05}, tensor(1, 1.2, 1.5));
  expectLinkAt(s, "left_panel", X_W_hub * origin({0, 0.5, 0}, {0, 0, 0}) * turn({0, 1, 0}, 0.4),
               {0, 0.6, 0}, tensor(0.1, 0.01, 0.105));
  expectLinkAt(s, "right_panel",
               X_W_hub * origin({0, -0.5, 0}, {0, 0, 3.141592653589793}) * turn({0, 1, 0}, -1.1),
               {0, 0.6, 0}, tensor(0.1, 0.01, 0.105));
  // The free root keeps its velocity; the panels' own stay zero.
  EXPECT_GT(s.bodies[0].omega_B0.angular().norm(), 0.19);
  EXPECT_EQ(s.bodies[1].omega_B0.coefficients(), cga::Bivelocity().coefficients());

  // Moving the hub again, later, moves the panels with it.
  Scene moved = s;
  ASSERT_TRUE(applyInitialState(moved, Map{{"hub", Map{{"position", List{0.0, 0.0, 0.0}}}}}).ok());
  const Isometry3d X_W_hub0 = origin({0, 0, 0}, rpy);
  expectLinkAt(moved, "left_panel",
               X_W_hub0 * origin({0, 0.5, 0}, {0, 0, 0}) * turn({0, 1, 0}, 0.4), {0, 0.6, 0},
               tensor(0.1, 0.01, 0.105));
}

// Bodies and joints are parent first even when the document lists a child link, and its joint,
// before its parent; otherwise bodies keep the document order of their root links.
TEST(Joints, BodiesAndJointsAreParentFirst) {
  const std::string urdf = R"(<robot name="shuffled">
    <link name="hand"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
    <joint name="wrist" type="continuous"><origin xyz="0 0 -0.3"/>
      <parent link="forearm"/><child link="hand"/></joint>
    <link name="ball"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
    <joint name="elbow" type="continuous"><origin xyz="0 0 -0.5"/>
      <parent link="arm"/><child link="forearm"/></joint>
    <link name="forearm"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
    <link name="world"/>
    <joint name="ball_float" type="floating"><parent link="world"/><child link="ball"/></joint>
    <joint name="shoulder" type="continuous"><origin xyz="0 0 2"/>
      <parent link="world"/><child link="arm"/></joint>
    <link name="arm"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  </robot>)";
  const Scene s = load(urdf);
  ASSERT_EQ(s.bodies.size(), 4u);
  std::vector<std::string> names;
  for (const BodyModel& b : s.bodies) names.push_back(b.name);
  // hand first in the document, but after its ancestors arm and forearm; ball after them.
  EXPECT_EQ(names, (std::vector<std::string>{"arm", "forearm", "hand", "ball"}));
  ASSERT_EQ(s.joints.size(), 3u);
  std::vector<std::string> joints;
  for (const JointModel& j : s.joints) joints.push_back(j.name);
  EXPECT_EQ(joints, (std::vector<std::string>{"shoulder", "elbow", "wrist"}));
  for (std::size_t k = 0; k < s.joints.size(); ++k) {
    const JointModel& j = s.joints[k];
    EXPECT_LT(j.parent_body, j.child_body) << j.name;
    EXPECT_EQ(s.bodies[j.child_body].name, j.child_link) << j.name;
    // The parent is the world, or the child of an earlier joint.
    bool parent_placed = j.parent_body < 0;
    for (std::size_t e = 0; e < k; ++e) parent_placed |= s.joints[e].child_body == j.parent_body;
    EXPECT_TRUE(parent_placed) << j.name;
  }
  // Every link at its chain pose (all joints at 0).
  expectSamePose(s.bodies[2].M_WB0, origin({0, 0, 1.2}, {0, 0, 0}), s.lambda, "hand");
}

// Limits: a position outside them is clamped with a warning naming the joint, the value and
// the limit, both for an initial_state entry and for the default 0.
TEST(Joints, InitialPositionsAreClampedIntoTheLimitsWithAWarning) {
  const std::string urdf = R"(<robot name="r">
    <link name="world"/>
    <joint name="lift" type="revolute"><parent link="world"/><child link="arm"/>
      <axis xyz="0 0 1"/><limit lower="0.2" upper="1" effort="1" velocity="1"/></joint>
    <link name="arm"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  </robot>)";
  // The default 0 is below the lower limit: the joint starts at 0.2.
  const Scene s = load(urdf);
  ASSERT_EQ(s.joints.size(), 1u);
  EXPECT_EQ(s.joints[0].initial_position, 0.2);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_TRUE(contains(s.warnings[0],
                       "test:3: joint 'lift': the default initial position 0 rad "
                       "is outside its limits [0.2, 1] rad: clamped to the lower "
                       "limit 0.2 rad"))
      << s.warnings[0];
  const Vector3d com(0.5 * std::cos(0.2), 0.5 * std::sin(0.2), 0);
  EXPECT_LT((s.bodies[0].M_WB0.translation(1.0) - com).cwiseAbs().maxCoeff(), kTol);

  // 2.5 rad is above the upper limit: clamped to 1, and said so.
  const Scene high = load(urdf, jointState("lift", 2.5));
  EXPECT_EQ(high.joints[0].initial_position, 1.0);
  ASSERT_EQ(high.warnings.size(), 2u);
  EXPECT_EQ(high.warnings[1],
            "test: initial_state.lift.position: 2.5 rad is outside the limits [0.2, 1] rad of "
            "joint 'lift': clamped to the upper limit 1 rad");
  const Vector3d com1(0.5 * std::cos(1.0), 0.5 * std::sin(1.0), 0);
  EXPECT_LT((high.bodies[0].M_WB0.translation(1.0) - com1).cwiseAbs().maxCoeff(), kTol);

  // Inside the limits: no further warning.
  EXPECT_EQ(load(urdf, jointState("lift", 0.5)).warnings.size(), 1u);
}

// A continuous joint ignores lower and upper (even lower > upper) but keeps effort and velocity;
// a revolute <limit> without lower (or upper) takes URDF's default 0, with a warning.
TEST(Joints, ContinuousIgnoresPositionLimitsAndMissingLowerIsZero) {
  const std::string urdf = R"(<robot name="r">
    <link name="world"/>
    <joint name="wheel" type="continuous"><parent link="world"/><child link="rim"/>
      <axis xyz="0 1 0"/><limit lower="1" upper="-1" effort="7" velocity="30"/></joint>
    <link name="rim"><inertial><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/></inertial></link>
    <joint name="flap" type="revolute"><origin xyz="1 0 0"/><parent link="world"/>
      <child link="plate"/><limit upper="0.5" effort="1" velocity="1"/></joint>
    <link name="plate"><inertial><mass value="1"/>
      <inertia ixx="0.015" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/></inertial></link>
  </robot>)";
  const Scene s = load(urdf, jointState("wheel", 12.0));
  ASSERT_EQ(s.joints.size(), 2u);
  const JointModel& wheel = s.joints[0];
  EXPECT_FALSE(wheel.limits.has_position);
  EXPECT_EQ(wheel.limits.effort, 7);
  EXPECT_EQ(wheel.limits.velocity, 30);
  EXPECT_EQ(wheel.initial_position, 12.0);  // not clamped, not wrapped
  const JointModel& flap = s.joints[1];
  EXPECT_EQ(flap.axis, Vector3d(1, 0, 0));  // no <axis>: URDF's default
  EXPECT_EQ(flap.limits.lower, 0);
  EXPECT_EQ(flap.limits.upper, 0.5);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_TRUE(contains(s.warnings[0],
                       "test:8: joint 'flap': <limit> has no lower; URDF's "
                       "default lower = 0 is used"))
      << s.warnings[0];
}

// Truth: a turn about a joint's axis keeps the child's centre of mass on its circle about the
// axis: the same distance from the axis and the same height along it as at q = 0, whatever q.
// A continuous joint set to 1e308 rad (found by fuzz_initial_state: it left a non-finite pose,
// exp squaring the angle) gives a finite pose on that circle (round-off, 1e-15 m), and 12 rad
// the same pose as 12 − 4π rad (the rotor's period) to round-off.
TEST(Joints, HugeContinuousAngleStaysOnTheJointsCircle) {
  const std::string urdf = R"(<robot name="r">
    <link name="world"/>
    <joint name="wheel" type="continuous"><origin xyz="0 0 1"/><parent link="world"/>
      <child link="arm"/><axis xyz="0 1 0"/></joint>
    <link name="arm"><inertial><origin xyz="0.3 0.2 0"/><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/></inertial></link>
  </robot>)";
  const auto com = [&](double q) {
    return load(urdf, jointState("wheel", q)).bodies[0].M_WB0.translation(1.0);
  };
  const Vector3d c0 = com(0.0);
  for (const double q : {1.01e308, -3e200, 1e20}) {
    const Vector3d c = com(q);
    ASSERT_TRUE(c.allFinite()) << q;
    EXPECT_NEAR(c.y(), c0.y(), 1e-15) << q;
    EXPECT_NEAR(std::hypot(c.x(), c.z() - 1.0), std::hypot(c0.x(), c0.z() - 1.0), 1e-15) << q;
  }
  EXPECT_LT((com(12.0) - com(12.0 - 4 * M_PI)).norm(), 1e-14);
}

// Errors of joint entries: the message names the joint and the key, and nothing is applied.
TEST(Joints, InitialStateErrorsNameTheJointAndChangeNothing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::string p = "test: initial_state";
  struct Case {
    ParamValue init;
    std::string expected;
  };
  const Case cases[] = {
      {Map{{"knee", Map{}}},
       p + ".knee: no body or joint named 'knee' (bodies: upper, lower; joints: shoulder, elbow)"},
      {Map{{"shoulder", 0.5}},
       p + ".shoulder: expected a map with keys among position, velocity (joint 'shoulder', "
           "revolute), got a number"},
      {Map{{"shoulder", Map{{"rpy", List{0.0, 0.0, 0.0}}}}},
       p + ".shoulder.rpy: unknown key of joint 'shoulder' (allowed: position in rad, velocity "
           "in rad/s)"},
      {Map{{"shoulder", Map{{"position", List{0.5}}}}},
       p + ".shoulder.position: expected a number (joint 'shoulder', in rad), got a list"},
      {Map{{"elbow", Map{{"velocity", "fast"}}}},
       p + ".elbow.velocity: expected a number (joint 'elbow', in rad/s), got a string"},
      {Map{{"elbow", Map{{"position", nan}}}}, p + ".elbow.position: must be finite (got nan)"},
      {Map{{"lower", Map{{"position", List{0.0, 0.0, 0.0}}}}},
       p + ".lower: body 'lower' is moved by joint 'elbow': give the joint's position instead"},
  };
  for (const Case& c : cases) {
    Scene s = load(kDoublePendulum);
    const Scene before = s;
    // A valid entry in the same call (sorted first) must not survive the error either.
    ParamValue::Map init = c.init.asMap();
    init.emplace("elbow", Map{{"position", 1.0}});
    const auto r = applyInitialState(s, init);
    ASSERT_FALSE(r.ok()) << c.expected;
    EXPECT_EQ(r.error().rfind(c.expected, 0), 0u)
        << "got:      " << r.error() << "\nexpected: " << c.expected;
    for (std::size_t k = 0; k < s.joints.size(); ++k)
      EXPECT_EQ(s.joints[k].initial_position, before.joints[k].initial_position);
    for (std::size_t k = 0; k < s.bodies.size(); ++k)
      EXPECT_EQ(s.bodies[k].M_WB0.coefficients(), before.bodies[k].M_WB0.coefficients());
    EXPECT_EQ(s.warnings, before.warnings);
  }
  // A clamped position in a call that fails leaves no warning behind.
  Scene s = load(kDoublePendulum);
  EXPECT_FALSE(
      applyInitialState(s, Map{{"shoulder", Map{{"position", 9.0}}}, {"upper", Map{{"x", 1.0}}}})
          .ok());
  EXPECT_TRUE(s.warnings.empty());
}

// A name that is both a free body's and a joint's is ambiguous as a key: refused. (A joint's
// child body may share its joint's name: the key is the joint's.)
TEST(Joints, AKeyNamingAFreeBodyAndAJointIsRefused) {
  const std::string urdf = R"(<robot name="r">
    <link name="base"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
    <joint name="base" type="continuous"><parent link="base"/><child link="arm"/></joint>
    <link name="arm"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
    <joint name="arm" type="continuous"><parent link="arm"/><child link="tip"/></joint>
    <link name="tip"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  </robot>)";
  Scene s = load(urdf);
  const auto r = applyInitialState(s, Map{{"base", Map{{"position", 1.0}}}});
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error(),
                       "test: initial_state.base: 'base' names both a free body and a "
                       "joint"))
      << r.error();
  // 'arm' is a body moved by a joint and the name of another joint: the joint's key.
  ASSERT_TRUE(applyInitialState(s, Map{{"arm", Map{{"position", 1.0}}}}).ok());
  EXPECT_EQ(s.joints.at(s.findJoint("arm")).initial_position, 1.0);
}

TEST(Joints, SummaryListsTheJoints) {
  const Scene s = load(kDoublePendulum, jointState("shoulder", 0.25));
  const std::string text = sceneSummary(s, "auto");
  EXPECT_TRUE(contains(text, "2 bodies (2 moving, 0 static), 2 joints, integrator 'auto'")) << text;
  EXPECT_TRUE(contains(text, "path articulated (moved by joint shoulder)")) << text;
  EXPECT_TRUE(contains(text,
                       "joints:\n  shoulder: revolute, world -> upper, axis (0.333333, "
                       "0.666667, 0.666667), position in [-3, 3] rad, |effort| <= 50 N m, "
                       "|velocity| <= 4 rad/s, damping 0.05 N m s/rad, friction 0.1 N m, "
                       "q0 = 0.25 rad\n"))
      << text;
  EXPECT_TRUE(contains(text,
                       "  elbow: continuous, upper -> lower, axis (0, 0.707107, 0.707107), "
                       "no position limits\n"))
      << text;
  EXPECT_TRUE(contains(text, "paths: articulated x2;")) << text;
}

// A floating joint below an articulated joint still starts a free body, at the joint chain
// with every joint at 0; it takes its own initial state.
TEST(Joints, FloatingJointBelowAHingedBody) {
  const std::string urdf = R"(<robot name="r">
    <link name="world"/>
    <joint name="hinge" type="continuous"><origin xyz="0 0 1"/><parent link="world"/>
      <child link="arm"/><axis xyz="0 0 1"/></joint>
    <link name="arm"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.25"/></inertial></link>
    <joint name="drop" type="floating"><origin xyz="1 0 0"/><parent link="arm"/>
      <child link="ball"/></joint>
    <link name="ball"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  </robot>)";
  const Scene s = load(urdf);
  ASSERT_EQ(s.bodies.size(), 2u);
  ASSERT_EQ(s.joints.size(), 1u);
  EXPECT_EQ(s.bodies[1].name, "ball");
  EXPECT_LT((s.bodies[1].M_WB0.translation(1.0) - Vector3d(1, 0, 1)).cwiseAbs().maxCoeff(), kTol);
}

}  // namespace joints_test
}  // namespace scene
}  // namespace cga_rigid_sim
