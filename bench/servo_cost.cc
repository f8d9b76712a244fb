// bench_servo_cost: what joint servos cost per step (issue: "a position-servoed 7-DoF arm costs
// no more than 10 % over the same arm with efforts"). The arm of urdf/arm7.urdf at dt = 1 ms,
// held still at the same pose by efforts (the holding torques) and by position servos (a
// reference at which their torque is the holding torque): the same state, so the difference is
// what servos cost; and, moving, a position trajectory controller following a reach (its cost
// includes the motion's: more iterations of the implicit step). Thread CPU time per step, the
// best of interleaved repeats (the machine may be shared); written to bench/out/servo_cost.csv.
// (Driving an effort arm along the servo arm's motion open-loop does not work: it drifts off
// the recorded motion within a second, so the two would not be doing the same work.)
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_clock.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/world.h"
#include "cga_rigid_sim/tree/articulated_body.h"

#ifndef CGA_RIGID_SIM_SOURCE_DIR
#define CGA_RIGID_SIM_SOURCE_DIR "."
#endif

namespace {

using namespace cga_rigid_sim;
using scene::ParamValue;

constexpr double kGain = 4000.0;  // pid_gains p of every joint, N m/rad
const std::vector<std::string> kJoints = {"joint1", "joint2", "joint3", "joint4",
                                          "joint5", "joint6", "joint7"};

std::unique_ptr<sim::World> arm(const sim::WorldConfig& config = sim::WorldConfig{}) {
  scene::SceneOptions options;
  options.gravity_W = {0, 0, -9.81};
  ParamValue::Map initial;
  const double q0[7] = {0.3, 0.6, -0.2, -1.0, 0.4, 0.5, 0.1};
  for (int k = 0; k < 7; ++k) {
    ParamValue::Map j;
    j["position"] = q0[k];
    initial[kJoints[k]] = ParamValue(j);
  }
  options.initial_state = ParamValue(initial);
  auto scene =
      scene::loadUrdfFile(std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/arm7.urdf", options);
  if (!scene) std::fprintf(stderr, "%s\n", scene.error().c_str()), std::exit(1);
  auto world = sim::World::create(std::move(*scene), config);
  if (!world) std::fprintf(stderr, "%s\n", world.error().c_str()), std::exit(1);
  return std::move(*world);
}

ParamValue controllers(const std::string& type) {
  ParamValue::List joints;
  for (const auto& j : kJoints) joints.emplace_back(j);
  ParamValue::Map c, yaml;
  c["type"] = type;
  c["joints"] = ParamValue(joints);
  yaml["arm"] = ParamValue(c);
  return ParamValue(yaml);
}

ParamValue pidGains() {
  ParamValue::Map m;
  for (const auto& j : kJoints) {
    ParamValue::Map g;
    g["p"] = kGain;
    g["d"] = 150.0;
    m[j] = ParamValue(g);
  }
  return ParamValue(m);
}

std::unique_ptr<sim::World> groupPosition() {
  auto w = arm();
  w->loadControllers(controllers("position_controllers/JointGroupPositionController"), {},
                     pidGains());
  return w;
}

std::unique_ptr<sim::World> trajectory() {
  auto w = arm();
  w->loadControllers(controllers("position_controllers/JointTrajectoryController"), {}, pidGains());
  control::JointTrajectory t;
  t.joint_names = kJoints;
  control::TrajectoryPoint p;
  p.positions = {0.6, 0.9, 0.1, -0.6, 0.7, 0.8, 0.4};
  p.velocities.assign(7, 0.0);
  p.time_from_start = 20.0;  // longer than the timed run: the whole run follows it
  t.points = {p};
  w->commandTrajectory("arm", t);
  return w;
}

}  // namespace

// The torques that hold the arm still at its start pose (the RNEA at rest under gravity).
std::vector<double> holdingTorques(const sim::World& w) {
  const auto& tree = w.model().trees[0].body;
  const auto& s = w.data().trees[0].state;
  dynamics::TreeKinematics kin;
  dynamics::treeKinematics(tree, s, kin);
  dynamics::BodyMoments f;
  dynamics::gravityMoments(tree, kin, {0, 0, -9.81}, f);
  const Eigen::VectorXd hold =
      dynamics::inverseDynamics(tree, s, kin, Eigen::VectorXd::Zero(tree.velocityCount()), f);
  return std::vector<double>(hold.data(), hold.data() + hold.size());
}

// Held still by efforts: the holding torques, as an effort controller would send them.
std::unique_ptr<sim::World> efforts() {
  auto w = arm();
  sim::JointEffortInput in;
  in.names = kJoints;
  in.efforts = holdingTorques(*w);
  w->setJointEfforts(in);
  return w;
}

// Held still by position servos: the reference r = q₀ + τ_hold/kp, where the servo's torque is
// the holding torque, so the arm stays at q₀ as the effort arm does.
std::unique_ptr<sim::World> heldByServos() {
  auto w = groupPosition();
  const std::vector<double> hold = holdingTorques(*w);
  std::vector<double> r(7);
  for (int k = 0; k < 7; ++k) r[k] = w->data().trees[0].state.q[k] + hold[k] / kGain;
  w->commandGroup("arm", r);
  return w;
}

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 5000,
            repeats = argc > 2 ? std::atoi(argv[2]) : 7;
  const char* names[3] = {"efforts_holding", "servos_holding", "servos_trajectory"};
  // A third argument runs one case alone (0–2: for callgrind's per-case counts).
  const int only = argc > 3 ? std::atoi(argv[3]) : -1;
  double best[3] = {1e300, 1e300, 1e300};
  for (int r = 0; r < repeats; ++r)
    for (int c = 0; c < 3; ++c) {  // interleaved: a load on the machine hits all alike
      if (only >= 0 && c != only) continue;
      auto w = c == 0 ? efforts() : c == 1 ? heldByServos() : trajectory();
      w->step(100);  // warm: caches, the integrator's history
      const double t0 = benchmark::threadCpuSeconds();
      w->step(static_cast<std::uint64_t>(steps));
      best[c] = std::min(best[c], (benchmark::threadCpuSeconds() - t0) / steps * 1e9);
    }
  const std::string path = std::string(BENCH_OUT_DIR) + "/servo_cost.csv";
  std::FILE* out = std::fopen(path.c_str(), "w");
  if (out) std::fprintf(out, "case,ns_per_step,ratio_to_efforts\n");
  for (int c = 0; c < 3; ++c) {
    const double ratio = best[c] / best[0];
    std::printf("%-18s %8.0f ns/step  %.3f x efforts_holding\n", names[c], best[c], ratio);
    if (out) std::fprintf(out, "%s,%.1f,%.4f\n", names[c], best[c], ratio);
  }
  if (out) std::fclose(out);
  return 0;
}
