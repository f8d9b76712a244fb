// Reading ros_control controller configuration (controller_config.h; doc/control.md).
#include "cga_rigid_sim/control/controller_config.h"

#include <cmath>
#include <set>
#include <utility>

namespace cga_rigid_sim {
namespace control {
namespace {

using scene::ParamValue;

constexpr ControllerType kAllTypes[] = {
    ControllerType::kJointState,       ControllerType::kPositionTrajectory,
    ControllerType::kEffortTrajectory, ControllerType::kVelocityTrajectory,
    ControllerType::kGroupPosition,    ControllerType::kGroupVelocity,
    ControllerType::kGroupEffort};

// Reads values of one dictionary, naming fields "<prefix>.<key>" in errors and warnings.
struct Reader {
  std::string input;
  std::string prefix;
  std::vector<std::string>* warnings;

  std::string field(const std::string& key) const {
    return prefix.empty() ? key : prefix + "." + key;
  }
  Error refuse(const std::string& key, const std::string& rule) const {
    return Error(input, field(key), rule);
  }
  Reader sub(const std::string& key) const { return {input, field(key), warnings}; }
  void warn(const std::string& key, const std::string& why) const {
    warnings->push_back(input + "." + field(key) + ": " + why);
  }
  // A finite number; `non_negative` also refuses values below 0.
  Result<double> number(const ParamValue& v, const std::string& key, bool non_negative) const {
    if (!v.isNumber()) return refuse(key, std::string("must be a number, not a ") + v.typeName());
    const double x = v.asNumber();
    if (!std::isfinite(x)) return refuse(key, "must be finite");
    if (non_negative && x < 0) return refuse(key, "must be >= 0");
    return x;
  }
  Result<bool> boolean(const ParamValue& v, const std::string& key) const {
    if (!v.isBool())
      return refuse(key, std::string("must be true or false, not a ") + v.typeName());
    return v.asBool();
  }
};

// control_toolbox's Pid::init: p required; i, d default 0; i_clamp → ±|i_clamp|; i_clamp_min and
// i_clamp_max override one side each (as −|v| and |v|); antiwindup default false.
Result<PidGains> readPid(const ParamValue& v, const Reader& r) {
  if (!v.isMap()) {
    return Error(r.input, r.prefix,
                 std::string("must be a dictionary {p, i, d, i_clamp}, not a ") + v.typeName());
  }
  const auto& m = v.asMap();
  if (!m.count("p")) return r.refuse("p", "is required (control_toolbox's Pid needs a p gain)");
  PidGains g;
  for (const auto& [key, value] : m) {
    if (key == "p" || key == "i" || key == "d") {
      auto x = r.number(value, key, true);
      if (!x) return x.failure();
      (key == "p" ? g.p : key == "i" ? g.i : g.d) = *x;
    } else if (key == "i_clamp" || key == "i_clamp_min" || key == "i_clamp_max") {
      auto x = r.number(value, key, false);
      if (!x) return x.failure();
      if (key == "i_clamp" && !m.count("i_clamp_min")) g.i_clamp_min = -std::abs(*x);
      if (key == "i_clamp" && !m.count("i_clamp_max")) g.i_clamp_max = std::abs(*x);
      if (key == "i_clamp_min") g.i_clamp_min = -std::abs(*x);
      if (key == "i_clamp_max") g.i_clamp_max = std::abs(*x);
    } else if (key == "antiwindup") {
      auto b = r.boolean(value, key);
      if (!b) return b.failure();
      g.antiwindup = *b;
    } else if (key == "publish_state") {
      r.warn(key, "not supported (no PID state topic); ignored");
    } else {
      r.warn(key,
             "not a PID key (p, i, d, i_clamp, i_clamp_min, i_clamp_max, antiwindup); ignored");
    }
  }
  return g;
}

Result<std::vector<std::string>> readJoints(const ParamValue& v, const Reader& r) {
  if (!v.isList() || v.asList().empty()) {
    return r.refuse("joints", "must be a non-empty list of joint names");
  }
  std::vector<std::string> joints;
  std::set<std::string> seen;
  for (std::size_t k = 0; k < v.asList().size(); ++k) {
    const ParamValue& j = v.asList()[k];
    const std::string key = "joints[" + std::to_string(k) + "]";
    if (!j.isString() || j.asString().empty()) return r.refuse(key, "must be a joint name");
    if (!seen.insert(j.asString()).second) {
      return r.refuse(key, "'" + j.asString() + "' is listed twice");
    }
    joints.push_back(j.asString());
  }
  return joints;
}

Result<ControllerConstraints> readConstraints(const ParamValue& v, const Reader& r,
                                              const std::vector<std::string>& joints) {
  if (!v.isMap()) return Error(r.input, r.prefix, "must be a dictionary");
  ControllerConstraints c;
  for (const auto& [key, value] : v.asMap()) {
    if (key == "goal_time" || key == "stopped_velocity_tolerance") {
      auto x = r.number(value, key, true);
      if (!x) return x.failure();
      (key == "goal_time" ? c.goal_time : c.stopped_velocity_tolerance) = *x;
      continue;
    }
    bool ours = false;
    for (const std::string& j : joints) ours = ours || j == key;
    if (!ours || !value.isMap()) {
      r.warn(key,
             "neither goal_time, stopped_velocity_tolerance nor a joint of this controller; "
             "ignored");
      continue;
    }
    const Reader joint = r.sub(key);
    JointConstraint& jc = c.joints[key];
    for (const auto& [k, x] : value.asMap()) {
      if (k != "trajectory" && k != "goal") {
        joint.warn(k, "not a joint constraint (trajectory, goal); ignored");
        continue;
      }
      auto t = joint.number(x, k, true);
      if (!t) return t.failure();
      (k == "trajectory" ? jc.trajectory : jc.goal) = *t;
    }
  }
  return c;
}

// `gains` or `velocity_ff`: joint → value; entries for other joints warned.
template <class T, class ReadOne>
Result<std::map<std::string, T>> readPerJoint(const ParamValue& v, const Reader& r,
                                              const std::vector<std::string>& joints,
                                              ReadOne readOne) {
  if (!v.isMap()) return Error(r.input, r.prefix, "must be a dictionary joint → value");
  std::map<std::string, T> out;
  for (const auto& [key, value] : v.asMap()) {
    bool ours = false;
    for (const std::string& j : joints) ours = ours || j == key;
    if (!ours) {
      r.warn(key, "not a joint of this controller; ignored");
      continue;
    }
    auto x = readOne(value, r.sub(key), key);
    if (!x) return x.failure();
    out[key] = *x;
  }
  return out;
}

Result<ControllerConfig> readController(const std::string& name, const ParamValue& v,
                                        std::vector<std::string>* warnings) {
  const Reader r{"controllers", name, warnings};
  if (!v.isMap()) return Error(r.input, name, "must be a controller's dictionary");
  const auto& m = v.asMap();
  if (!m.count("type") || !m.at("type").isString()) {
    return r.refuse("type", "is required: a ros_control controller type string");
  }
  ControllerConfig c;
  c.name = name;
  const std::string& type = m.at("type").asString();
  bool known = false;
  std::string supported;
  for (ControllerType t : kAllTypes) {
    supported += std::string(supported.empty() ? "" : ", ") + typeName(t);
    if (type == typeName(t)) c.type = t, known = true;
  }
  if (!known) {
    return r.refuse("type", "'" + type +
                                "' is not a controller type the simulator runs; "
                                "supported: " +
                                supported);
  }
  const bool trajectory = isTrajectoryController(c.type);
  const bool pid =
      c.type == ControllerType::kEffortTrajectory || c.type == ControllerType::kVelocityTrajectory;
  if (c.type == ControllerType::kJointState) {
    if (!m.count("publish_rate")) {
      return r.refuse("publish_rate", "is required by joint_state_controller (Hz, > 0)");
    }
  } else {
    if (!m.count("joints")) return r.refuse("joints", "is required: the joints it commands");
    auto joints = readJoints(m.at("joints"), r);
    if (!joints) return joints.failure();
    c.joints = std::move(*joints);
  }
  if (trajectory) c.publish_rate = 50;  // joint_trajectory_controller's default
  for (const auto& [key, value] : m) {
    const bool jsc = c.type == ControllerType::kJointState;
    if (key == "type" || (key == "joints" && !jsc)) continue;
    if ((jsc && key == "publish_rate") || (trajectory && key == "state_publish_rate") ||
        (trajectory && key == "action_monitor_rate")) {
      auto x = r.number(value, key, true);
      if (!x) return x.failure();
      if (*x == 0) return r.refuse(key, "must be > 0 (Hz)");
      (key == "action_monitor_rate" ? c.action_monitor_rate : c.publish_rate) = *x;
    } else if (trajectory &&
               (key == "stop_trajectory_duration" || key == "hold_trajectory_duration")) {
      auto x = r.number(value, key, true);
      if (!x) return x.failure();
      c.stop_trajectory_duration = *x;
      if (key == "hold_trajectory_duration")
        r.warn(key, "deprecated; read as stop_trajectory_duration");
    } else if (trajectory && key == "allow_partial_joints_goal") {
      auto b = r.boolean(value, key);
      if (!b) return b.failure();
      c.allow_partial_joints_goal = *b;
    } else if (trajectory && key == "constraints") {
      auto k = readConstraints(value, r.sub(key), c.joints);
      if (!k) return k.failure();
      c.constraints = std::move(*k);
    } else if (pid && key == "gains") {
      auto g = readPerJoint<PidGains>(
          value, r.sub(key), c.joints,
          [](const ParamValue& x, const Reader& jr, const std::string&) { return readPid(x, jr); });
      if (!g) return g.failure();
      c.gains = std::move(*g);
    } else if (pid && key == "velocity_ff") {
      // (A copy, not the structured binding `key`: C++17 lambdas cannot capture those.)
      const Reader sub = r.sub(key);
      auto f = readPerJoint<double>(
          value, sub, c.joints,
          [&sub](const ParamValue& x, const Reader&, const std::string& joint) {
            return sub.number(x, joint, false);
          });
      if (!f) return f.failure();
      c.velocity_ff = std::move(*f);
    } else if (trajectory && (key == "gains" || key == "velocity_ff")) {
      r.warn(key,
             "ignored: a position_controllers trajectory controller forwards positions; "
             "the position servos' gains are gazebo_ros_control/pid_gains");
    } else {
      r.warn(key, std::string("not read for ") + typeName(c.type) + "; ignored");
    }
  }
  if (pid) {
    for (const std::string& j : c.joints) {
      if (!c.gains.count(j)) {
        return r.refuse("gains." + j + ".p", std::string("is required: ") + typeName(c.type) +
                                                 " closes a PID per joint (gains: {" + j +
                                                 ": {p, i, d, i_clamp}})");
      }
    }
  }
  return c;
}

}  // namespace

Result<ControllerSet> parseControllers(const ParamValue& ns,
                                       const std::vector<std::string>& names) {
  if (!ns.isMap()) {
    return Error("controllers", "",
                 std::string("the controllers' namespace must be a dictionary, "
                             "not a ") +
                     ns.typeName());
  }
  const auto& m = ns.asMap();
  ControllerSet set;
  std::vector<std::string> chosen = names;
  if (chosen.empty()) {
    for (const auto& [key, value] : m) {
      if (value.isMap() && value.asMap().count("type")) {
        chosen.push_back(key);
      } else if (key != "gazebo_ros_control") {
        set.warnings.push_back("controllers." + key + ": not a controller (no type); passed over");
      }
    }
  }
  std::string found;
  for (const auto& entry : m) found += (found.empty() ? "" : ", ") + entry.first;
  std::map<std::string, std::string> owner;  // joint → commanding controller
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    const std::string& name = chosen[k];
    if (!m.count(name)) {
      return Error("controllers", name,
                   "no controller of that name in the namespace (found: " + found + ")");
    }
    for (std::size_t i = 0; i < k; ++i) {
      if (chosen[i] == name) return Error("controllers", name, "is listed twice");
    }
    auto c = readController(name, m.at(name), &set.warnings);
    if (!c) return c.failure();
    for (std::size_t j = 0; j < c->joints.size(); ++j) {
      auto [it, fresh] = owner.emplace(c->joints[j], name);
      if (!fresh) {
        return Error("controllers", name + ".joints[" + std::to_string(j) + "]",
                     "joint '" + c->joints[j] + "' is already commanded by controller '" +
                         it->second + "'; a joint takes commands from one controller");
      }
    }
    set.controllers.push_back(std::move(*c));
  }
  return set;
}

Result<PidGainsSet> parsePidGains(const ParamValue& pid_gains) {
  PidGainsSet set;
  if (!pid_gains.isMap()) {
    return Error("pid_gains", "",
                 std::string("must be a dictionary joint → {p, i, d, i_clamp}, "
                             "not a ") +
                     pid_gains.typeName());
  }
  for (const auto& [joint, value] : pid_gains.asMap()) {
    auto g = readPid(value, Reader{"pid_gains", joint, &set.warnings});
    if (!g) return g.failure();
    set.gains[joint] = *g;
  }
  return set;
}

}  // namespace control
}  // namespace cga_rigid_sim
