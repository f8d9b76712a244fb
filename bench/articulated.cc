// bench_articulated: our side of the articulated benchmark (doc/benchmarks-articulated.md).
//
// Every case of bench/cases/articulated_cases.h is loaded from its URDF (scene::loadUrdfFile,
// the case's gravity, the initial joint positions and velocities and a floating base's angular
// and linear velocity through SceneOptions::initial_state), its collision shapes are dropped (the
// peers run without contacts; the URDFs' shapes would otherwise meet within a tree) and it runs
// in a sim::World (WorldConfig: dt = h, the config's integrator, one thread, no ground plane).
// Joint states come from World::jointStates() (matched to the case by joint name), a floating
// base's pose and velocities from getBodyState(base link).
//
// The sweep, the timing protocol, the metrics and the CSV are the peers'
// (bench/peers/articulated_common.h, compiled in, no peer engine linked): median over 3 fresh
// runs of the thread-CPU time of world->step(n), errors from a separate run that reads the
// joint state after every step. Output: bench/out/articulated_cga_rigid_sim.csv; configs = the
// integrators that apply to trees (--configs, default all of kTreeIntegrators).
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "articulated_common.h"
#include "cga_rigid_sim/scene/param_value.h"
#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"

#ifndef BENCH_REPO_ROOT
#define BENCH_REPO_ROOT "."
#endif

namespace cga_rigid_sim {
namespace benchmark {
namespace {

using ::bench::articulated::ArticulatedCase;
using ::bench::articulated::BaseState;

// The ~integrator names for trees (doc/articulated.md, tree/tree_integrator.h): auto and
// cga2 (the variational midpoint), cga4 (its triple jump), rk4 and euler on ABA.
const char* const kTreeIntegrators[] = {"auto", "cga2", "cga4", "rk4", "euler"};

scene::ParamValue list3(const std::array<double, 3>& a) {
  return scene::ParamValue(scene::ParamValue::List{a[0], a[1], a[2]});
}

class OurArticulated : public ::bench::articulated::ArticulatedSim {
 public:
  OurArticulated(const ArticulatedCase& c, double h, const std::string& integrator) {
    scene::SceneOptions options;
    options.gravity_W = Eigen::Vector3d(c.gravity[0], c.gravity[1], c.gravity[2]);
    scene::ParamValue::Map init;
    for (int i = 0; i < c.n(); ++i)
      init[c.joints[i].joint] =
          scene::ParamValue(scene::ParamValue::Map{{"position", c.q0[i]}, {"velocity", c.qd0[i]}});
    if (c.base.floating) {
      // The base starts at its URDF pose (the identity); its CoM velocity follows from v0, w0.
      const Eigen::Vector3d w0(c.base.w0[0], c.base.w0[1], c.base.w0[2]);
      const Eigen::Vector3d com(c.base.com[0], c.base.com[1], c.base.com[2]);
      const Eigen::Vector3d vc =
          Eigen::Vector3d(c.base.v0[0], c.base.v0[1], c.base.v0[2]) + w0.cross(com);
      init[c.base.link] = scene::ParamValue(
          scene::ParamValue::Map{{"angular_velocity", list3(c.base.w0)},
                                 {"linear_velocity", list3({vc.x(), vc.y(), vc.z()})}});
      base_link_ = c.base.link;
      base_com_ = com;
    }
    options.initial_state = scene::ParamValue(init);
    Result<scene::Scene> loaded =
        scene::loadUrdfFile(std::string(BENCH_REPO_ROOT) + "/" + c.urdf, options);
    if (!loaded) throw std::runtime_error("loading " + c.urdf + ": " + loaded.error());
    scene::Scene sc = *loaded;
    for (scene::BodyModel& b : sc.bodies) b.shapes.clear();  // no contacts, as for the peers
    sim::WorldConfig config;
    config.dt = h;
    config.integrator = integrator;
    config.threads = 1;
    Result<std::unique_ptr<sim::World>> w = sim::World::create(std::move(sc), config);
    if (!w) throw std::runtime_error("World::create: " + w.error());
    world_ = std::move(w).value();
    // Case order -> index in jointStates().
    const std::vector<sim::JointStateReport> js = world_->jointStates();
    for (const auto& j : c.joints) {
      int found = -1;
      for (size_t k = 0; k < js.size(); ++k)
        if (js[k].name == j.joint) found = static_cast<int>(k);
      if (found < 0) throw std::runtime_error("the world has no joint '" + j.joint + "'");
      index_.push_back(found);
    }
  }
  void step(long n) override { world_->step(static_cast<std::uint64_t>(n)); }
  void joints(std::vector<double>* q, std::vector<double>* qd) override {
    const std::vector<sim::JointStateReport> js = world_->jointStates();
    q->resize(index_.size());
    qd->resize(index_.size());
    for (size_t i = 0; i < index_.size(); ++i) {
      (*q)[i] = js[index_[i]].position;
      (*qd)[i] = js[index_[i]].velocity;
    }
  }
  bool base(BaseState<double>* b) override {
    if (base_link_.empty()) return false;
    Result<sim::BodyStateReport> r = world_->getBodyState(base_link_);
    if (!r) throw std::runtime_error("getBodyState: " + r.error());
    b->R = r->pose_root.linear();
    b->p = r->pose_root.translation();
    b->w = r->angular_velocity;
    b->v = r->linear_velocity - b->w.cross(b->R * base_com_);  // CoM velocity -> origin velocity
    return true;
  }

 private:
  std::unique_ptr<sim::World> world_;
  std::vector<int> index_;
  std::string base_link_;
  Eigen::Vector3d base_com_ = Eigen::Vector3d::Zero();
};

}  // namespace
}  // namespace benchmark
}  // namespace cga_rigid_sim

int main(int argc, char** argv) {
  using ::bench::articulated::ArticulatedConfig;
  std::vector<ArticulatedConfig> configs;
  for (const char* name : cga_rigid_sim::benchmark::kTreeIntegrators) {
    const std::string integ = name;
    configs.push_back({integ, [integ](const ::bench::articulated::ArticulatedCase& c, double h) {
                         return std::unique_ptr<::bench::articulated::ArticulatedSim>(
                             new cga_rigid_sim::benchmark::OurArticulated(c, h, integ));
                       }});
  }
  return ::bench::articulated::runArticulatedSweep("cga_rigid_sim", "cga_rigid_sim (sim::World)",
                                                   configs, argc, argv);
}
