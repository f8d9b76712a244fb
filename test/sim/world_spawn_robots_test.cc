// Whole robots spawned and deleted at run time (World::spawnUrdf with a robot_namespace,
// World::deleteBody of a robot; doc/node.md#spawning-robots): two copies of the 7-DoF arm of
// urdf/arm7.urdf under namespaces, each driven by its own trajectory controller; a spawn and a
// delete leave everything else bit-identical; a free robot keeps its momentum; refusals change
// nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace sim {
namespace world_spawn_robots_test {

using scene::ParamValue;

const std::vector<std::string> kJoints = {"joint1", "joint2", "joint3", "joint4",
                                          "joint5", "joint6", "joint7"};
const std::string kArmPath = std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/arm7.urdf";
const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();

std::string armUrdf() {
  std::ifstream in(kArmPath);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The arm hanging from the ceiling at the origin: the start scene of every world here.
std::unique_ptr<World> armWorld(const Eigen::Vector3d& gravity = {0, 0, -9.81},
                                const WorldConfig& config = {}) {
  scene::SceneOptions options;
  options.gravity_W = gravity;
  auto scene = scene::loadUrdfFile(kArmPath, options);
  EXPECT_TRUE(scene.ok()) << scene.error();
  auto world = World::create(std::move(*scene), config);
  EXPECT_TRUE(world.ok()) << world.error();
  return std::move(*world);
}

// config/arm7_controllers.yaml's arm_controller (path tolerance 0.05 rad, goal 0.01 rad) with
// its joint_state_controller, and its pid_gains: the node's ~controllers.
ParamValue controllersYaml() {
  ParamValue::List joints;
  for (const std::string& j : kJoints) joints.emplace_back(j);
  ParamValue::Map c, constraints;
  c["type"] = std::string("position_controllers/JointTrajectoryController");
  c["joints"] = ParamValue(joints);
  constraints["goal_time"] = 1.0;
  for (const std::string& j : kJoints) {
    ParamValue::Map tol;
    tol["trajectory"] = 0.05;
    tol["goal"] = 0.01;
    constraints[j] = ParamValue(tol);
  }
  c["constraints"] = ParamValue(constraints);
  ParamValue::Map jsc;
  jsc["type"] = std::string("joint_state_controller/JointStateController");
  jsc["publish_rate"] = 50.0;
  ParamValue::Map yaml;
  yaml["arm_controller"] = ParamValue(c);
  yaml["joint_state_controller"] = ParamValue(jsc);
  return ParamValue(yaml);
}

ParamValue pidGains() {
  const double p[] = {15000, 15000, 6000, 6000, 2000, 2000, 500};
  const double d[] = {300, 300, 100, 100, 30, 30, 10};
  ParamValue::Map m;
  for (int k = 0; k < 7; ++k) {
    ParamValue::Map g;
    g["p"] = p[k];
    g["d"] = d[k];
    m[kJoints[k]] = ParamValue(g);
  }
  return ParamValue(m);
}

SpawnOptions robotOptions(const std::string& ns) {
  SpawnOptions o;
  o.robot_namespace = ns;
  o.controllers = controllersYaml();
  o.controller_names = {"arm_controller", "joint_state_controller"};
  o.pid_gains = pidGains();
  return o;
}

Eigen::Isometry3d at(double x, double y, double yaw = 0.0) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(x, y, 0.0);
  p.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return p;
}

// A trajectory through two points to `goal` (scaled copies of one reach), in `names`.
control::JointTrajectory reach(const std::vector<std::string>& names, double scale) {
  control::JointTrajectory t;
  t.joint_names = names;
  control::TrajectoryPoint mid, end;
  const std::vector<double> goal = {0.4, 0.6, 0.2, -1.0, 0.4, 0.6, 0.3};
  for (double g : goal) {
    mid.positions.push_back(0.5 * scale * g);
    mid.velocities.push_back(0.5 * scale * g);
    end.positions.push_back(scale * g);
  }
  end.velocities.assign(7, 0.0);
  mid.time_from_start = 1.0;
  end.time_from_start = 2.0;
  t.points = {mid, end};
  return t;
}

std::vector<std::string> prefixed(const std::string& ns) {
  std::vector<std::string> out;
  for (const std::string& j : kJoints) out.push_back(ns + "/" + j);
  return out;
}

bool sameBits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

// The tree of the robot whose joint is called `joint`.
int treeOf(const World& w, const std::string& joint) {
  return w.model().joint_by_name.at(joint).first;
}

const control::TrajectoryController& controllerOf(const World& w, const std::string& name) {
  for (const ControllerData& c : w.data().controllers.running)
    if (c.config.name == name) return *c.trajectory;
  ADD_FAILURE() << "no controller " << name;
  return *w.data().controllers.running.front().trajectory;
}

// Inputs for robot `ns` that fall after the deletion step (2.0 s): a wrench on a link, a timed
// effort on a joint, and a second trajectory, waiting in their queues when r2 is deleted.
void queueLaterInputs(World& w, const std::string& ns) {
  WrenchInput f;
  f.body = ns + "/link5";
  f.F.f = Eigen::Vector3d(0, 20, 0);
  f.start_time = 2.0;
  f.duration = 0.1;
  ASSERT_TRUE(w.applyWrench(f).ok());
  TimedJointEffortInput e;
  e.joint = ns + "/joint7";
  e.effort = 5.0;
  e.start_time = 2.2;
  e.duration = 0.05;
  ASSERT_TRUE(w.applyJointEffort(e).ok());
  control::JointTrajectory back = reach(prefixed(ns), 0.3);
  back.start_time = 2.5;
  ASSERT_TRUE(w.commandTrajectory(ns + "/arm_controller", back).ok());
}

// Truths: (1) a robot spawned far from everything does not change a bit of what the world
// simulated before (the scene's arm with and without the spawns steps identically: the robots
// are separate arrays appended after it); (2) two copies of the arm that cannot touch do not
// affect each other: r1 with r2 beside it is bit-identical to r1 alone; (3) each tracks its own
// trajectory within its controller's path tolerance (0.05 rad) and reaches its goal (0.01 rad);
// (4) r2, spawned before r1, is deleted while inputs for both wait: r1's indices shift under
// its queued wrench, timed effort and trajectory, and r1 goes on bit-identical to the run in
// which r2 never existed; r2's joints, bodies, controller and inputs are gone.
TEST(WorldSpawnRobots, TwoCopiesTrackTheirOwnTrajectoriesAndDeletingOneChangesNothingElse) {
  auto both = armWorld(), one = armWorld(), none = armWorld();
  for (World* w : {both.get(), one.get(), none.get()}) {
    auto loaded = w->loadControllers(controllersYaml(), {"arm_controller"}, pidGains());
    ASSERT_TRUE(loaded.ok()) << loaded.error();
  }
  const std::string urdf = armUrdf();
  // 3 m apart, the arms reach 1.4 m: they cannot touch each other or the scene's arm.
  auto r2 = both->spawnUrdf("r2", urdf, at(-3.0, 0.0), kZero, kZero, robotOptions("r2"));
  ASSERT_TRUE(r2.ok()) << r2.error();
  for (World* w : {both.get(), one.get()}) {
    auto r1 = w->spawnUrdf("r1", urdf, at(3.0, 0.0, 0.5), kZero, kZero, robotOptions("r1"));
    ASSERT_TRUE(r1.ok()) << r1.error();
  }
  EXPECT_EQ(both->model().trees.size(), 3u);
  EXPECT_EQ(both->model().joint_by_name.count("r2/joint4"), 1u);
  EXPECT_GE(both->scene().findLink("r2/link7"), 0);
  // The joint state controller is not copied: /joint_states carries every joint already.
  EXPECT_EQ(both->data().controllers.running.size(), 3u);

  for (World* w : {both.get(), one.get(), none.get()})
    ASSERT_TRUE(w->commandTrajectory("arm_controller", reach(kJoints, 0.5)).ok());
  for (World* w : {both.get(), one.get()}) {
    ASSERT_TRUE(w->commandTrajectory("r1/arm_controller", reach(prefixed("r1"), 1.0)).ok());
    queueLaterInputs(*w, "r1");
  }
  // r2's trajectory names its joints as the URDF does: the controller takes either.
  ASSERT_TRUE(both->commandTrajectory("r2/arm_controller", reach(kJoints, -0.8)).ok());
  queueLaterInputs(*both, "r2");

  const int scene_tree = 0;
  double worst_r1 = 0.0, worst_r2 = 0.0;
  const auto worst = [](const control::TrajectoryController& c, double& w) {
    for (double e : c.state().error_positions) w = std::max(w, std::abs(e));
  };
  const int kBeforeDelete = 1500, kAfterDelete = 4000;  // to 5.5 s: the second trajectory's end
  for (int k = 0; k < kBeforeDelete + kAfterDelete; ++k) {
    if (k == kBeforeDelete) {
      const std::size_t queued = both->queuedInputCount();
      ASSERT_TRUE(both->deleteBody("r2").ok());
      EXPECT_EQ(both->queuedInputCount(), queued - 2);  // r2's wrench and timed effort
      EXPECT_EQ(both->queuedInputCount(), one->queuedInputCount());
      EXPECT_EQ(both->data().controllers.waiting.size(), one->data().controllers.waiting.size());
      EXPECT_EQ(both->model().joint_by_name.count("r2/joint1"), 0u);
      EXPECT_EQ(both->scene().findLink("r2/link1"), -1);
      EXPECT_EQ(both->model().trees.size(), 2u);
      EXPECT_EQ(both->scene().bodies.size(), one->scene().bodies.size());
      EXPECT_EQ(both->data().controllers.running.size(), 2u);
      EXPECT_FALSE(both->commandTrajectory("r2/arm_controller", reach(kJoints, 0.1)).ok());
      EXPECT_FALSE(both->deleteBody("r2").ok());
    }
    for (World* w : {both.get(), one.get(), none.get()}) w->step();
    const auto& s0 = both->data().trees[scene_tree].state;
    for (World* w : {one.get(), none.get()}) {
      const auto& s = w->data().trees[scene_tree].state;
      ASSERT_TRUE(sameBits(s.q, s0.q) && sameBits(s.v, s0.v)) << "scene arm, step " << k;
    }
    const auto& a = both->data().trees[treeOf(*both, "r1/joint1")].state;
    const auto& b = one->data().trees[treeOf(*one, "r1/joint1")].state;
    ASSERT_TRUE(sameBits(a.q, b.q) && sameBits(a.v, b.v))
        << "r1, step " << k << ": |dq| " << (a.q - b.q).norm() << ", |dv| " << (a.v - b.v).norm();
    if (k < 2000) worst(controllerOf(*both, "r1/arm_controller"), worst_r1);
    if (k < kBeforeDelete) worst(controllerOf(*both, "r2/arm_controller"), worst_r2);
  }
  // The controller's own path tolerance (config/arm7_controllers.yaml): a violation would have
  // aborted the trajectory; the stiff servos keep the lag near a milliradian.
  EXPECT_LT(worst_r1, 0.05);
  EXPECT_LT(worst_r2, 0.05);
  // The second trajectory (from 2.5 s, 2 s long, and goal_time 1 s) ran to its goal; that r1
  // stayed bit-identical to `one` through the wrench and the effort after the deletion says
  // they were kept and reached the same link and joint of r1 under its shifted indices.
  const auto& r1 = controllerOf(*both, "r1/arm_controller");
  EXPECT_EQ(r1.status(), control::TrajectoryStatus::kSucceeded) << r1.reason();
  const Eigen::VectorXd& q = both->data().trees[treeOf(*both, "r1/joint1")].state.q;
  const auto goal = reach(kJoints, 0.3).points.back().positions;
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(q[k], goal[k], 0.01) << kJoints[k];  // goal tolerance
  // Every joint of the scene's arm and r1 in /joint_states, r1's prefixed.
  std::vector<std::string> names;
  for (const auto& j : both->jointStates()) names.push_back(j.name);
  ASSERT_EQ(names.size(), 14u);
  EXPECT_EQ(names[7], "r1/joint1");
}

// Truth: placing the robot moves every frame of it rigidly: each link of the copy at P is P
// times that link of the scene's arm (at the same joint positions, here the initial zero pose),
// to the round-off of composing unit motors (1e-12 m, 1e-12 in rotation entries, on numbers of
// order 1). reset() brings the robot back to that placement exactly.
TEST(WorldSpawnRobots, PlacementMovesTheWholeRobotAndResetReturnsToIt) {
  auto w = armWorld();
  const Eigen::Isometry3d P = at(2.0, -1.0, 1.2);
  ASSERT_TRUE(w->spawnUrdf("copy", armUrdf(), P, kZero, kZero, robotOptions("c")).ok());
  std::map<std::string, Eigen::Isometry3d> frames;
  for (const FramePose& f : w->movingFrames()) frames[f.child] = f.pose;
  for (const FramePose& f : w->staticFrames())
    if (f.parent == w->config().world_frame) frames[f.child] = f.pose;
  for (const std::string link : {"base_link", "link1", "link4", "link7"}) {
    ASSERT_TRUE(frames.count(link) && frames.count("c/" + link)) << link;
    const Eigen::Isometry3d expected = P * frames[link];
    EXPECT_LT((frames["c/" + link].translation() - expected.translation()).norm(), 1e-12) << link;
    EXPECT_LT((frames["c/" + link].linear() - expected.linear()).norm(), 1e-12) << link;
  }
  const int t = treeOf(*w, "c/joint1");
  const dynamics::TreeState initial = w->data().trees[t].state;
  w->step(300);  // it swings under gravity, its servos holding q = 0
  w->reset();
  EXPECT_TRUE(sameBits(w->data().trees[t].state.q, initial.q));
  EXPECT_TRUE(sameBits(w->data().trees[t].state.v, initial.v));
}

// The arm as a free robot: no world link, base_link given a mass (a 4 kg cylinder of the
// collision's size).
std::string freeArmUrdf() {
  std::string urdf = armUrdf();
  const auto cut = [&urdf](const std::string& from, const std::string& to) {
    const std::size_t a = urdf.find(from), b = urdf.find(to, a);
    urdf.erase(a, b + to.size() - a);
  };
  cut("<link name=\"world\"/>", "/>");
  cut("<joint name=\"world_to_base\"", "</joint>");
  const std::string base = "<link name=\"base_link\">";
  urdf.insert(urdf.find(base) + base.size(),
              "<inertial><origin xyz=\"0 0 0.075\"/><mass value=\"4\"/>"
              "<inertia ixx=\"0.0139\" ixy=\"0\" ixz=\"0\" iyy=\"0.0139\" iyz=\"0\" "
              "izz=\"0.0128\"/></inertial>");
  return urdf;
}

// Truth: in zero gravity, with no input, a free tree's world momentum is conserved, and the
// default integrator carries it exactly (doc/articulated.md#integrators): the spawned robot's
// linear and angular momentum about the origin, as momentum() recomputes them from its links,
// stay at their initial values to round-off — 1e-12 relative to |P| and |L|, about 1e3 ulps of
// the sums over 8 links over 2000 steps. The velocity it was given is its root's: P = m_total v
// when the links start at rest in their joints and the root does not turn.
TEST(WorldSpawnRobots, FreeRobotKeepsItsMomentumInZeroGravity) {
  auto w = armWorld(kZero);
  const Eigen::Vector3d v(0.3, -0.2, 0.1), omega(0.4, 0.1, -0.3);
  auto spawned = w->spawnUrdf("flyer", freeArmUrdf(), at(0.0, 4.0), v, omega, robotOptions("f"));
  ASSERT_TRUE(spawned.ok()) << spawned.error();
  EXPECT_EQ(w->model().robots.size(), 1u);
  const auto total = [&w]() {
    MomentumReport sum;
    for (const MomentumReport& m : w->momentum())
      if (m.kind == MomentumReport::Kind::kBody && m.body.rfind("f/", 0) == 0) {
        sum.linear += m.linear;
        sum.angular_origin += m.angular_origin;
      }
    return sum;
  };
  const MomentumReport start = total();
  // The links start at rest in their joints: the robot moves as one rigid body with the root's
  // motion, each link's centre at v + ω × (c − c_root) (rigid-body kinematics, not the code
  // under test), so its momentum is Σ m (v + ω × (c − c_root)).
  const Model& model = w->model();
  Eigen::Vector3d c_root = Eigen::Vector3d::Zero(), P = Eigen::Vector3d::Zero();
  for (const BodyStateReport& b : w->bodyStates())
    if (b.name == "f/base_link") c_root = b.com;
  for (const BodyStateReport& b : w->bodyStates()) {
    if (b.name.rfind("f/", 0) != 0) continue;
    const double m = model.moving[model.moving_of_body[model.findBody(b.name)]].inertia.mass();
    P += m * (v + omega.cross(b.com - c_root));
  }
  // Round-off of composing the links' poses and velocities: 1e-12 relative.
  EXPECT_LT((start.linear - P).norm(), 1e-12 * P.norm()) << start.linear.transpose();
  // Its servos move the arm through a trajectory (internal torques: they move momentum
  // between the links, never change the total).
  control::JointTrajectory t;
  t.joint_names = kJoints;
  control::TrajectoryPoint p;
  p.positions = {0.5, 0.8, 0.3, -1.0, 0.2, 0.5, 0.1};
  p.time_from_start = 1.0;
  t.points = {p};
  ASSERT_TRUE(w->commandTrajectory("f/arm_controller", t).ok());
  w->step(2000);
  const MomentumReport end = total();
  EXPECT_LT((end.linear - start.linear).norm(), 1e-12 * start.linear.norm());
  EXPECT_LT((end.angular_origin - start.angular_origin).norm(),
            1e-12 * start.angular_origin.norm());
  EXPECT_GT(std::abs(w->data().trees[treeOf(*w, "f/joint2")].state.q[1]), 0.5);  // it moved
}

// Truth: a refused request changes nothing: after every refusal below the world steps exactly
// as a world that never received them (every body's state bit for bit), its topology version
// and names unchanged. Each refusal names the field and the rule.
TEST(WorldSpawnRobots, RefusalsLeaveTheWorldBitIdentical) {
  // With a ball bouncing on a ground plane beside the arms: the last step's contacts are part
  // of what must not change.
  WorldConfig config;
  config.ground_plane = GroundPlane{};
  auto w = armWorld({0, 0, -9.81}, config), clean = armWorld({0, 0, -9.81}, config);
  const std::string urdf = armUrdf();
  const std::string ball =
      "<robot name=\"ball\"><link name=\"ball\"><inertial><mass value=\"1\"/><inertia "
      "ixx=\"0.004\" iyy=\"0.004\" izz=\"0.004\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>"
      "<collision><geometry><sphere radius=\"0.1\"/></geometry></collision></link></robot>";
  Eigen::Isometry3d above = at(0, -3);
  above.translation().z() = 0.3;
  for (World* x : {w.get(), clean.get()}) {
    ASSERT_TRUE(x->spawnUrdf("r1", urdf, at(3, 0), kZero, kZero, robotOptions("r1")).ok());
    ASSERT_TRUE(x->spawnUrdf("ball", ball, above, kZero, kZero).ok());
    x->step(260);  // the ball lands after 0.2 s (h = 0.2 m) and rests
  }
  ASSERT_FALSE(w->data().contacts.empty());
  const auto version = w->topologyVersion();
  const std::size_t bodies = w->scene().bodies.size();
  Eigen::Isometry3d nan_pose = at(0, 3);
  nan_pose.translation().y() = std::nan("");
  SpawnOptions bad_type = robotOptions("r9");
  {
    ParamValue::Map yaml = bad_type.controllers.asMap();
    ParamValue::Map c = yaml["arm_controller"].asMap();
    c["type"] = std::string("position_controllers/NoSuchController");
    yaml["arm_controller"] = ParamValue(c);
    bad_type.controllers = ParamValue(yaml);
  }
  struct Case {
    std::string name, urdf;
    SpawnOptions options;
    Eigen::Isometry3d pose;
    Eigen::Vector3d v;
    std::string expected;
  };
  const Case cases[] = {
      {"r2", urdf, robotOptions("r 2"), at(0, 3), kZero,
       "spawn_urdf.robot_namespace: 'r 2' is not a valid ROS name"},
      {"r2", urdf, robotOptions("/r2"), at(0, 3), kZero, "not a valid ROS name"},
      {"r2", urdf, robotOptions("r2/"), at(0, 3), kZero, "not a valid ROS name"},
      {"r2", urdf, robotOptions("2r"), at(0, 3), kZero, "not a valid ROS name"},
      {"r2", urdf, robotOptions("r1"), at(0, 3), kZero,
       "spawn_urdf.robot_namespace: the robot's link 'r1/base_link' clashes"},
      {"r1", urdf, robotOptions("r2"), at(0, 3), kZero,
       "spawn_urdf.name: robot 'r1' already exists"},
      {"link3", urdf, robotOptions("r2"), at(0, 3), kZero,
       "spawn_urdf.name: body 'link3' already exists"},
      {"r2", urdf, robotOptions(""), at(0, 3), kZero, "clashes"},
      {"r2", urdf, robotOptions("r2"), nan_pose, kZero,
       "spawn_urdf.pose.translation.y: not finite"},
      {"r2", urdf, robotOptions("r2"), at(0, 3), Eigen::Vector3d(1, 0, 0),
       "spawn_urdf.linear_velocity: must be zero: the robot is fixed to the world (its root "
       "link is 'world')"},
      {"r2", "<robot name=\"x\"><link", robotOptions("r2"), at(0, 3), kZero, "spawn_urdf 'r2'"},
      {"r9", urdf, bad_type, at(0, 3), kZero,
       "spawn_urdf.controllers: controllers.arm_controller.type"},
  };
  for (const Case& c : cases) {
    auto r = w->spawnUrdf(c.name, c.urdf, c.pose, c.v, kZero, c.options);
    ASSERT_FALSE(r.ok()) << c.expected;
    EXPECT_NE(r.error().find(c.expected), std::string::npos) << r.error();
    EXPECT_EQ(w->topologyVersion(), version) << c.expected;
    EXPECT_EQ(w->scene().bodies.size(), bodies) << c.expected;
    EXPECT_EQ(w->model().robots.size(), 1u) << c.expected;
    EXPECT_EQ(w->contacts().size(), clean->contacts().size()) << c.expected;  // still reported
  }
  // A part of a robot is not deleted alone.
  auto part = w->deleteBody("r1/link3");
  ASSERT_FALSE(part.ok());
  EXPECT_EQ(part.error(),
            "delete_body.body: body 'r1/link3' belongs to the spawned robot 'r1' (delete the "
            "robot whole, by its name)");
  EXPECT_FALSE(w->deleteBody("link3").ok());  // the scene's tree, as before
  EXPECT_EQ(w->topologyVersion(), version);
  EXPECT_EQ(w->data().controllers.running.size(), clean->data().controllers.running.size());

  for (World* x : {w.get(), clean.get()})
    ASSERT_TRUE(x->commandTrajectory("r1/arm_controller", reach(kJoints, 1.0)).ok());
  for (int k = 0; k < 300; ++k) {
    w->step();
    clean->step();
  }
  const auto a = w->bodyStates(), b = clean->bodyStates();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_TRUE(a[i].state.M_WB.coefficients() == b[i].state.M_WB.coefficients()) << a[i].name;
    EXPECT_TRUE(a[i].state.omega_B.rot == b[i].state.omega_B.rot &&
                a[i].state.omega_B.trans == b[i].state.omega_B.trans)
        << a[i].name;
  }
}

}  // namespace world_spawn_robots_test
}  // namespace sim
}  // namespace cga_rigid_sim
