// scene_summary <file.urdf> [integrator] [--all] [--strict]: loads a URDF scene as the simulator
// would (default options: gravity 0 0 -9.81, the inertia repairs of doc/urdf.md#inertias-from-cad
// made with warnings, no initial state) and prints its summary — every entry with --all; with
// --strict the repairs are refused as the node's ~relax_inertia:=false refuses them — or the
// loader's error on stderr with exit status 1. ROS-free.
#include "cga_rigid_sim/scene/scene_summary.h"

#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

int main(int argc, char** argv) {
  using namespace cga_rigid_sim::scene;
  std::vector<std::string> args;
  bool all = false, strict = false, help = false;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--all")
      all = true;
    else if (a == "--strict")
      strict = true;
    else if (a == "-h" || a == "--help")
      help = true;
    else
      args.push_back(a);
  }
  if (help || args.empty() || args.size() > 2) {
    std::cerr << "usage: scene_summary <file.urdf> [integrator] [--all] [--strict]\n"
                 "  integrator: cga2 | cga4 | exact | auto (default) | euler | rk4\n"
                 "  --all: list every body and joint (by default a long list is cut)\n"
                 "  --strict: refuse the inertia repairs (~relax_inertia:=false)\n";
    return help ? 0 : 1;
  }
  const std::string integrator = args.size() == 2 ? args[1] : "auto";
  const auto& names = summaryIntegratorNames();
  if (std::find(names.begin(), names.end(), integrator) == names.end()) {
    std::cerr << "scene_summary: unknown integrator '" << integrator << "' (known:";
    for (const auto& n : names) std::cerr << " " << n;
    std::cerr << ")\n";
    return 1;
  }
  SceneOptions options;
  if (strict) options.triangle_policy = cga_rigid_sim::dynamics::TrianglePolicy::kRefuse;
  const auto scene = loadUrdfFile(args[0], options);
  if (!scene) {
    std::cerr << scene.error() << "\n";
    return 1;
  }
  SummaryOptions summary;
  if (all) summary.max_bodies = summary.max_robot_entries = 0;
  summary.whole_list = "scene_summary " + args[0] + " --all lists every entry";
  std::cout << sceneSummary(*scene, integrator, summary);
  return 0;
}
