// scene_summary <file.urdf> [integrator]: loads a URDF scene as the simulator would (default
// options: gravity 0 0 -9.81, triangle inequality enforced, no initial state) and prints the
// one-screen summary, or the loader's error on stderr with exit status 1. ROS-free.
#include "cga_rigid_sim/scene/scene_summary.h"

#include <algorithm>
#include <iostream>
#include <string>

#include "cga_rigid_sim/scene/urdf_loader.h"

int main(int argc, char** argv) {
  using namespace cga_rigid_sim::scene;
  if (argc < 2 || argc > 3 || std::string(argv[1]) == "-h" || std::string(argv[1]) == "--help") {
    std::cerr << "usage: scene_summary <file.urdf> [integrator]\n"
                 "  integrator: cga2 | cga4 | exact | auto (default) | euler | rk4\n";
    return argc == 2 ? 0 : 1;
  }
  const std::string integrator = argc == 3 ? argv[2] : "auto";
  const auto& names = summaryIntegratorNames();
  if (std::find(names.begin(), names.end(), integrator) == names.end()) {
    std::cerr << "scene_summary: unknown integrator '" << integrator << "' (known:";
    for (const auto& n : names) std::cerr << " " << n;
    std::cerr << ")\n";
    return 1;
  }
  const auto scene = loadUrdfFile(argv[1], SceneOptions());
  if (!scene) {
    std::cerr << scene.error() << "\n";
    return 1;
  }
  std::cout << sceneSummary(*scene, integrator);
  return 0;
}
