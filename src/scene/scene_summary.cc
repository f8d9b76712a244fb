#include "cga_rigid_sim/scene/scene_summary.h"

#include <algorithm>
#include <map>
#include <sstream>

#include "cga_rigid_sim/format.h"

namespace cga_rigid_sim {
namespace scene {

namespace {

constexpr int kDigits = 6;  // significant digits of the summary's numbers: one screen

// The count by kind, e.g. "3 (2 box, 1 mesh)".
std::string shapeCounts(const BodyModel& body) {
  using Kind = CollisionShape::Kind;
  std::ostringstream os;
  os << body.shapes.size() << " (";
  const char* separator = "";
  for (const Kind kind : {Kind::kBox, Kind::kSphere, Kind::kCylinder, Kind::kMesh}) {
    const auto n = std::count_if(body.shapes.begin(), body.shapes.end(),
                                 [&](const CollisionShape& s) { return s.kind == kind; });
    if (n == 0) continue;
    os << separator << n << " " << toString(kind);
    separator = ", ";
  }
  os << ")";
  return os.str();
}

}  // namespace

std::string sceneSummary(const Scene& scene, const std::string& integrator) {
  constexpr std::size_t kMaxListed = 20;  // one screen
  std::ostringstream os;
  std::size_t moving = 0;
  for (const auto& b : scene.bodies) moving += b.is_static ? 0 : 1;
  os << "scene '" << scene.robot_name << "' from " << scene.source << ": " << scene.bodies.size()
     << (scene.bodies.size() == 1 ? " body (" : " bodies (") << moving << " moving, "
     << scene.bodies.size() - moving << " static), integrator '" << integrator
     << "', lambda = " << formatNumber(scene.lambda, kDigits) << " m\n";
  const auto& names = summaryIntegratorNames();
  if (std::find(names.begin(), names.end(), integrator) == names.end()) {
    os << "  unknown integrator '" << integrator << "' (known:";
    for (const auto& n : names) os << " " << n;
    os << ")\n";
  }
  os << "loads:\n";
  if (scene.gravity_W.isZero(0.0))
    os << "  gravity: off\n";
  else
    os << "  gravity: " << formatVector(scene.gravity_W, kDigits)
       << " m/s^2 on every moving body (uniform, at the centre of mass: no torque)\n";
  os << "  applied wrenches and impulses: can reach every moving body\n"
        "    (under 'auto' a wrench with a torque switches the body to exact+kicks while it "
        "acts)\n";
  os << "bodies:\n";
  std::map<std::string, std::size_t> path_count;
  for (std::size_t k = 0; k < scene.bodies.size(); ++k) {
    const BodyModel& b = scene.bodies[k];
    const std::string path = plannedIntegratorPath(scene, b, integrator);
    ++path_count[path];
    if (k >= kMaxListed) continue;
    os << "  " << b.name << ": ";
    if (b.is_static) {
      os << "static (never stepped)";
    } else {
      const auto& I = *b.inertia;
      os << "mass " << formatNumber(I.mass(), kDigits)
         << " kg, J = " << formatVector(I.principalMoments(), kDigits) << " kg m^2, "
         << dynamics::toString(I.inertiaClass()) << ", path " << path;
      if (integrator == "auto" && path != "at-rest") os << " (torque-free)";
    }
    os << "\n";
    os << "    links:";
    for (std::size_t i = 0; i < b.links.size(); ++i) os << (i ? ", " : " ") << b.links[i].link;
    if (!b.merged_joints.empty()) {
      os << " (merged by fixed joint" << (b.merged_joints.size() > 1 ? "s" : "");
      for (const auto& j : b.merged_joints) os << " " << j;
      os << ")";
    }
    os << "\n";
    // Only bodies with shapes get the line: a scene without contacts keeps its one screen.
    if (!b.shapes.empty()) os << "    collision shapes: " << shapeCounts(b) << "\n";
  }
  if (scene.bodies.size() > kMaxListed)
    os << "  ... and " << scene.bodies.size() - kMaxListed << " more bodies\n";
  os << "paths:";
  for (const auto& [path, n] : path_count) os << " " << path << " x" << n << ";";
  os << "\n";
  if (!scene.warnings.empty()) {
    os << "warnings:\n";
    for (const auto& w : scene.warnings) os << "  " << w << "\n";
  }
  return os.str();
}

}  // namespace scene
}  // namespace cga_rigid_sim
