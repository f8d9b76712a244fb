#include "cga_rigid_sim/ros/parameters.h"

#include <ros/param.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <thread>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/scene/flow_text.h"

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

// ---- Parameters typed as text ----
//
// One rule for every parameter: when a parameter that is not a string arrives as a string —
// rosrun hands `_gravity:=[0,0,0]` and `_initial_state:={...}` over so, a launch file's
// <param value="…"/> may, and YAML 1.1 reads `1e-3` (no dot) as a string — the string is read
// as a one-line YAML flow value (a number, true/false, [a, b], {key: value}, nested) and must
// then have the parameter's type. A string that is not such a value, or reads as the wrong
// type, is refused with the form the parameter takes.

// The text itself is read by scene::parseFlowText (scene/flow_text.h), without ROS, so that the
// initial-state fuzz target reads it with the same parser; here it becomes an XmlRpcValue.
XmlRpcValue toXmlRpc(const scene::FlowValue& v) {
  switch (v.type) {
    case scene::FlowValue::Type::kBool:
      return XmlRpcValue(v.b);
    case scene::FlowValue::Type::kInt:
      return XmlRpcValue(v.i);
    case scene::FlowValue::Type::kDouble:
      return XmlRpcValue(v.d);
    case scene::FlowValue::Type::kString:
      return XmlRpcValue(v.s);
    case scene::FlowValue::Type::kList: {
      XmlRpcValue list;
      list.setSize(0);  // an empty array, not an invalid value, for "[]"
      for (const scene::FlowValue& item : v.items) list[list.size()] = toXmlRpc(item);
      return list;
    }
    case scene::FlowValue::Type::kMap: {
      XmlRpcValue map;
      map.begin();  // an empty struct, not an invalid value, for "{}"
      for (std::size_t k = 0; k < v.items.size(); ++k) map[v.keys[k]] = toXmlRpc(v.items[k]);
      return map;
    }
  }
  return XmlRpcValue();
}

// The parameter `key`, with a string read as a YAML flow value when `expected` is not a string
// type; false when unset.
Result<bool> getTyped(const ::ros::NodeHandle& pnh, const std::string& key, XmlRpcValue* v,
                      std::string* text) {
  if (!pnh.getParam(key, *v)) return false;
  text->clear();
  if (v->getType() == XmlRpcValue::TypeString) {
    *text = static_cast<const std::string&>(*v);
    if (auto parsed = scene::parseFlowText(*text)) *v = toXmlRpc(*parsed);
  }
  return true;
}

// "~dt: expected a number, got string 'abc' (rosrun: _dt:=0.001)".
Error wrongForm(const std::string& key, const std::string& form, const std::string& example,
                const XmlRpcValue& v, const std::string& text) {
  std::string got = typeName(v);
  if (!text.empty() || v.getType() == XmlRpcValue::TypeString) got = "string '" + text + "'";
  const bool quote = example.find_first_of(" [{") != std::string::npos;
  return Error{"~" + key + ": expected " + form + ", got " + got + " (rosrun: _" + key +
               ":=" + (quote ? "\"" + example + "\"" : example) + ")"};
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
Result<bool> readNumber(const ::ros::NodeHandle& pnh, const std::string& key, double* out,
                        const char* example) {
  XmlRpcValue v;
  std::string text;
  auto set = getTyped(pnh, key, &v, &text);
  if (!set || !*set) return set;
  if (v.getType() != XmlRpcValue::TypeInt && v.getType() != XmlRpcValue::TypeDouble)
    return wrongForm(key, "a number", example, v, text);
  auto d = asFiniteNumber(v, "~" + key);
  if (!d) return Error{d.error()};
  *out = *d;
  return true;
}

// A whole number in [lo, hi] (an int, or a double that is whole).
Result<bool> readWhole(const ::ros::NodeHandle& pnh, const std::string& key, int* out, int lo,
                       int hi, const char* example, const char* meaning = "") {
  double d = *out;
  auto set = readNumber(pnh, key, &d, example);
  if (!set || !*set) return set;
  if (d != std::floor(d) || d < lo || d > hi)
    return Error{"~" + key + ": must be a whole number from " + std::to_string(lo) + meaning +
                 " to " + std::to_string(hi) + " (got " + formatNumber(d) + ")"};
  *out = static_cast<int>(d);
  return true;
}

// true or false; also as text (true/false, yes/no, on/off, any case) or the numbers 1 and 0.
Result<bool> readBool(const ::ros::NodeHandle& pnh, const std::string& key, bool* out) {
  XmlRpcValue v;
  std::string text;
  auto set = getTyped(pnh, key, &v, &text);
  if (!set || !*set) return set;
  if (v.getType() == XmlRpcValue::TypeInt &&
      (static_cast<int&>(v) == 0 || static_cast<int&>(v) == 1)) {
    *out = static_cast<int&>(v) == 1;
    return true;
  }
  if (v.getType() != XmlRpcValue::TypeBoolean)
    return wrongForm(key, "true or false", "true", v, text);
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

Result<bool> readVector3(const ::ros::NodeHandle& pnh, const std::string& key, Eigen::Vector3d* out,
                         const char* example) {
  XmlRpcValue v;
  std::string text;
  auto set = getTyped(pnh, key, &v, &text);
  if (!set || !*set) return set;
  if (v.getType() != XmlRpcValue::TypeArray || v.size() != 3)
    return wrongForm(key, std::string("a list of 3 numbers such as ") + example, example, v, text);
  Eigen::Vector3d x;
  for (int i = 0; i < 3; ++i) {
    auto d = asFiniteNumber(v[i], "~" + key + "[" + std::to_string(i) + "]");
    if (!d) return Error{d.error()};
    x[i] = *d;
  }
  *out = x;
  return true;
}

// A dictionary (also as text, "{a: 1.0, b: {c: [1, 2]}}").
Result<bool> readDictionary(const ::ros::NodeHandle& pnh, const std::string& key, XmlRpcValue* out,
                            const char* example) {
  std::string text;
  auto set = getTyped(pnh, key, out, &text);
  if (!set || !*set) return set;
  if (out->getType() != XmlRpcValue::TypeStruct)
    return wrongForm(key, std::string("a dictionary such as ") + example, example, *out, text);
  return true;
}

// ~ground_plane: a dictionary {height (m), mu, restitution}, each key optional (height 0, μ and
// e unset = ~contact_mu, ~contact_restitution), or the same as a string. Unset: no plane. The
// core checks the ranges (μ >= 0, e in [0, 1]).
Result<bool> readGroundPlane(const ::ros::NodeHandle& pnh, std::optional<sim::GroundPlane>* out) {
  const std::string name = "~ground_plane";
  XmlRpcValue v;
  auto set = readDictionary(pnh, "ground_plane", &v, "{height: 0.0, mu: 0.8, restitution: 0.2}");
  // (every key optional)
  if (!set || !*set) return set;
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
      "max_impulse", "relax_inertia", "threads", "curvature", "controllers", "spawn_controllers",
      "sensor_seed",
      // contacts
      "ground_plane", "contact_mu", "contact_restitution", "contact_sleeping", "self_collision",
      "srdf_file", "self_collision_pairs",
      // ~markers (doc/node.md "Seeing the simulation")
      "marker_length", "marker_angular_momentum_ref", "marker_angular_velocity_ref",
      "marker_force_ref",
      // bounds on inputs
      "max_queued_inputs", "max_queued_inputs_per_body", "max_active_wrenches",
      "max_active_wrenches_per_body"};
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
  CGA_RIGID_SIM_READ(readNumber(pnh, "dt", &p.world.dt, "0.001"));
  CGA_RIGID_SIM_READ(readNumber(pnh, "max_force", &p.world.max_force, "1000000.0"));
  CGA_RIGID_SIM_READ(readNumber(pnh, "max_impulse", &p.world.max_impulse, "10000.0"));
  CGA_RIGID_SIM_READ(readString(pnh, "world_frame", &p.world.world_frame));
  if (p.world.world_frame.empty()) return Error{"~world_frame: must not be empty"};
  p.scene.world_frame = p.world.world_frame;
  CGA_RIGID_SIM_READ(readVector3(pnh, "gravity", &p.scene.gravity_W, "[0.0, 0.0, -9.81]"));
  CGA_RIGID_SIM_READ(readNumber(pnh, "lambda", &p.scene.lambda, "1.0"));
  bool relax_inertia = true;  // the inertia repairs of doc/urdf.md#inertias-from-cad
  CGA_RIGID_SIM_READ(readBool(pnh, "relax_inertia", &relax_inertia));
  p.scene.triangle_policy = relax_inertia ? dynamics::TrianglePolicy::kNearestPhysical
                                          : dynamics::TrianglePolicy::kRefuse;
  p.world.triangle_policy = p.scene.triangle_policy;  // and for ~spawn_urdf's descriptions
  CGA_RIGID_SIM_READ(readGroundPlane(pnh, &p.world.ground_plane));
  // ~curvature: the radius R of curved space, m (doc/curved_space.md); unset = Euclidean. Its
  // range (finite, nonzero) and what it needs (gravity off, free bodies) the core checks.
  double curvature = 0.0;
  auto has_curvature = readNumber(pnh, "curvature", &curvature, "50.0");
  if (!has_curvature) return Error{has_curvature.error()};
  if (*has_curvature) p.world.curvature = curvature;
  CGA_RIGID_SIM_READ(readNumber(pnh, "contact_mu", &p.world.contact_mu, "0.5"));
  CGA_RIGID_SIM_READ(readNumber(pnh, "contact_restitution", &p.world.contact_restitution, "0.0"));
  CGA_RIGID_SIM_READ(readBool(pnh, "contact_sleeping", &p.world.contact_sleeping));
  // ~self_collision: auto | all | none (doc/contacts.md#self-collision).
  std::string self_collision = scene::toString(p.world.self_collision);
  CGA_RIGID_SIM_READ(readString(pnh, "self_collision", &self_collision));
  if (auto mode = scene::parseSelfCollisionMode(self_collision))
    p.world.self_collision = *mode;
  else
    return Error{"~self_collision: must be auto, all or none (got '" + self_collision + "')"};
  // The SRDF: ~srdf_file (explicit, private) wins over robot_description_semantic.
  CGA_RIGID_SIM_READ(readString(pnh, "srdf_file", &p.srdf_file));
  XmlRpcValue semantic;
  const std::string semantic_name = nh.resolveName("robot_description_semantic");
  if (!p.srdf_file.empty()) {
    p.srdf_source_name = p.srdf_file;
  } else if (nh.getParam("robot_description_semantic", semantic)) {
    if (semantic.getType() != XmlRpcValue::TypeString)
      return wrongType(semantic_name, "an SRDF string", semantic);
    p.srdf_xml = static_cast<const std::string&>(semantic);
    p.srdf_source_name = semantic_name;
  }
  XmlRpcValue initial_state;
  auto has_initial_state = readDictionary(pnh, "initial_state", &initial_state,
                                          "{racket_handle: {angular_velocity: [0.0, 10.0, 0.1]}}");
  if (!has_initial_state) return Error{has_initial_state.error()};
  if (*has_initial_state) {
    auto value = toParamValue(initial_state, "~initial_state");
    if (!value) return Error{value.error()};
    p.scene.initial_state = std::move(*value);
  }

  CGA_RIGID_SIM_READ(readNumber(pnh, "real_time_factor", &p.real_time_factor, "1.0"));
  if (p.real_time_factor < 0.0)
    return Error{"~real_time_factor: must be >= 0 (0 = as fast as possible)"};
  CGA_RIGID_SIM_READ(readNumber(pnh, "publish_rate", &p.publish_rate, "100.0"));
  int sensor_seed = 0;
  CGA_RIGID_SIM_READ(readWhole(pnh, "sensor_seed", &sensor_seed, 0, 2147483647, "1"));
  p.sensor_seed = static_cast<std::uint64_t>(sensor_seed);
  if (!(p.publish_rate > 0.0)) return Error{"~publish_rate: must be > 0 Hz"};
  CGA_RIGID_SIM_READ(readBool(pnh, "publish_clock", &p.publish_clock));
  CGA_RIGID_SIM_READ(readNumber(pnh, "clock_rate", &p.clock_rate, "1000.0"));
  if (p.clock_rate < 0.0) return Error{"~clock_rate: must be > 0 Hz (or unset: every step)"};
  CGA_RIGID_SIM_READ(readBool(pnh, "paused", &p.paused));
  int threads = 0;  // 0: the cores available
  CGA_RIGID_SIM_READ(
      readWhole(pnh, "threads", &threads, 0, sim::kMaxThreads, "2", " (the cores available)"));
  p.world.threads =
      threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  // The bounds on inputs (doc/node.md "Limits and bounds").
  constexpr int kMaxBound = 100000000;  // 1e8 inputs of ~150 bytes: 15 GB, past any machine
  CGA_RIGID_SIM_READ(
      readWhole(pnh, "max_queued_inputs", &p.world.max_queued_inputs, 1, kMaxBound, "10000"));
  CGA_RIGID_SIM_READ(readWhole(pnh, "max_queued_inputs_per_body",
                               &p.world.max_queued_inputs_per_body, 1, kMaxBound, "1000"));
  CGA_RIGID_SIM_READ(
      readWhole(pnh, "max_active_wrenches", &p.world.max_active_wrenches, 1, kMaxBound, "1000"));
  CGA_RIGID_SIM_READ(readWhole(pnh, "max_active_wrenches_per_body",
                               &p.world.max_active_wrenches_per_body, 1, kMaxBound, "64"));
  // ~markers scaling (include/cga_rigid_sim/ros/markers.h): ℓ > 0; references ≥ 0, 0 = chosen.
  CGA_RIGID_SIM_READ(readNumber(pnh, "marker_length", &p.markers.length, "0.25"));
  if (!(p.markers.length > 0.0)) return Error{"~marker_length: must be > 0 m"};
  for (auto [name, ref] :
       {std::pair{"marker_angular_momentum_ref", &p.markers.angular_momentum_ref},
        std::pair{"marker_angular_velocity_ref", &p.markers.angular_velocity_ref}}) {
    CGA_RIGID_SIM_READ(readNumber(pnh, name, ref, "0.0"));
    if (!(*ref >= 0.0))
      return Error{std::string("~") + name + ": must be >= 0 (0 = chosen from the motion)"};
  }
  CGA_RIGID_SIM_READ(readNumber(pnh, "marker_force_ref", &p.markers.force_ref, "10.0"));
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
