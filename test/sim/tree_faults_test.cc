// Tree steps that leave a non-finite state (stage_trees.cc, doc/articulated.md#faults): undone,
// the tree set at rest at its pose before the step, counted and described by World; other
// trees step on unaffected; the contacts stage leaves out a tree whose kick is NaN. The scenes
// are findings of the URDF fuzz target (a link 2.2e7 m and 5.6e27 m from its joint), reduced;
// the tests fail without the undo (the first two) or without leaving the tree out (the third).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace sim {
namespace tree_faults_test {

// A fixed-base tree whose second link hangs 2.2e7 m from the first joint: its mass matrix,
// formed in the frame of the tree's root link, loses every digit of the 0.004 kg m² of the
// second joint (3 kg × (2.2e7 m)² × ε ≈ 0.3 kg m²), and its factorization fails at once.
const std::string kFarLink =
    "<link name='far_base'/>"
    "<joint name='far_weld' type='fixed'><parent link='world'/><child link='far_base'/></joint>"
    "<joint name='far_i' type='revolute'><parent link='far_base'/><child link='far_1'/>"
    "<limit effort='6' velocity='1'/></joint>"
    "<link name='far_1'><inertial><mass value='5'/>"
    "<inertia ixx='.014' ixy='0' ixz='0' iyy='.01' iyz='0' izz='.007'/></inertial></link>"
    "<joint name='far_j' type='revolute'><parent link='far_1'/><child link='far_2'/>"
    "<origin xyz='22222222 0 0'/><axis xyz='0 0 1'/><limit effort='0' velocity='1'/></joint>"
    "<link name='far_2'><inertial><mass value='3'/>"
    "<inertia ixx='0.02' ixy='0' ixz='0' iyy='.02' iyz='0' izz='.004'/></inertial></link>";

// A pendulum on the same world, to show that the other trees step on.
const std::string kPendulum =
    "<joint name='hinge' type='continuous'><parent link='world'/><child link='bob'/>"
    "<origin xyz='5 0 2'/><axis xyz='0 1 0'/><limit effort='5' velocity='100'/></joint>"
    "<link name='bob'><inertial><origin xyz='0 0 -1'/><mass value='1'/>"
    "<inertia ixx='0.01' ixy='0' ixz='0' iyy='0.01' iyz='0' izz='0.01'/></inertial></link>";

std::unique_ptr<World> makeWorld(const std::string& links, const std::string& integrator,
                                 double initial_angle = 0.0) {
  scene::SceneOptions options;
  if (initial_angle != 0.0) {
    scene::ParamValue::Map hinge, all;
    hinge["position"] = scene::ParamValue(initial_angle);
    all["hinge"] = scene::ParamValue(hinge);
    options.initial_state = scene::ParamValue(all);
  }
  auto scene = scene::loadUrdfString("<robot name='r'><link name='world'/>" + links + "</robot>",
                                     "test", options);
  EXPECT_TRUE(scene.ok()) << scene.error();
  WorldConfig config;
  config.integrator = integrator;
  auto world = World::create(std::move(scene.value()), config);
  EXPECT_TRUE(world.ok()) << world.error();
  return std::move(world.value());
}

void expectSameState(const dynamics::BodyState& a, const dynamics::BodyState& b,
                     const std::string& what) {
  EXPECT_EQ(a.M_WB.coefficients(), b.M_WB.coefficients()) << what;
  EXPECT_EQ(a.omega_B.rot, b.omega_B.rot) << what;
  EXPECT_EQ(a.omega_B.trans, b.omega_B.trans) << what;
}

TEST(TreeFaults, AStepThatLeavesNonFiniteNumbersIsUndoneCountedAndNamed) {
  for (const char* integrator : {"auto", "cga4", "rk4", "euler"}) {
    SCOPED_TRACE(integrator);
    auto w = makeWorld(kFarLink, integrator);
    const auto start = w->bodyStates();
    ASSERT_EQ(w->treeFaultCount(), 0u);
    EXPECT_FALSE(w->lastTreeFault());
    w->step();
    // Undone: every link where it was, at rest (it started at rest), bit for bit.
    const auto after = w->bodyStates();
    ASSERT_EQ(after.size(), start.size());
    for (std::size_t i = 0; i < after.size(); ++i) {
      EXPECT_TRUE(after[i].state.allFinite()) << after[i].name;
      expectSameState(after[i].state, start[i].state, after[i].name);
    }
    for (const JointStateReport& j : w->jointStates()) {
      EXPECT_EQ(j.position, 0.0) << j.name;
      EXPECT_EQ(j.velocity, 0.0) << j.name;
    }
    EXPECT_EQ(w->treeFaultCount(), 1u);
    ASSERT_TRUE(w->lastTreeFault());
    const std::string message = w->lastTreeFault()->message();
    EXPECT_NE(message.find("step.tree: tree 'far_base': step 1 left a non-finite state"),
              std::string::npos)
        << message;
    // Tried again from rest in every step, and every failed step counted.
    w->step(2);
    EXPECT_EQ(w->treeFaultCount(), 3u);
    EXPECT_NE(w->lastTreeFault()->message().find("step 3 left"), std::string::npos);
    for (const BodyStateReport& b : w->bodyStates()) EXPECT_TRUE(b.state.allFinite()) << b.name;
    EXPECT_TRUE(std::isfinite(w->momentum().back().kinetic_energy));
  }
}

TEST(TreeFaults, OtherTreesStepOnAsIfTheFaultyOneWereNotThere) {
  // The pendulum beside the faulty tree against the pendulum alone: the same states, bit for
  // bit (each tree has its own integrator; the undo touches only its tree).
  auto both = makeWorld(kFarLink + kPendulum, "auto", 0.8);
  auto alone = makeWorld(kPendulum, "auto", 0.8);
  both->step(200);
  alone->step(200);
  EXPECT_EQ(both->treeFaultCount(), 200u);
  const auto a = both->getBodyState("bob"), b = alone->getBodyState("bob");
  ASSERT_TRUE(a.ok() && b.ok());
  expectSameState(a->state, b->state, "bob");
  // And it did move: 200 ms of swinging from 0.8 rad.
  EXPECT_GT(b->state.omega_B.rot.norm(), 0.1);
  EXPECT_EQ(alone->treeFaultCount(), 0u);  // a sound tree never faults
}

TEST(TreeFaults, ATreeWhoseContactKickIsNotFiniteIsLeftOutOfTheContactSolve) {
  // The free brick overlaps the tree (and both the ground). The tree's kick is NaN at its pose;
  // solved with it, the brick's impulses were NaN in step 2 (the fuzz finding). Left out, the
  // brick's contact with the tree is dropped and every state stays finite.
  scene::SceneOptions options;
  auto scene = scene::loadUrdfFile(
      std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/test/sim/data/far_link_contact_kick.urdf", options);
  ASSERT_TRUE(scene.ok()) << scene.error();
  WorldConfig config;
  config.ground_plane = GroundPlane();
  auto w = World::create(std::move(scene.value()), config);
  ASSERT_TRUE(w.ok()) << w.error();
  for (int k = 1; k <= 5; ++k) {
    (*w)->step();
    for (const BodyStateReport& b : (*w)->bodyStates())
      EXPECT_TRUE(b.state.allFinite()) << b.name << " after step " << k;
    EXPECT_TRUE(std::isfinite((*w)->momentum().back().kinetic_energy)) << "after step " << k;
  }
}

}  // namespace tree_faults_test
}  // namespace sim
}  // namespace cga_rigid_sim
