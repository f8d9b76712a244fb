// The guards of a tree step (stage_trees.cc, doc/articulated.md#faults): a step that leaves a
// joint past its limit, that the implicit integrator could not solve, or — in a contact step —
// that raises the tree's energy beyond its inputs' work or changes a floating tree's momentum by
// more than its external impulses, is undone: the tree is put back at rest at its pose before
// the step, the fault is counted and described naming the tree, the joint or contact pair and
// the rule, and the energy book still balances (the kinetic energy it had is booked as
// dissipated). Each guard is made to fire by an integrator that breaks its rule on purpose in
// one step, injected into the Data of a real scene, which the stages then step as World::step
// does.
#include <gtest/gtest.h>

#include <cmath>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/reports.h"
#include "cga_rigid_sim/sim/stages.h"
#include "cga_rigid_sim/tree/tree_integrator.h"
#include "common/real_like_robots.h"

namespace cga_rigid_sim {
namespace sim {
namespace tree_guards_test {

enum class Break { kUnsolved, kPastLimit, kAddEnergy, kFlipBase };

// The real integrator, which in step `at` breaks one rule.
class Breaking final : public dynamics::TreeIntegrator {
 public:
  Breaking(std::unique_ptr<dynamics::TreeIntegrator> inner, Break what, int at)
      : inner_(std::move(inner)), what_(what), at_(at) {}
  const char* name() const override { return "breaking"; }
  void step(const dynamics::ArticulatedBody& tree, const dynamics::TreeLoads& loads, double h,
            dynamics::TreeState& state) override {
    inner_->step(tree, loads, h, state);
    broken_ = ++steps_ == at_;
    if (!broken_) return;
    switch (what_) {
      case Break::kUnsolved:
        break;
      case Break::kPastLimit:
        state.q[0] = tree.joints()[0].upper + 0.1;
        break;
      case Break::kAddEnergy:
        state.v[0] += 1.0;
        break;
      case Break::kFlipBase:  // the same kinetic energy, the opposite momentum
        state.omega_0 = state.omega_0 * -1.0;
        state.v *= -1.0;
        break;
    }
  }
  void reset() override { inner_->reset(); }
  double lastDissipated() const override { return inner_->lastDissipated(); }
  bool lastLimited() const override { return inner_->lastLimited(); }
  bool conservesMomentum() const override { return inner_->conservesMomentum(); }
  bool lastSolved() const override {
    return !(broken_ && what_ == Break::kUnsolved) && inner_->lastSolved();
  }

 private:
  std::unique_ptr<dynamics::TreeIntegrator> inner_;
  Break what_;
  int at_;
  int steps_ = 0;
  bool broken_ = false;
};

struct Scene {
  Model model;
  Data data;
};

Scene load(const std::string& urdf, const Eigen::Vector3d& g, scene::ParamValue initial,
           bool plane) {
  scene::SceneOptions options;
  options.gravity_W = g;
  options.initial_state = std::move(initial);
  auto s = scene::loadUrdfString(urdf, "robot", options);
  EXPECT_TRUE(s.ok()) << s.error();
  WorldConfig config;
  if (plane) config.ground_plane = GroundPlane{};
  auto model = compileModel(std::move(s.value()), config);
  EXPECT_TRUE(model.ok()) << model.error();
  auto data = makeData(model.value());
  EXPECT_TRUE(data.ok()) << data.error();
  return {std::move(model.value()), std::move(data.value())};
}

void step(const Model& m, Data& d) {  // World::step's stages
  applyDueInputs(m, d);
  updateLoads(m, d);
  loadTrees(m, d);
  solveContacts(m, d);
  integrateTrees(m, d);
  integrateBodies(m, d);
  expireInputs(m, d);
}

double bookedEnergy(const Model& m, const Data& d) {
  const auto reports = momentumReports(m, d);
  const MomentumReport& t = reports.back();
  return t.kinetic_energy + t.potential_energy + t.dissipated_energy;
}

// The shared check: step `at` broke the rule; it was counted once, named, undone (the pose of
// the step before, at rest), and the book balances as before it (to the integrator's own
// energy error over those steps, 1e-6 of the energies involved).
void expectUndone(Scene& s, Break what, int at, TreeFaults::Rule rule, const std::string& words) {
  Model& m = s.model;
  Data& d = s.data;
  d.trees[0].integrator =
      std::make_unique<Breaking>(dynamics::makeTreeIntegrator("auto").value(), what, at);
  const double E0 = bookedEnergy(m, d);
  const std::uint64_t first = d.step_count;  // steps the scene took before
  for (int k = 1; k < at; ++k) step(m, d);
  const Eigen::VectorXd q_before = d.trees[0].state.q;
  const cga::Motor M_before = d.trees[0].state.M_W0;
  step(m, d);
  const TreeFaults& f = d.tree_faults;
  ASSERT_EQ(f.count, 1u);
  EXPECT_EQ(f.rule, rule);
  EXPECT_EQ(f.tree, 0);
  EXPECT_EQ(f.step, first + static_cast<std::uint64_t>(at));
  EXPECT_EQ(d.trees[0].state.q, q_before);
  EXPECT_EQ(d.trees[0].state.M_W0.coefficients(), M_before.coefficients());
  EXPECT_TRUE(d.trees[0].state.v.isZero(0.0));
  EXPECT_TRUE(d.trees[0].state.omega_0.rot.isZero(0.0) &&
              d.trees[0].state.omega_0.trans.isZero(0.0));
  EXPECT_NEAR(bookedEnergy(m, d), E0, 1e-6 * (std::abs(E0) + 1.0));
  const std::string message = treeFaultError(m, f).message();
  EXPECT_EQ(message.rfind("step.tree: tree '", 0), 0u) << message;
  EXPECT_NE(message.find(words), std::string::npos) << message;
  EXPECT_NE(message.find("it was undone and the tree is at rest"), std::string::npos) << message;
  // The next steps run on, unbroken.
  for (int k = 0; k < 10; ++k) step(m, d);
  EXPECT_EQ(d.tree_faults.count, 1u);
}

scene::ParamValue rate(const char* joint, double v) {
  scene::ParamValue::Map entry, m;
  entry["velocity"] = scene::ParamValue(v);
  m[joint] = scene::ParamValue(entry);
  return scene::ParamValue(m);
}

TEST(TreeGuards, AJointPastItsLimitIsUndoneAndNamed) {
  Scene s = load(test::overlappingArmUrdf(), {0, 0, -9.81}, rate("j1", 1.0), false);
  expectUndone(s, Break::kPastLimit, 20, TreeFaults::Rule::kLimit,
               "left joint 'j1' at 2.1, past its limit 2 (rule: no joint passes its limits)");
}

TEST(TreeGuards, AnUnsolvedStepIsUndone) {
  Scene s = load(test::overlappingArmUrdf(), {0, 0, -9.81}, rate("j2", -1.5), false);
  expectUndone(s, Break::kUnsolved, 7, TreeFaults::Rule::kNotSolved,
               "could not be solved: the implicit step did not converge");
}

// The gripper's fingers pressed on each other (closed by their efforts first; each finger is a
// tree of its own, hanging from the static palm): a contact step in which the left finger's drift
// gains a rate of 1 m/s raises its energy by 0.05 J, far beyond the tolerance (the kick-drift's
// own error is ~1e-9 J here).
TEST(TreeGuards, AContactStepThatCreatesEnergyIsUndoneNamingItsPair) {
  Scene s = load(test::gripperUrdf(), {0, 0, -9.81}, {}, false);
  for (TreeData& td : s.data.trees) td.held_effort.setConstant(5.0);  // each finger is a tree
  // Close them, then break a step while they touch.
  Model& m = s.model;
  Data& d = s.data;
  // They meet after ~35 steps; 150 leaves them pressed together and still awake (an island
  // sleeps after 0.2 s at rest, and a sleeping tree is not stepped).
  for (int k = 0; k < 150; ++k) step(m, d);
  ASSERT_FALSE(d.contacts.empty());
  ASSERT_FALSE(d.trees[0].asleep);
  ASSERT_EQ(d.tree_faults.count, 0u);
  expectUndone(s, Break::kAddEnergy, 5, TreeFaults::Rule::kEnergy,
               "(its deepest contact: 'left_finger' against 'right_finger')");
}

// A floating box with a hinged flap sliding on the ground: a contact step whose drift reverses
// the whole motion keeps the kinetic energy and flips the momentum: the momentum guard.
TEST(TreeGuards, AContactStepThatChangesAFloatingTreesMomentumIsUndone) {
  const std::string urdf =
      "<robot name='sled'><link name='body'>" + test::boxInertial(4.0, {0.4, 0.3, 0.1}) +
      test::boxCollision({0.4, 0.3, 0.1}) + "</link><link name='flap'>" +
      test::boxInertial(0.5, {0.1, 0.3, 0.02}, {0.05, 0, 0}) +
      test::boxCollision({0.1, 0.3, 0.02}, {0.05, 0, 0}) +
      "</link><joint name='hinge' type='revolute'><parent link='body'/><child link='flap'/>"
      "<origin xyz='0.21 0 0.04'/><axis xyz='0 1 0'/><limit lower='-1' upper='1' effort='10' "
      "velocity='5'/></joint></robot>";
  scene::ParamValue::Map body, initial;
  body["position"] = scene::ParamValue(std::vector<scene::ParamValue>{
      scene::ParamValue(0.0), scene::ParamValue(0.0), scene::ParamValue(0.05)});
  body["linear_velocity"] = scene::ParamValue(std::vector<scene::ParamValue>{
      scene::ParamValue(2.0), scene::ParamValue(0.0), scene::ParamValue(0.0)});
  initial["body"] = scene::ParamValue(body);
  Scene s = load(urdf, {0, 0, -9.81}, scene::ParamValue(initial), true);
  expectUndone(s, Break::kFlipBase, 30, TreeFaults::Rule::kMomentum,
               "changed the floating tree's momentum by");
}

}  // namespace tree_guards_test
}  // namespace sim
}  // namespace cga_rigid_sim
