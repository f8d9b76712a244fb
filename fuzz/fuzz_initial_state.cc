// Fuzz target: the initial-state dictionary (applyInitialState, scene/initial_state.h). The
// input's first line names one of the example scenes below (others: the first), the rest is
// the dictionary in flow text, read by the node's own parser (scene/flow_text.h), e.g.
//   double_pendulum
//   {shoulder: {position: 0.7, velocity: 0.5}, elbow: {position: nan}}
// Text that is not flow text is skipped. The scenes are loaded once; each input is applied to
// a copy.
//
// Checks: no crash or sanitizer report; a refused dictionary leaves the scene bit-identical
// (poses, velocities, joint positions and velocities, warnings) and its message starts with
// the source and names initial_state; an accepted one leaves only finite numbers.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "cga_rigid_sim/scene/flow_text.h"
#include "cga_rigid_sim/scene/initial_state.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "common/finite_scene.h"

using namespace cga_rigid_sim;

namespace {

// The example scenes (urdf/<name>.urdf, each with an initial state in config/<name>.yaml):
// free bodies, static bodies, chains of continuous joints, revolute joints with limits.
const char* const kScenes[] = {"tennis_racket", "tabletop",    "double_pendulum", "arm7",
                               "dumbbell",      "many_bodies", "projectile",      "satellite",
                               "symmetric_top", "t_handle",    "thin_rod"};

std::vector<scene::Scene>& scenes() {
  static std::vector<scene::Scene> loaded;
  return loaded;
}

// The bytes of every number applyInitialState may change, and the warnings.
std::string fingerprint(const scene::Scene& s) {
  std::string out;
  auto add = [&out](const auto& coefficients) {
    out.append(reinterpret_cast<const char*>(coefficients.data()),
               coefficients.size() * sizeof(double));
  };
  for (const scene::BodyModel& b : s.bodies) {
    add(b.M_WB0.coefficients());
    add(b.omega_B0.coefficients());
  }
  for (const scene::JointModel& j : s.joints) {
    const double q[2] = {j.initial_position, j.initial_velocity};
    out.append(reinterpret_cast<const char*>(q), sizeof q);
  }
  for (const std::string& w : s.warnings) out += w + '\n';
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  for (const char* name : kScenes) {
    const std::string path = std::string(CGA_RIGID_SIM_SOURCE_DIR "/urdf/") + name + ".urdf";
    Result<scene::Scene> s = scene::loadUrdfFile(path, scene::SceneOptions());
    if (!s.ok()) fuzz::fail("cannot load " + path + ": " + s.error());
    scenes().push_back(std::move(*s));
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::size_t newline = text.find('\n');
  const std::string scene_name = text.substr(0, newline);
  std::size_t index = 0;
  for (std::size_t k = 0; k < scenes().size(); ++k)
    if (scene_name == kScenes[k]) index = k;
  const std::optional<scene::FlowValue> flow =
      scene::parseFlowText(newline == std::string::npos ? std::string() : text.substr(newline + 1));
  if (!flow) return 0;
  const scene::ParamValue dict = scene::toParamValue(*flow);

  scene::Scene s = scenes()[index];
  const std::string before = fingerprint(s);
  const Result<bool> applied = scene::applyInitialState(s, dict);
  if (!applied.ok()) {
    if (fingerprint(s) != before)
      fuzz::fail("refused dictionary changed the scene: " + applied.error());
    if (applied.error().rfind(s.source + ": initial_state", 0) != 0)
      fuzz::fail("error does not start with '<source>: initial_state': " + applied.error());
    return 0;
  }
  fuzz::checkSceneFinite(s, "after applyInitialState");
  return 0;
}
