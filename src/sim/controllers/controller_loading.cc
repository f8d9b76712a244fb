// Loading ros_control controllers onto the trees' joints (controllers.h,
// doc/control.md#in-the-world): the YAML read by control/controller_config.h, each joint found
// by name, each joint's servo law chosen, the trajectory controllers started holding the pose.
#include <cmath>
#include <map>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/tree/tree_integrator.h"
#include "sim/controllers/controllers.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

const std::string kInput = "controllers";

// The gains of a position or velocity joint that pid_gains leaves out: a servo critically damped
// at ω = 1/(2h) on the joint's inertia at the initial pose, I = M_kk (the rest of the tree held):
// kp = I ω², kd = 2 I ω for a position joint, the gain I ω on q̇ for a velocity joint. Stiff
// enough that the joint follows its reference within a few steps (gazebo_ros_control sets such a
// joint's position outright), and stable because the tree step integrates the servo implicitly.
control::PidGains defaultGains(const Model& model, const Eigen::MatrixXd& M, int tree, int joint,
                               control::JointInterface interface) {
  const dynamics::ArticulatedBody& body = model.trees[tree].body;
  const double I = M(body.velocityIndex(joint), body.velocityIndex(joint));
  const double w = 0.5 / model.config.dt;
  control::PidGains g;
  if (interface == control::JointInterface::kPosition) {
    g.p = I * w * w;
    g.d = 2.0 * I * w;
  } else {
    g.p = I * w;
  }
  return g;
}

// The tree and joint indices of a controller's joints: every joint known, all in one tree,
// none a mimic follower (its leader is what moves it), none driven by a running controller.
Result<bool> placeJoints(const Model& model, const ControllersData& running,
                         const control::ControllerConfig& c, ControllerData& out) {
  for (std::size_t j = 0; j < c.joints.size(); ++j) {
    const std::string field = c.name + ".joints[" + std::to_string(j) + "]";
    const auto it = model.joint_by_name.find(c.joints[j]);
    if (it == model.joint_by_name.end())
      return Error(kInput, field, "unknown joint '" + c.joints[j] + "'");
    const auto [tree, joint] = it->second;
    if (out.tree >= 0 && tree != out.tree)
      return Error(kInput, field,
                   "joint '" + c.joints[j] + "' is not in the same robot as '" + c.joints[0] +
                       "' (a controller drives one robot)");
    const dynamics::TreeJoint& tj = model.trees[tree].body.joints()[joint];
    if (tj.mimic >= 0)
      return Error(kInput, field,
                   "joint '" + c.joints[j] + "' mimics joint '" +
                       model.scene.joints[model.trees[tree].scene_joint[tj.mimic]].name +
                       "': command that one");
    for (const ControllerData& other : running.running)
      if (other.tree == tree && other.config.type != control::ControllerType::kJointState)
        for (int k : other.joints)
          if (k == joint)
            return Error(kInput, field,
                         "joint '" + c.joints[j] + "' is already driven by controller '" +
                             other.config.name + "'");
    out.tree = tree;
    out.joints.push_back(joint);
  }
  return true;
}

// Each joint's servo law and integral gains; pid_gains missing for a position or velocity joint
// are the defaults (defaultGains), said in a warning.
Result<bool> chooseGains(const Model& model, const Data& data, const control::PidGainsSet& pid,
                         ControllerData& out, std::vector<std::string>& warnings) {
  const control::ControllerConfig& c = out.config;
  const control::JointInterface interface = control::jointInterface(c.type);
  std::map<std::string, control::PidGains> gains = pid.gains;
  Eigen::MatrixXd M;
  for (std::size_t j = 0; j < c.joints.size(); ++j) {
    const bool servoed = interface == control::JointInterface::kPosition ||
                         interface == control::JointInterface::kVelocity;
    if (servoed && !gains.count(c.joints[j])) {
      if (M.size() == 0) {
        dynamics::TreeKinematics kin;
        dynamics::treeKinematics(model.trees[out.tree].body, data.trees[out.tree].state, kin);
        dynamics::massMatrix(model.trees[out.tree].body, kin, M);
      }
      const control::PidGains g = defaultGains(model, M, out.tree, out.joints[j], interface);
      gains[c.joints[j]] = g;
      warnings.push_back(c.name + ": no gazebo_ros_control/pid_gains/" + c.joints[j] +
                         ": using p " + formatNumber(g.p, 6) + ", d " + formatNumber(g.d, 6) +
                         " (critically damped at 1/(2 dt))");
    }
    auto servo = control::servoGains(c, c.joints[j], gains);
    if (!servo) return servo.failure();
    out.gains.push_back(*servo);
    control::PidGains integral;  // the integral term of the law: ki and its clamps
    integral.i = servo->ki;
    integral.i_clamp_min = servo->i_clamp_min;
    integral.i_clamp_max = servo->i_clamp_max;
    integral.antiwindup = servo->antiwindup;
    out.pid.push_back(integral);
  }
  out.integral.assign(c.joints.size(), control::PidIntegral());
  return true;
}

// Trajectory controllers start holding the pose; group position controllers hold it too.
Result<bool> start(const Model& model, const Data& data, ControllerData& out) {
  const control::ControllerConfig& c = out.config;
  const Eigen::VectorXd& q = data.trees[out.tree].state.q;
  if (control::isTrajectoryController(c.type)) {
    control::TrajectoryControllerOptions o;
    o.name = c.name;
    o.joint_names = c.joints;
    o.joint_indices.assign(out.joints.begin(), out.joints.end());
    o.constraints.goal_time = c.constraints.goal_time;
    o.constraints.stopped_velocity_tolerance = c.constraints.stopped_velocity_tolerance;
    for (const std::string& name : c.joints) {
      const auto it = c.constraints.joints.find(name);
      control::JointTolerances t;
      if (it != c.constraints.joints.end()) t = {it->second.trajectory, it->second.goal};
      o.constraints.joints.push_back(t);
    }
    o.stop_trajectory_duration = c.stop_trajectory_duration;
    o.allow_partial_joints_goal = c.allow_partial_joints_goal;
    const double now = static_cast<double>(data.step_count) * model.config.dt;
    auto made = control::TrajectoryController::create(std::move(o), now, q);
    if (!made) return Error(kInput, c.name, made.failure().message());
    out.trajectory = std::move(*made);
  }
  out.command.assign(c.joints.size(), 0.0);
  if (c.type == control::ControllerType::kGroupPosition)
    for (std::size_t j = 0; j < out.joints.size(); ++j) out.command[j] = q[out.joints[j]];
  return true;
}

}  // namespace

namespace {

// Adds the controllers of `set` with the servo gains `pid`, all or nothing; their names and
// joints as they are. `name_space` is recorded in each (ControllerData::name_space).
Result<std::vector<std::string>> addControllers(const Model& model, Data& data,
                                                const control::ControllerSet& set,
                                                const control::PidGainsSet& pid,
                                                const std::string& name_space) {
  std::vector<std::string> warnings = set.warnings;
  warnings.insert(warnings.end(), pid.warnings.begin(), pid.warnings.end());
  // Every controller is checked before any is added: a refusal leaves the world as it was.
  ControllersData next = data.controllers;
  for (const control::ControllerConfig& c : set.controllers) {
    for (const ControllerData& other : next.running)
      if (other.config.name == c.name)
        return Error(kInput, c.name, "a controller of that name is already running");
    ControllerData cd;
    cd.config = c;
    cd.name_space = name_space;
    if (c.type != control::ControllerType::kJointState) {
      if (auto placed = placeJoints(model, next, c, cd); !placed) return placed.failure();
      if (auto chosen = chooseGains(model, data, pid, cd, warnings); !chosen)
        return chosen.failure();
      if (auto started = start(model, data, cd); !started) return started.failure();
    }
    next.running.push_back(std::move(cd));
  }
  data.controllers = std::move(next);
  for (const ControllerData& cd : data.controllers.running) {  // the servos the trees carry
    if (cd.tree < 0) continue;
    dynamics::JointServos& servos = data.trees[cd.tree].loads.servos;
    if (!servos.active()) servos.resize(model.trees[cd.tree].body.jointCount());
  }
  return warnings;
}

// A map keyed by joint names with the keys prefixed.
template <class T>
std::map<std::string, T> prefixedKeys(const std::map<std::string, T>& by_joint,
                                      const std::string& prefix) {
  std::map<std::string, T> out;
  for (const auto& [joint, value] : by_joint) out.emplace(prefix + joint, value);
  return out;
}

// The YAML's controllers `names` and its pid_gains (none: no gains), as control/ reads them.
struct Parsed {
  control::ControllerSet set;
  control::PidGainsSet pid;
};
Result<Parsed> parse(const scene::ParamValue& controllers, const std::vector<std::string>& names,
                     const scene::ParamValue& pid_gains) {
  Parsed out;
  auto set = control::parseControllers(controllers, names);
  if (!set) return set.failure();
  out.set = std::move(*set);
  if (!pid_gains.isNone()) {
    auto pid = control::parsePidGains(pid_gains);
    if (!pid) return pid.failure();
    out.pid = std::move(*pid);
  }
  return out;
}

}  // namespace

Result<std::vector<std::string>> loadControllers(const Model& model, Data& data,
                                                 const scene::ParamValue& controllers,
                                                 const std::vector<std::string>& names,
                                                 const scene::ParamValue& pid_gains) {
  auto parsed = parse(controllers, names, pid_gains);
  if (!parsed) return parsed.failure();
  return addControllers(model, data, parsed->set, parsed->pid, "");
}

Result<std::vector<std::string>> loadRobotControllers(const Model& model, Data& data, int robot,
                                                      const scene::ParamValue& controllers,
                                                      const std::vector<std::string>& names,
                                                      const scene::ParamValue& pid_gains) {
  const RobotModel& r = model.robots[robot];
  auto parsed = parse(controllers, names, pid_gains);
  if (!parsed) return parsed.failure();
  const control::ControllerSet& set = parsed->set;
  control::PidGainsSet& pid = parsed->pid;
  const std::string prefix = r.name_space.empty() ? "" : r.name_space + "/";
  pid.gains = prefixedKeys(pid.gains, prefix);
  const auto ours = [&model, &r](const std::string& joint) {
    const auto it = model.joint_by_name.find(joint);
    return it != model.joint_by_name.end() && it->second.first >= r.first_tree &&
           it->second.first < r.first_tree + r.tree_count;
  };
  control::ControllerSet robot_set;
  robot_set.warnings = set.warnings;
  for (control::ControllerConfig c : set.controllers) {
    if (c.type == control::ControllerType::kJointState) continue;
    std::size_t have = 0;
    for (std::string& joint : c.joints) {
      joint = prefix + joint;
      have += ours(joint) ? 1 : 0;
    }
    if (have == 0) continue;  // a controller of another robot
    c.name = prefix + c.name;
    c.gains = prefixedKeys(c.gains, prefix);
    c.velocity_ff = prefixedKeys(c.velocity_ff, prefix);
    c.constraints.joints = prefixedKeys(c.constraints.joints, prefix);
    robot_set.controllers.push_back(std::move(c));
  }
  return addControllers(model, data, robot_set, pid, r.name_space);
}

void removeControllersOfTrees(Data& data, int first_tree, int count) {
  ControllersData& cs = data.controllers;
  std::vector<int> new_index(cs.running.size(), -1);
  std::size_t kept = 0;
  for (std::size_t c = 0; c < cs.running.size(); ++c) {
    ControllerData& cd = cs.running[c];
    if (cd.tree >= first_tree && cd.tree < first_tree + count) continue;
    if (cd.tree >= first_tree + count) cd.tree -= count;
    new_index[c] = static_cast<int>(kept);
    if (kept != c) cs.running[kept] = std::move(cd);
    ++kept;
  }
  cs.running.resize(kept);
  std::size_t out = 0;
  for (std::size_t k = 0; k < cs.waiting.size(); ++k) {
    ControllerCommand& command = cs.waiting[k];
    if (new_index[command.controller] < 0) continue;
    command.controller = new_index[command.controller];
    if (out != k) cs.waiting[out] = std::move(command);
    ++out;
  }
  cs.waiting.resize(out);
}

void resetControllers(const Model& model, Data& data) {
  data.controllers.waiting.clear();
  for (ControllerData& cd : data.controllers.running) {
    if (cd.tree < 0) continue;
    data.trees[cd.tree].loads.servos.resize(model.trees[cd.tree].body.jointCount());
    for (control::PidIntegral& i : cd.integral) i.reset();
    start(model, data, cd);
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
