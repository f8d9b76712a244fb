#include "cga_rigid_sim/ros/parameters.h"

#include <ros/param.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <thread>

#include "cga_rigid_sim/format.h"

namespace cga_rigid_sim {
namespace node {
namespace {

using XmlRpc::XmlRpcValue;

const char* typeName(const XmlRpcValue& v) {
  switch (v.getType()) {
    case XmlRpcValue::TypeBoolean:
      return "bool";
    case XmlRpcValue::TypeInt:
      return "int";
    case XmlRpcValue::TypeDouble:
      return "double";
    case XmlRpcValue::TypeString:
      return "string";
    case XmlRpcValue::TypeDateTime:
      return "date/time";
    case XmlRpcValue::TypeBase64:
      return "binary";
    case XmlRpcValue::TypeArray:
      return "list";
    case XmlRpcValue::TypeStruct:
      return "dictionary";
    default:
      return "invalid";
  }
}

Error wrongType(const std::string& name, const char* expected, const XmlRpcValue& v) {
  return Error{name + ": expected " + expected + ", got " + typeName(v)};
}

// A number (int or double) as double.
Result<double> asNumber(const XmlRpcValue& v, const std::string& name) {
  if (v.getType() == XmlRpcValue::TypeInt) return static_cast<double>(static_cast<const int&>(v));
  if (v.getType() == XmlRpcValue::TypeDouble) return static_cast<const double&>(v);
  return wrongType(name, "a number", v);
}

// A finite number (int or double) as double.
Result<double> asFiniteNumber(const XmlRpcValue& v, const std::string& name) {
  auto d = asNumber(v, name);
  if (!d) return Error{d.error()};
  if (!std::isfinite(*d)) return Error{name + ": not finite"};
  return *d;
}

// Each reader leaves `out` unchanged (the default) when the parameter is not set.
Result<bool> readNumber(const ::ros::NodeHandle& pnh, const std::string& key, double* out) {
  XmlRpcValue v;
  if (!pnh.getParam(key, v)) return false;
  auto d = asFiniteNumber(v, "~" + key);
  if (!d) return Error{d.error()};
  *out = *d;
  return true;
}

Result<bool> readBool(const ::ros::NodeHandle& pnh, const std::string& key, bool* out) {
  XmlRpcValue v;
  if (!pnh.getParam(key, v)) return false;
  if (v.getType() != XmlRpcValue::TypeBoolean) return wrongType("~" + key, "true or false", v);
  *out = static_cast<const bool&>(v);
  return true;
}

Result<bool> readString(const ::ros::NodeHandle& pnh, const std::string& key, std::string* out) {
  XmlRpcValue v;
  if (!pnh.getParam(key, v)) return false;
  if (v.getType() != XmlRpcValue::TypeString) return wrongType("~" + key, "a string", v);
  *out = static_cast<const std::string&>(v);
  return true;
}

Result<bool> readVector3(const ::ros::NodeHandle& pnh, const std::string& key,
                         Eigen::Vector3d* out) {
  XmlRpcValue v;
  if (!pnh.getParam(key, v)) return false;
  if (v.getType() != XmlRpcValue::TypeArray || v.size() != 3)
    return Error{"~" + key + ": expected a list of 3 numbers, got " + typeName(v)};
  Eigen::Vector3d x;
  for (int i = 0; i < 3; ++i) {
    auto d = asFiniteNumber(v[i], "~" + key + "[" + std::to_string(i) + "]");
    if (!d) return Error{d.error()};
    x[i] = *d;
  }
  *out = x;
  return true;
}

// How ~ground_plane is written, for its errors.
constexpr const char* kGroundPlaneForm =
    "a dictionary such as {height: 0.0, mu: 0.8, restitution: 0.2} (every key optional)";

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\n");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\n") - first + 1);
}

// A one-level YAML flow mapping of plain scalars, "{height: 0.0, mu: 0.8}", as the dictionary
// rosparam would have made of it: a value that reads whole as a number becomes a double, any
// other a string (which the dictionary's rules then refuse by name). rosrun's
// _ground_plane:={...} and a launch file's <param value="{...}"/> hand the parameter over as
// such a string. Nothing else is YAML here: a string that is not of this form is refused.
Result<XmlRpcValue> parseFlowMapping(const std::string& text, const std::string& name) {
  const std::string t = trim(text);
  const Error refused{name + ": expected " + kGroundPlaneForm + ", got string '" + text + "'"};
  if (t.size() < 2 || t.front() != '{' || t.back() != '}') return refused;
  XmlRpcValue map;
  map.begin();  // an empty struct, not an invalid value, for "{}"
  const std::string inner = trim(t.substr(1, t.size() - 2));
  if (inner.empty()) return map;
  std::size_t start = 0;
  while (start <= inner.size()) {
    const std::size_t comma = std::min(inner.find(',', start), inner.size());
    const std::string item = inner.substr(start, comma - start);
    const std::size_t colon = item.find(':');
    if (colon == std::string::npos) return refused;
    const std::string key = trim(item.substr(0, colon));
    const std::string value = trim(item.substr(colon + 1));
    if (key.empty() || value.empty()) return refused;
    if (map.hasMember(key)) return Error{name + "." + key + ": given twice"};
    char* end = nullptr;
    const double d = std::strtod(value.c_str(), &end);
    if (end == value.c_str() + value.size())
      map[key] = d;
    else
      map[key] = value;
    start = comma + 1;
  }
  return map;
}

// ~ground_plane: a dictionary {height (m), mu, restitution}, each key optional (height 0, μ and
// e unset = ~contact_mu, ~contact_restitution), or the same as a string (parseFlowMapping).
// Unset: no plane. The core checks the ranges (μ >= 0, e in [0, 1]).
Result<bool> readGroundPlane(const ::ros::NodeHandle& pnh, std::optional<sim::GroundPlane>* out) {
  const std::string name = "~ground_plane";
  XmlRpcValue v;
  if (!pnh.getParam("ground_plane", v)) return false;
  if (v.getType() == XmlRpcValue::TypeString) {
    auto parsed = parseFlowMapping(static_cast<const std::string&>(v), name);
    if (!parsed) return Error{parsed.error()};
    v = *parsed;
  }
  if (v.getType() != XmlRpcValue::TypeStruct) return wrongType(name, kGroundPlaneForm, v);
  sim::GroundPlane plane;
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string field = name + "." + it->first;
    if (it->first != "height" && it->first != "mu" && it->first != "restitution")
      return Error{field + ": unknown key (known: height, mu, restitution)"};
    auto d = asFiniteNumber(it->second, field);
    if (!d) return Error{d.error()};
    if (it->first == "height") plane.height = *d;
    if (it->first == "mu") plane.surface.mu = *d;
    if (it->first == "restitution") plane.surface.restitution = *d;
  }
  *out = plane;
  return true;
}

}  // namespace

const std::vector<std::string>& knownPrivateParams() {
  static const std::vector<std::string> kNames = {
      "urdf_file", "initial_state", "integrator", "dt", "gravity", "real_time_factor",
      "publish_rate", "publish_clock", "clock_rate", "world_frame", "paused", "lambda", "max_force",
      "max_impulse", "relax_inertia", "threads",
      // contacts
      "ground_plane", "contact_mu", "contact_restitution",
      // ~markers (README "Seeing the simulation")
      "marker_length", "marker_angular_momentum_ref", "marker_angular_velocity_ref",
      "marker_force_ref"};
  return kNames;
}

Result<scene::ParamValue> toParamValue(const XmlRpcValue& v, const std::string& path) {
  switch (v.getType()) {
    case XmlRpcValue::TypeBoolean:
      return scene::ParamValue(static_cast<const bool&>(v));
    case XmlRpcValue::TypeInt:
      return scene::ParamValue(static_cast<const int&>(v));
    case XmlRpcValue::TypeDouble:
      return scene::ParamValue(static_cast<const double&>(v));
    case XmlRpcValue::TypeString:
      return scene::ParamValue(static_cast<const std::string&>(v));
    case XmlRpcValue::TypeArray: {
      scene::ParamValue::List list;
      list.reserve(static_cast<std::size_t>(v.size()));
      for (int i = 0; i < v.size(); ++i) {
        auto item = toParamValue(v[i], path + "[" + std::to_string(i) + "]");
        if (!item) return Error{item.error()};
        list.push_back(std::move(*item));
      }
      return scene::ParamValue(std::move(list));
    }
    case XmlRpcValue::TypeStruct: {
      scene::ParamValue::Map map;
      for (auto it = v.begin(); it != v.end(); ++it) {
        auto item = toParamValue(it->second, path + "." + it->first);
        if (!item) return Error{item.error()};
        map.emplace(it->first, std::move(*item));
      }
      return scene::ParamValue(std::move(map));
    }
    default:
      return Error{path + ": unsupported parameter type " + std::string(typeName(v)) +
                   " (use numbers, strings, booleans, lists and dictionaries)"};
  }
}

Result<NodeParams> readNodeParams(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh,
                                  std::vector<std::string>* warnings) {
  NodeParams p;
  // Each step returns the first error; an unset parameter keeps its default.
#define CGA_RIGID_SIM_READ(call)       \
  do {                                 \
    auto r_ = (call);                  \
    if (!r_) return Error{r_.error()}; \
  } while (false)

  // The URDF: ~urdf_file (explicit, private) wins over robot_description.
  std::string urdf_file;
  if (auto r = readString(pnh, "urdf_file", &urdf_file); !r) {
    return Error{r.error()};
  }
  const std::string description_name = nh.resolveName("robot_description");
  XmlRpcValue description;
  const bool has_description = nh.getParam("robot_description", description);
  if (!urdf_file.empty()) {
    p.urdf_from_file = true;
    p.urdf_file = urdf_file;
    p.urdf_source_name = urdf_file;
    if (has_description && warnings)
      warnings->push_back("both ~urdf_file and " + description_name +
                          " are set: using ~urdf_file '" + urdf_file + "'");
  } else if (has_description) {
    if (description.getType() != XmlRpcValue::TypeString)
      return wrongType(description_name, "a URDF string", description);
    p.urdf_xml = static_cast<const std::string&>(description);
    p.urdf_source_name = description_name;
  } else {
    return Error{"no URDF: set the parameter " + description_name +
                 " (the URDF as a string) or ~urdf_file (a path)"};
  }

  CGA_RIGID_SIM_READ(readString(pnh, "integrator", &p.world.integrator));
  CGA_RIGID_SIM_READ(readNumber(pnh, "dt", &p.world.dt));
  CGA_RIGID_SIM_READ(readNumber(pnh, "max_force", &p.world.max_force));
  CGA_RIGID_SIM_READ(readNumber(pnh, "max_impulse", &p.world.max_impulse));
  CGA_RIGID_SIM_READ(readString(pnh, "world_frame", &p.world.world_frame));
  if (p.world.world_frame.empty()) return Error{"~world_frame: must not be empty"};
  p.scene.world_frame = p.world.world_frame;
  CGA_RIGID_SIM_READ(readVector3(pnh, "gravity", &p.scene.gravity_W));
  CGA_RIGID_SIM_READ(readNumber(pnh, "lambda", &p.scene.lambda));
  bool relax_inertia = false;
  CGA_RIGID_SIM_READ(readBool(pnh, "relax_inertia", &relax_inertia));
  p.scene.triangle_policy = relax_inertia ? dynamics::TrianglePolicy::kNearestPhysical
                                          : dynamics::TrianglePolicy::kRefuse;
  CGA_RIGID_SIM_READ(readGroundPlane(pnh, &p.world.ground_plane));
  CGA_RIGID_SIM_READ(readNumber(pnh, "contact_mu", &p.world.contact_mu));
  CGA_RIGID_SIM_READ(readNumber(pnh, "contact_restitution", &p.world.contact_restitution));
  XmlRpcValue initial_state;
  if (pnh.getParam("initial_state", initial_state)) {
    auto value = toParamValue(initial_state, "~initial_state");
    if (!value) return Error{value.error()};
    p.scene.initial_state = std::move(*value);
  }

  CGA_RIGID_SIM_READ(readNumber(pnh, "real_time_factor", &p.real_time_factor));
  if (p.real_time_factor < 0.0)
    return Error{"~real_time_factor: must be >= 0 (0 = as fast as possible)"};
  CGA_RIGID_SIM_READ(readNumber(pnh, "publish_rate", &p.publish_rate));
  if (!(p.publish_rate > 0.0)) return Error{"~publish_rate: must be > 0 Hz"};
  CGA_RIGID_SIM_READ(readBool(pnh, "publish_clock", &p.publish_clock));
  CGA_RIGID_SIM_READ(readNumber(pnh, "clock_rate", &p.clock_rate));
  if (p.clock_rate < 0.0) return Error{"~clock_rate: must be > 0 Hz (or unset: every step)"};
  CGA_RIGID_SIM_READ(readBool(pnh, "paused", &p.paused));
  double threads = 0.0;  // 0: the cores available
  CGA_RIGID_SIM_READ(readNumber(pnh, "threads", &threads));
  if (threads != std::floor(threads) || threads < 0 || threads > sim::kMaxThreads)
    return Error{"~threads: must be a whole number from 0 (the cores available) to " +
                 std::to_string(sim::kMaxThreads) + " (got " + formatNumber(threads) + ")"};
  p.world.threads = threads > 0
                        ? static_cast<int>(threads)
                        : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  // ~markers scaling (include/cga_rigid_sim/ros/markers.h): ℓ > 0; references ≥ 0, 0 = chosen.
  CGA_RIGID_SIM_READ(readNumber(pnh, "marker_length", &p.markers.length));
  if (!(p.markers.length > 0.0)) return Error{"~marker_length: must be > 0 m"};
  for (auto [name, ref] :
       {std::pair{"marker_angular_momentum_ref", &p.markers.angular_momentum_ref},
        std::pair{"marker_angular_velocity_ref", &p.markers.angular_velocity_ref}}) {
    CGA_RIGID_SIM_READ(readNumber(pnh, name, ref));
    if (!(*ref >= 0.0))
      return Error{std::string("~") + name + ": must be >= 0 (0 = chosen from the motion)"};
  }
  CGA_RIGID_SIM_READ(readNumber(pnh, "marker_force_ref", &p.markers.force_ref));
  if (!(p.markers.force_ref > 0.0)) return Error{"~marker_force_ref: must be > 0 N"};
#undef CGA_RIGID_SIM_READ

  // Unknown private parameters are most likely typos: say so (not fatal).
  XmlRpcValue all;
  if (warnings && ::ros::param::get(pnh.getNamespace(), all) &&
      all.getType() == XmlRpcValue::TypeStruct) {
    const auto& known = knownPrivateParams();
    for (auto it = all.begin(); it != all.end(); ++it) {
      if (std::find(known.begin(), known.end(), it->first) == known.end()) {
        std::ostringstream os;
        os << "unknown parameter ~" << it->first << " ignored (known:";
        for (const auto& k : known) os << " " << k;
        os << ")";
        warnings->push_back(os.str());
      }
    }
  }
  return p;
}

}  // namespace node
}  // namespace cga_rigid_sim
