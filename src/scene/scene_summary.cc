#include "cga_rigid_sim/scene/scene_summary.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

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

// One joint on one line: type, parent -> child link, axis, limits, dynamics, initial state.
std::string jointLine(const JointModel& j) {
  const bool prismatic = j.type == JointType::kPrismatic;
  const char* q_unit = prismatic ? " m" : " rad";
  const char* v_unit = prismatic ? " m/s" : " rad/s";
  const JointLimits& l = j.limits;
  std::ostringstream os;
  os << j.name << ": " << toString(j.type) << ", " << j.parent_link << " -> " << j.child_link
     << ", axis " << formatVector(j.axis, kDigits);
  if (l.has_position)
    os << ", position in [" << formatNumber(l.lower, kDigits) << ", "
       << formatNumber(l.upper, kDigits) << "]" << q_unit;
  else
    os << ", no position limits";
  if (std::isfinite(l.effort))
    os << ", |effort| <= " << formatNumber(l.effort, kDigits) << (prismatic ? " N" : " N m");
  if (std::isfinite(l.velocity))
    os << ", |velocity| <= " << formatNumber(l.velocity, kDigits) << v_unit;
  if (j.damping != 0)
    os << ", damping " << formatNumber(j.damping, kDigits) << (prismatic ? " N s/m" : " N m s/rad");
  if (j.friction != 0)
    os << ", friction " << formatNumber(j.friction, kDigits) << (prismatic ? " N" : " N m");
  if (j.initial_position != 0)
    os << ", q0 = " << formatNumber(j.initial_position, kDigits) << q_unit;
  if (j.initial_velocity != 0)
    os << ", v0 = " << formatNumber(j.initial_velocity, kDigits) << v_unit;
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
     << scene.bodies.size() - moving << " static)";
  if (!scene.joints.empty())
    os << ", " << scene.joints.size() << (scene.joints.size() == 1 ? " joint" : " joints");
  os << ", integrator '" << integrator << "', lambda = " << formatNumber(scene.lambda, kDigits)
     << " m\n";
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
  // The bodies of articulated trees (the joints' children and the free roots they hang from)
  // are stepped with their tree, not by the per-body paths.
  std::vector<std::string> tree_role(scene.bodies.size());
  for (const JointModel& j : scene.joints) {
    tree_role[j.child_body] = "moved by joint " + j.name;
    if (j.parent_body >= 0 && !scene.bodies[j.parent_body].is_static &&
        tree_role[j.parent_body].empty())
      tree_role[j.parent_body] = "free root of the tree of joint " + j.name;
  }
  std::map<std::string, std::size_t> path_count;
  for (std::size_t k = 0; k < scene.bodies.size(); ++k) {
    const BodyModel& b = scene.bodies[k];
    const bool in_tree = !tree_role[k].empty();
    const std::string path = in_tree ? "articulated" : plannedIntegratorPath(scene, b, integrator);
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
      if (in_tree)
        os << " (" << tree_role[k] << ")";
      else if (integrator == "auto" && path != "at-rest")
        os << " (torque-free)";
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
  if (!scene.joints.empty()) {
    os << "joints:\n";
    for (std::size_t k = 0; k < scene.joints.size() && k < kMaxListed; ++k)
      os << "  " << jointLine(scene.joints[k]) << "\n";
    if (scene.joints.size() > kMaxListed)
      os << "  ... and " << scene.joints.size() - kMaxListed << " more joints\n";
  }
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
