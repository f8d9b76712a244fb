// Fuzz target: the URDF loader (loadUrdfString, scene/urdf/urdf_loader.h) on arbitrary text, with
// our extension elements (<cga_rigid_sim:mass_from_geometry>, <cga_rigid_sim:contact>), Gazebo
// friction and meshes. Mesh file names are resolved relative to the current directory, which
// is set to fuzz/meshes/ once: it holds closed and broken STL and OBJ meshes that the seeds
// (fuzz/corpus/urdf/) and the dictionary (fuzz/urdf.dict) name.
//
// Checks: the loader returns a scene or an error and never crashes (ASan, UBSan, LSan watch);
// an error is a non-empty message that starts with the source name; a loaded scene holds only
// finite numbers (common/finite_scene.h) and a World is built from it and stepped a few times,
// with contacts against a ground plane, without a non-finite state.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"
#include "common/finite_scene.h"

using namespace cga_rigid_sim;

namespace {
// Scenes with more bodies than this are loaded and checked but not stepped (speed).
constexpr std::size_t kMaxSteppedBodies = 8;
constexpr int kSteps = 3;
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (chdir(CGA_RIGID_SIM_SOURCE_DIR "/fuzz/meshes") != 0) fuzz::fail("cannot enter fuzz/meshes");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string xml(reinterpret_cast<const char*>(data), size);
  Result<scene::Scene> loaded = scene::loadUrdfString(xml, "fuzz_urdf", scene::SceneOptions());
  if (!loaded.ok()) {
    if (loaded.error().rfind("fuzz_urdf", 0) != 0)
      fuzz::fail("error does not start with the source name: " + loaded.error());
    return 0;
  }
  fuzz::checkSceneFinite(*loaded, "loaded scene");
  if (loaded->bodies.size() > kMaxSteppedBodies) return 0;

  sim::WorldConfig config;
  config.integrator = "auto";
  config.ground_plane = sim::GroundPlane();
  Result<std::unique_ptr<sim::World>> world = sim::World::create(std::move(*loaded), config);
  if (!world.ok()) {
    if (world.error().empty()) fuzz::fail("World::create refused with an empty message");
    return 0;
  }
  for (int k = 0; k < kSteps; ++k) {
    (*world)->step();
    for (const sim::BodyStateReport& body : (*world)->bodyStates())
      if (!body.state.allFinite())
        fuzz::fail("body '" + body.name + "' not finite after step " + std::to_string(k + 1));
  }
  return 0;
}
