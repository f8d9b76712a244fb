// Reading the node's controllers from the parameter server (controller_params.h).
#include "cga_rigid_sim/ros/controller_params.h"

#include <ros/console.h>

#include <sstream>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/ros/parameters.h"
#include "cga_rigid_sim/scene/flow_text.h"
#include "cga_rigid_sim/sim/data.h"

namespace cga_rigid_sim {
namespace node {
namespace {

constexpr const char* kListForm =
    "a list of controller names such as [arm_controller, joint_state_controller], or the names "
    "in one string separated by spaces";

// ~controllers as names: a list of strings, or a string of names separated by white space (a
// string holding a flow list, "[a, b]", as rosrun may hand it over, is read as that list).
Result<std::vector<std::string>> controllerNames(const scene::ParamValue& value) {
  std::vector<std::string> names;
  scene::ParamValue list = value;
  if (value.isString()) {
    const auto parsed = scene::parseFlowText(value.asString());
    if (parsed && parsed->type == scene::FlowValue::Type::kList) {
      list = scene::toParamValue(*parsed);
    } else {
      std::istringstream words(value.asString());
      for (std::string name; words >> name;) names.push_back(name);
      return names;
    }
  }
  if (!list.isList())
    return Error{std::string("~controllers: expected ") + kListForm + ", got " + value.typeName()};
  const scene::ParamValue::List& items = list.asList();
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (!items[k].isString() || items[k].asString().empty())
      return Error{"~controllers[" + std::to_string(k) +
                   "]: expected a controller name (a non-empty string), got " +
                   (items[k].isString() ? std::string("an empty string") : items[k].typeName())};
    names.push_back(items[k].asString());
  }
  return names;
}

// The value of `name` (a full parameter name) as a ParamValue; none when unset.
Result<scene::ParamValue> readValue(const ::ros::NodeHandle& nh, const std::string& name) {
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(name, v)) return scene::ParamValue();
  return toParamValue(v, name);
}

}  // namespace

Result<ControllerParams> readControllerParams(const ::ros::NodeHandle& nh,
                                              const ::ros::NodeHandle& pnh) {
  ControllerParams p;
  const std::string ns = nh.getNamespace();
  p.prefix = ns.empty() || ns.back() != '/' ? ns + "/" : ns;
  XmlRpc::XmlRpcValue raw;
  if (pnh.getParam("controllers", raw)) {
    p.set = true;
    auto value = toParamValue(raw, "~controllers");
    if (!value) return Error{value.error()};
    auto names = controllerNames(*value);
    if (!names) return Error{names.error()};
    p.names = std::move(*names);
  }
  p.spawn_names = p.names;
  if (pnh.getParam("spawn_controllers", raw)) {
    auto value = toParamValue(raw, "~spawn_controllers");
    if (!value) return Error{value.error()};
    auto names = controllerNames(*value);
    // (its messages name ~controllers: the form is the same)
    if (!names) return Error{"~spawn_" + names.error().substr(1)};
    p.spawn_names = std::move(*names);
  }
  if (p.names.empty() && p.spawn_names.empty()) return p;

  // The named controllers, and every entry of the namespace with a type (found by its
  // `<prefix><name>/type` parameter), so that the World's refusal of a misspelt name lists them.
  std::vector<std::string> entries = p.names;
  entries.insert(entries.end(), p.spawn_names.begin(), p.spawn_names.end());
  std::vector<std::string> all;
  if (nh.getParamNames(all)) {
    for (const std::string& param : all) {
      if (param.compare(0, p.prefix.size(), p.prefix) != 0) continue;
      const std::string rest = param.substr(p.prefix.size());
      const std::size_t slash = rest.find('/');
      if (slash == std::string::npos || rest.substr(slash) != "/type") continue;
      entries.push_back(rest.substr(0, slash));
    }
  }
  scene::ParamValue::Map controllers;
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const std::string& name = entries[k];
    if (controllers.count(name)) continue;
    auto entry = readValue(nh, p.prefix + name);
    if (!entry && k < p.names.size() + p.spawn_names.size()) return Error{entry.error()};
    if (entry && !entry->isNone()) controllers.emplace(name, std::move(*entry));
  }
  p.controllers = scene::ParamValue(std::move(controllers));
  auto pid = readValue(nh, p.prefix + "gazebo_ros_control/pid_gains");
  if (!pid) return Error{pid.error()};
  p.pid_gains = std::move(*pid);
  return p;
}

std::string controllerRefusalText(const Error& refusal, const std::string& prefix) {
  std::string root;
  if (refusal.input == "controllers")
    root = prefix;
  else if (refusal.input == "pid_gains")
    root = prefix + "gazebo_ros_control/pid_gains/";
  else
    return refusal.message();
  // The core's dotted path as the parameter's name: keys joined by '/', list indices kept.
  std::string path = refusal.field;
  for (char& c : path)
    if (c == '.') c = '/';
  if (path.empty() && root.size() > 1) root.pop_back();  // the whole namespace or pid_gains
  return root + path + ": " + refusal.rule;
}

bool startControllers(sim::World& world, const ControllerParams& params) {
  if (params.names.empty()) {
    if (params.set)
      ROS_WARN(
          "simulator: ~controllers is empty: no controller runs (name them, e.g. "
          "_controllers:=\"arm_controller joint_state_controller\")");
    return true;
  }
  auto loaded = world.loadControllers(params.controllers, params.names, params.pid_gains);
  if (!loaded) {
    ROS_FATAL("simulator: cannot start the controllers of ~controllers: %s",
              controllerRefusalText(loaded.failure(), params.prefix).c_str());
    return false;
  }
  for (const std::string& w : *loaded) ROS_WARN("simulator: controllers: %s", w.c_str());
  const auto& running = world.data().controllers.running;
  ROS_INFO("simulator: %zu controller%s (~controllers, read from %s):", running.size(),
           running.size() == 1 ? "" : "s", params.prefix.c_str());
  for (const sim::ControllerData& c : running) {
    const control::ControllerConfig& config = c.config;
    std::string what;
    if (config.type == control::ControllerType::kJointState) {
      what = "/joint_states at " + formatNumber(config.publish_rate) + " Hz";
    } else {
      for (const std::string& j : config.joints) what += (what.empty() ? "" : ", ") + j;
      what = "joints " + what + "; " + config.name + "/command";
      if (control::isTrajectoryController(config.type))
        what += ", " + config.name + "/state at " + formatNumber(config.publish_rate) + " Hz";
    }
    ROS_INFO("simulator:   %s (%s): %s", config.name.c_str(), control::typeName(config.type),
             what.c_str());
  }
  return true;
}

}  // namespace node
}  // namespace cga_rigid_sim
