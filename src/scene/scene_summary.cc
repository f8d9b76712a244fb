#include "cga_rigid_sim/scene/scene_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <vector>

#include "cga_rigid_sim/format.h"

namespace cga_rigid_sim {
namespace scene {

namespace {

constexpr int kSummaryDigits = 6;  // significant digits of the summary's numbers: one screen

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

// One joint on one line: type, parent -> child link, axis, limits, dynamics, mimic, initial
// state.
std::string jointLine(const Scene& scene, const JointModel& j) {
  const bool prismatic = j.type == JointType::kPrismatic;
  const char* q_unit = prismatic ? " m" : " rad";
  const char* v_unit = prismatic ? " m/s" : " rad/s";
  const JointLimits& l = j.limits;
  std::ostringstream os;
  os << j.name << ": " << toString(j.type) << ", " << j.parent_link << " -> " << j.child_link
     << ", axis " << formatVector(j.axis, kSummaryDigits);
  if (l.has_position)
    os << ", position in [" << formatNumber(l.lower, kSummaryDigits) << ", "
       << formatNumber(l.upper, kSummaryDigits) << "]" << q_unit;
  else
    os << ", no position limits";
  if (std::isfinite(l.effort))
    os << ", |effort| <= " << formatNumber(l.effort, kSummaryDigits) << (prismatic ? " N" : " N m");
  if (std::isfinite(l.velocity))
    os << ", |velocity| <= " << formatNumber(l.velocity, kSummaryDigits) << v_unit;
  if (j.damping != 0)
    os << ", damping " << formatNumber(j.damping, kSummaryDigits)
       << (prismatic ? " N s/m" : " N m s/rad");
  if (j.friction != 0)
    os << ", friction " << formatNumber(j.friction, kSummaryDigits) << (prismatic ? " N" : " N m");
  if (j.mimic) {
    os << ", mimics " << scene.joints[j.mimic->leader].name
       << ": q = " << formatNumber(j.mimic->multiplier, kSummaryDigits) << " q_"
       << scene.joints[j.mimic->leader].name;
    if (j.mimic->offset != 0)
      os << " + " << formatNumber(j.mimic->offset, kSummaryDigits) << q_unit;
    if (j.mimic->written != scene.joints[j.mimic->leader].name)
      os << " (through " << j.mimic->written << ")";
  }
  if (j.initial_position != 0)
    os << ", q0 = " << formatNumber(j.initial_position, kSummaryDigits) << q_unit;
  if (j.initial_velocity != 0)
    os << ", v0 = " << formatNumber(j.initial_velocity, kSummaryDigits) << v_unit;
  return os.str();
}

// "  ... and 3 more bodies (<where the whole list is>)" when `listed` of `total` were shown.
void more(std::ostream& os, std::size_t total, std::size_t listed, const char* what,
          const SummaryOptions& options) {
  if (total > listed)
    os << "  ... and " << total - listed << " more " << what << " (" << options.whole_list << ")\n";
}

// The limit of a section (0: all).
std::size_t limitOf(std::size_t max) { return max == 0 ? SIZE_MAX : max; }

// The sections, in the order the summary prints them. Each writes its heading and lines.
void headerSection(std::ostream& os, const Scene& scene, const std::string& integrator) {
  std::size_t moving = 0;
  for (const auto& b : scene.bodies) moving += b.is_static ? 0 : 1;
  os << "scene '" << scene.robot_name << "' from " << scene.source << ": " << scene.bodies.size()
     << (scene.bodies.size() == 1 ? " body (" : " bodies (") << moving << " moving, "
     << scene.bodies.size() - moving << " static)";
  if (!scene.joints.empty())
    os << ", " << scene.joints.size() << (scene.joints.size() == 1 ? " joint" : " joints");
  os << ", integrator '" << integrator
     << "', lambda = " << formatNumber(scene.lambda, kSummaryDigits) << " m\n";
  const auto& names = summaryIntegratorNames();
  if (std::find(names.begin(), names.end(), integrator) == names.end()) {
    os << "  unknown integrator '" << integrator << "' (known:";
    for (const auto& n : names) os << " " << n;
    os << ")\n";
  }
}

void loadsSection(std::ostream& os, const Scene& scene) {
  os << "loads:\n";
  if (scene.gravity_W.isZero(0.0))
    os << "  gravity: off\n";
  else
    os << "  gravity: " << formatVector(scene.gravity_W, kSummaryDigits)
       << " m/s^2 on every moving body (uniform, at the centre of mass: no torque)\n";
  os << "  applied wrenches and impulses: can reach every moving body\n"
        "    (under 'auto' a wrench with a torque switches the body to exact+kicks while it "
        "acts)\n";
}

// Bodies, and the count of each integrator path (for the paths section).
void bodiesSection(std::ostream& os, const Scene& scene, const std::string& integrator,
                   const SummaryOptions& options, std::map<std::string, std::size_t>& paths) {
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
  std::size_t robot_total = 0, robot_listed = 0, other_total = 0, other_listed = 0;
  for (std::size_t k = 0; k < scene.bodies.size(); ++k) {
    const BodyModel& b = scene.bodies[k];
    const bool in_tree = !tree_role[k].empty();
    const std::string path = in_tree ? "articulated" : plannedIntegratorPath(scene, b, integrator);
    ++paths[path];
    std::size_t& total = in_tree ? robot_total : other_total;
    std::size_t& listed = in_tree ? robot_listed : other_listed;
    ++total;
    if (listed >= limitOf(in_tree ? options.max_robot_entries : options.max_bodies)) continue;
    ++listed;
    os << "  " << b.name << ": ";
    if (b.is_static) {
      os << "static (never stepped)";
    } else {
      const auto& I = *b.inertia;
      os << "mass " << formatNumber(I.mass(), kSummaryDigits)
         << " kg, J = " << formatVector(I.principalMoments(), kSummaryDigits) << " kg m^2, "
         << dynamics::toString(I.inertiaClass()) << ", path " << path;
      if (in_tree)
        os << " (" << tree_role[k] << ")";
      else if (integrator == "auto" && path != "at-rest")
        os << " (torque-free)";
    }
    os << "\n";
    // The links, when the body is more than its root link.
    if (b.links.size() > 1 || !b.merged_joints.empty()) {
      os << "    links:";
      for (std::size_t i = 0; i < b.links.size(); ++i) os << (i ? ", " : " ") << b.links[i].link;
      if (!b.merged_joints.empty()) {
        os << " (merged by fixed joint" << (b.merged_joints.size() > 1 ? "s" : "");
        for (const auto& j : b.merged_joints) os << " " << j;
        os << ")";
      }
      os << "\n";
    }
    // Only bodies with shapes get the line: a scene without contacts keeps its one screen.
    if (!b.shapes.empty()) os << "    collision shapes: " << shapeCounts(b) << "\n";
  }
  more(os, robot_total, robot_listed, "bodies of articulated trees", options);
  more(os, other_total, other_listed, "bodies", options);
}

void jointsSection(std::ostream& os, const Scene& scene, const SummaryOptions& options) {
  if (scene.joints.empty()) return;
  os << "joints:\n";
  const std::size_t listed = std::min(scene.joints.size(), limitOf(options.max_robot_entries));
  for (std::size_t k = 0; k < listed; ++k) os << "  " << jointLine(scene, scene.joints[k]) << "\n";
  more(os, scene.joints.size(), listed, "joints", options);
}

void pathsSection(std::ostream& os, const std::map<std::string, std::size_t>& paths) {
  os << "paths:";
  for (const auto& [path, n] : paths) os << " " << path << " x" << n << ";";
  os << "\n";
}

std::string rateText(double rate) {
  return rate > 0 ? formatNumber(rate, 6) + " Hz" : std::string("every step");
}

// Each sensor and drive the URDF declares: its kind, where it sits, its topic and rate.
void sensorsSection(std::ostream& os, const Scene& scene) {
  if (scene.sensors.empty()) return;
  os << "sensors:\n";
  for (const SensorModel& s : scene.sensors.sensors) {
    os << "  " << toString(s.kind) << " " << inQuotes(s.name) << " (" << s.plugin << ") on "
       << (s.joint.empty() ? "link " + s.link : "joint " + s.joint) << " -> " << s.topic << " at "
       << rateText(s.update_rate) << "\n";
  }
  for (const DriveModel& d : scene.sensors.drives) {
    os << "  " << (d.kind == DriveKind::kDifferential ? "diff_drive " : "skid_steer_drive ")
       << inQuotes(d.name) << " (" << d.plugin << ") wheels";
    for (const auto& j : d.left_joints) os << " " << j;
    for (const auto& j : d.right_joints) os << " " << j;
    os << ": " << d.command_topic << " -> " << d.odometry_topic << "\n";
  }
}

void warningsSection(std::ostream& os, const Scene& scene) {
  if (scene.warnings.empty()) return;
  os << "warnings (" << scene.warnings.size() << "):\n";
  for (const auto& w : scene.warnings) os << "  " << w << "\n";
}

}  // namespace

std::string sceneSummary(const Scene& scene, const std::string& integrator,
                         const SummaryOptions& options) {
  std::ostringstream os;
  std::map<std::string, std::size_t> paths;
  headerSection(os, scene, integrator);
  loadsSection(os, scene);
  bodiesSection(os, scene, integrator, options, paths);
  jointsSection(os, scene, options);
  pathsSection(os, paths);
  sensorsSection(os, scene);
  warningsSection(os, scene);
  return os.str();
}

}  // namespace scene
}  // namespace cga_rigid_sim
