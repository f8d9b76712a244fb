// bench_robot_rest: a real robot falling onto the ground plane and lying there, traced: every
// `--every` seconds the fastest link (|v| of its centre of mass + |ω| · 0.5 m), whether its tree
// sleeps, the root's height, the deepest contact and its links, the energy balance (kinetic +
// potential + dissipated − initial), tree faults, and the wall time per step since the last
// line. The cases are the contact benchmark's (bench/peers/robot_cases.h): atlas_fall (Debian's
// dart-doc) and humanoid_fall (generated). Used for doc/decisions.md#a-resting-robots-island.
//
//   bench_robot_rest [--cases atlas_fall,humanoid_fall] [--T 10] [--every 0.5]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/world.h"
#include "robot_cases.h"

namespace cga_rigid_sim {
namespace robot_rest {

double energy(const sim::World& w) {
  const sim::MomentumReport t = w.momentum().back();
  return t.kinetic_energy + t.potential_energy + t.dissipated_energy;
}

int run(const bench::robots::RobotCase& c, double T, double every) {
  std::string urdf = c.urdf;
  if (c.generate) {
    const std::string dir =
        (std::filesystem::temp_directory_path() / ("robot_rest_" + c.name)).string();
    std::filesystem::create_directories(dir);
    urdf = dir + "/robot.urdf";
    std::FILE* f = std::fopen(urdf.c_str(), "w");
    const std::string text = c.generate(dir);
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
  } else if (!std::filesystem::exists(urdf)) {
    std::printf("%s: %s absent, skipped\n", c.name.c_str(), urdf.c_str());
    return 0;
  }
  Result<scene::Scene> loaded = scene::loadUrdfFile(urdf, scene::SceneOptions());
  if (!loaded) {
    std::fprintf(stderr, "%s\n", loaded.error().c_str());
    return 2;
  }
  sim::WorldConfig config;
  config.dt = c.h;
  config.threads = 1;
  config.ground_plane = sim::GroundPlane{c.ground_z, {}};
  auto made = sim::World::create(std::move(loaded).value(), config);
  if (!made) {
    std::fprintf(stderr, "%s\n", made.error().c_str());
    return 2;
  }
  sim::World& w = *made.value();
  const double e0 = energy(w);
  const long per = std::lround(every / c.h);
  std::printf("%s\n%6s %10s %-10s %6s %9s %10s %-28s %10s %6s %8s %11s %10s\n", c.name.c_str(), "t",
              "fastest", "(link)", "asleep", "root_z", "depth", "deepest", "balance", "faults",
              "ms/step", "dissipated", "kinetic");
  for (double t = 0; t < T - 1e-9; t += every) {
    const auto t0 = std::chrono::steady_clock::now();
    w.step(per);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
        per;
    double fastest = 0;
    std::string fastest_link;
    for (const sim::BodyStateReport& b : w.bodyStates()) {
      const double v = b.linear_velocity.norm() + 0.5 * b.angular_velocity.norm();
      if (v > fastest) fastest = v, fastest_link = b.name;
    }
    double depth = 0;
    std::string deepest;
    for (const sim::ContactReport& k : w.contacts())
      if (k.depth > depth) depth = k.depth, deepest = k.link_a + "/" + k.link_b;
    double root_z = 0;
    if (auto r = w.getBodyState(c.root_link)) root_z = r->pose_root.translation().z();
    const bool asleep = !w.data().trees.empty() && w.data().trees[0].asleep;
    std::printf("%6.2f %10.3g %-10s %6d %9.5f %10.3g %-28s %10.3g %6llu %8.4f %11.6f %10.3g\n",
                w.time(), fastest, fastest_link.substr(0, 10).c_str(), asleep ? 1 : 0, root_z,
                depth, deepest.substr(0, 28).c_str(), energy(w) - e0,
                static_cast<unsigned long long>(w.treeFaultCount()), ms,
                w.momentum().back().dissipated_energy, w.momentum().back().kinetic_energy);
    std::fflush(stdout);
  }
  if (w.treeFaultCount() > 0) std::printf("last fault: %s\n", w.lastTreeFault()->message().c_str());
  return 0;
}

}  // namespace robot_rest
}  // namespace cga_rigid_sim

int main(int argc, char** argv) {
  std::string cases = "atlas_fall,humanoid_fall";
  double T = 10, every = 0.5;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--cases"))
      cases = argv[i + 1];
    else if (!std::strcmp(argv[i], "--T"))
      T = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--every"))
      every = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: bench_robot_rest [--cases a,b] [--T s] [--every s]\n");
      return 2;
    }
  }
  int rc = 0;
  for (const bench::robots::RobotCase& c : bench::robots::allRobotCases())
    if (c.contacts && ("," + cases + ",").find("," + c.name + ",") != std::string::npos)
      rc |= cga_rigid_sim::robot_rest::run(c, T, every);
  return rc;
}
