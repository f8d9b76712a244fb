// The initial-state dictionary (schema: top of urdf_loader.cc and doc/initial_state.md).
//
// Poses are given for the root link R (the frame users know from the URDF); the scene keeps the
// body frame B (centre of mass, principal axes), related by the constant M_BR (the root link's
// LinkFrame). So M_WB = M_WR M_BR⁻¹. Velocities are given in world or root link axes and stored
// as the body bivelocity Ω_B = (w_B, v_B/λ) with w_B = R_WBᵀ w_W, v_B = R_WBᵀ v_W
// (doc/conventions.md (E6)).
//
// Joints (joint.h): an entry under a joint's name sets its initial position q0 (clamped into
// the limits, with a warning) and velocity q̇0. The joints' child bodies are not given poses of
// their own: after every entry is applied, each one is placed from its parent down the tree,
// M_WBc = M_WBp M_PJ exp(−½ q0 S) M_JC (placeJointChildren), so a body entry that moves the free
// root of a tree moves the whole tree.
#include "cga_rigid_sim/scene/initial_state.h"

#include <Eigen/Geometry>
#include <cmath>
#include <optional>
#include <unordered_map>
#include <vector>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/math/constants.h"
#include "cga_rigid_sim/scene/placement.h"
#include "cga_rigid_sim/scene/rotation_rule.h"

namespace cga_rigid_sim {
namespace scene {

namespace {

const char* const kKeys[] = {"position",
                             "orientation",
                             "rpy",
                             "linear_velocity",
                             "angular_velocity",
                             "linear_velocity_body",
                             "angular_velocity_body"};

const char* const kJointKeys[] = {"position", "velocity"};

std::string allowedKeys() {
  std::string s;
  for (const char* k : kKeys) s += (s.empty() ? "" : ", ") + std::string(k);
  return s;
}

// "rad" or "m" for a joint position; "rad/s" or "m/s" for its velocity.
const char* positionUnit(JointType t) { return t == JointType::kPrismatic ? "m" : "rad"; }
const char* velocityUnit(JointType t) { return t == JointType::kPrismatic ? "m/s" : "rad/s"; }

constexpr int kDigits = 10;  // significant digits of numbers in messages

// A list of n finite numbers; the error says which element is wrong and why.
Result<Eigen::VectorXd> readNumbers(const ParamValue& v, int n, const std::string& where) {
  if (!v.isList())
    return Error{where + ": expected a list of " + std::to_string(n) + " numbers, got a " +
                 v.typeName()};
  const auto& list = v.asList();
  if (static_cast<int>(list.size()) != n)
    return Error{where + ": expected a list of " + std::to_string(n) + " numbers, got " +
                 std::to_string(list.size())};
  Eigen::VectorXd out(n);
  for (int i = 0; i < n; ++i) {
    if (!list[i].isNumber())
      return Error{where + "[" + std::to_string(i) + "]: expected a number, got a " +
                   list[i].typeName()};
    out[i] = list[i].asNumber();
    if (!std::isfinite(out[i]))
      return Error{where + "[" + std::to_string(i) + "]: must be finite (got " +
                   formatNumber(out[i], kDigits) + ")"};
  }
  return out;
}

// The joint's own motion exp(−½ q S): S = (axis, 0) for a revolute or continuous joint (a turn
// by q about the axis, (E3)), S = (0, axis/λ) for a prismatic one (a shift by q along it, (E2)).
// A turn beyond ±4π is first reduced by whole multiples of 4π, the rotor's period (so not even
// its sign changes; std::remainder is exact, and the reduction's error, |q| 1.4e-16, is below
// the rounding of q itself): exp squares its angle, and a continuous joint set to 1e308 rad
// left a non-finite pose (found by fuzz_initial_state).
cga::Motor jointMotion(const JointModel& j, double q, double lambda) {
  if (j.type == JointType::kPrismatic)
    return cga::exp(cga::Bivelocity(Eigen::Vector3d::Zero(), j.axis / lambda) * (-0.5 * q));
  constexpr double kPeriod = 4 * math::kPi;
  const double turn = std::abs(q) > kPeriod ? std::remainder(q, kPeriod) : q;
  return cga::exp(cga::Bivelocity(j.axis, Eigen::Vector3d::Zero()) * (-0.5 * turn));
}

// One joint's entry {position: q, velocity: v}, `where` = "<source>: initial_state.<joint>".
// Writes the new q0 (clamped into the limits) and q̇0 and, when q had to be clamped, a warning.
std::optional<Error> readJointEntry(const JointModel& j, const ParamValue& entry,
                                    const std::string& where, double* q0, double* v0,
                                    std::vector<std::string>* warnings) {
  const std::string joint = "joint " + inQuotes(j.name);
  if (!entry.isMap())
    return Error{where + ": expected a map with keys among position, velocity (" + joint + ", " +
                 toString(j.type) + "), got a " + entry.typeName()};
  for (const auto& kv : entry.asMap()) {
    bool known = false;
    for (const char* k : kJointKeys) known = known || kv.first == k;
    if (!known)
      return Error{where + "." + kv.first + ": unknown key of " + joint +
                   " (allowed: position in " + positionUnit(j.type) + ", velocity in " +
                   velocityUnit(j.type) + ")"};
  }
  for (const char* key : kJointKeys) {
    const auto it = entry.asMap().find(key);
    if (it == entry.asMap().end()) continue;
    const bool is_position = key[0] == 'p';
    const std::string at = where + "." + key;
    if (!it->second.isNumber())
      return Error{at + ": expected a number (" + joint + ", in " +
                   (is_position ? positionUnit(j.type) : velocityUnit(j.type)) + "), got a " +
                   it->second.typeName()};
    const double x = it->second.asNumber();
    if (!std::isfinite(x))
      return Error{at + ": must be finite (got " + formatNumber(x, kDigits) + ")"};
    if (!is_position) {
      *v0 = x;
      continue;
    }
    const JointLimits& l = j.limits;
    *q0 = x;
    if (l.has_position && (x < l.lower || x > l.upper)) {
      *q0 = x < l.lower ? l.lower : l.upper;
      const std::string unit = std::string(" ") + positionUnit(j.type);
      warnings->push_back(at + ": " + formatNumber(x, kDigits) + unit + " is outside the limits [" +
                          formatNumber(l.lower, kDigits) + ", " + formatNumber(l.upper, kDigits) +
                          "]" + unit + " of " + joint + ": clamped to the " +
                          (x < l.lower ? "lower" : "upper") + " limit " +
                          formatNumber(*q0, kDigits) + unit);
    }
  }
  return std::nullopt;
}

}  // namespace

void placeJointChildren(Scene& scene) {
  followLeaders(scene.joints);  // mimic joints where their leaders put them
  for (const JointModel& j : scene.joints) {
    const cga::Motor M_WP =
        j.parent_body < 0 ? cga::Motor::identity() : scene.bodies[j.parent_body].M_WB0;
    scene.bodies[j.child_body].M_WB0 =
        (M_WP * j.M_PJ * jointMotion(j, j.initial_position, scene.lambda) * j.M_JC).normalized();
  }
}

Result<bool> applyInitialState(Scene& scene, const ParamValue& initial_state) {
  const std::string prefix = scene.source + ": initial_state";
  if (initial_state.isNone()) return true;
  if (!initial_state.isMap())
    return Error{prefix + ": expected a map from body name to its initial state, got a " +
                 initial_state.typeName()};
  const double lambda = scene.lambda;
  std::unordered_map<std::string, int> index, joint_index;
  for (std::size_t k = 0; k < scene.bodies.size(); ++k)
    index.emplace(scene.bodies[k].name, static_cast<int>(k));
  std::vector<int> moved_by(scene.bodies.size(), -1);  // the joint whose child the body is
  for (std::size_t k = 0; k < scene.joints.size(); ++k) {
    joint_index.emplace(scene.joints[k].name, static_cast<int>(k));
    moved_by[scene.joints[k].child_body] = static_cast<int>(k);
  }

  struct Update {
    int body;
    dynamics::BodyState state0;
  };
  struct JointUpdate {
    int joint;
    double q0, v0;
  };
  std::vector<Update> updates;  // applied only when every entry is valid
  std::vector<JointUpdate> joint_updates;
  std::vector<std::string> warnings;
  for (const auto& [name, entry] : initial_state.asMap()) {
    const std::string where = prefix + "." + name;
    const auto it = index.find(name);
    const auto jt = joint_index.find(name);
    // A name can be a link's (a body's) and a joint's: the joint's unless the body takes an
    // initial state of its own (a free body), and then the key is ambiguous.
    const bool body_takes_state =
        it != index.end() && !scene.bodies[it->second].is_static && moved_by[it->second] < 0;
    if (jt != joint_index.end() && body_takes_state)
      return Error{where + ": " + inQuotes(name) +
                   " names both a free body and a joint; rename one of them in the URDF (link "
                   "and joint names are separate in URDF, the keys of initial_state are not)"};
    if (jt != joint_index.end()) {
      const JointModel& j = scene.joints[jt->second];
      if (j.mimic)
        return Error{where + ": joint '" + name + "' mimics joint '" +
                     scene.joints[j.mimic->leader].name +
                     "' (<mimic>): its position and velocity follow that joint's; give them "
                     "there"};
      JointUpdate u{jt->second, j.initial_position, j.initial_velocity};
      if (auto err = readJointEntry(j, entry, where, &u.q0, &u.v0, &warnings)) return *err;
      // A leader also keeps the joints that mimic it within their limits.
      const auto [lower, upper] = mimicRange(scene.joints, jt->second);
      if (u.q0 < lower || u.q0 > upper) {
        const double q = u.q0;
        u.q0 = q < lower ? lower : upper;
        const std::string unit = std::string(" ") + positionUnit(j.type);
        warnings.push_back(where + ".position: " + formatNumber(q, kDigits) + unit +
                           " would take a joint that mimics joint '" + name +
                           "' outside its limits: clamped to " + formatNumber(u.q0, kDigits) +
                           unit + " (the range [" + formatNumber(lower, kDigits) + ", " +
                           formatNumber(upper, kDigits) + "]" + unit + " keeps them all within)");
      }
      joint_updates.push_back(u);
      continue;
    }
    if (it == index.end()) {
      std::string names;
      for (std::size_t k = 0; k < scene.bodies.size() && k < 10; ++k)
        names += (k ? ", " : "") + scene.bodies[k].name;
      if (scene.bodies.size() > 10) names += ", …";
      if (scene.joints.empty())
        return Error{where + ": no body named '" + name + "' (bodies: " + names + ")"};
      std::string joints;
      for (std::size_t k = 0; k < scene.joints.size() && k < 10; ++k)
        joints += (k ? ", " : "") + scene.joints[k].name;
      if (scene.joints.size() > 10) joints += ", …";
      return Error{where + ": no body or joint named '" + name + "' (bodies: " + names +
                   "; joints: " + joints + ")"};
    }
    const BodyModel& body = scene.bodies[it->second];
    if (body.is_static)
      return Error{where + ": body '" + name +
                   "' is static (fixed to the world frame): it never moves and takes no initial "
                   "state"};
    if (moved_by[it->second] >= 0)
      return Error{where + ": body '" + name + "' is moved by joint '" +
                   scene.joints[moved_by[it->second]].name +
                   "': give the joint's position instead"};
    if (!entry.isMap())
      return Error{where + ": expected a map with keys among " + allowedKeys() + ", got a " +
                   entry.typeName()};
    const auto& keys = entry.asMap();
    for (const auto& kv : keys) {
      bool known = false;
      for (const char* k : kKeys) known = known || kv.first == k;
      if (!known)
        return Error{where + "." + kv.first + ": unknown key (allowed: " + allowedKeys() + ")"};
    }
    for (const auto& [a, b] : {std::pair<const char*, const char*>{"orientation", "rpy"},
                               {"linear_velocity", "linear_velocity_body"},
                               {"angular_velocity", "angular_velocity_body"}})
      if (keys.count(a) && keys.count(b))
        return Error{where + ": give either '" + a + "' or '" + b + "', not both"};

    // The current root-link pose and world velocities; keys given replace parts of them.
    const cga::Motor& M_BR = body.links.front().M_BL;
    const cga::Motor M_WR = body.M_WB0 * M_BR;
    Eigen::Quaterniond q_WR = M_WR.rotation();
    Eigen::Vector3d x_WR = M_WR.translation(lambda);
    const Eigen::Quaterniond q_WB_old = body.M_WB0.rotation();
    Eigen::Vector3d w_W = q_WB_old * body.omega_B0.angular();
    Eigen::Vector3d v_W = q_WB_old * body.omega_B0.linear(lambda);

    if (keys.count("position")) {
      auto x = readNumbers(keys.at("position"), 3, where + ".position");
      if (!x) return Error{x.error()};
      x_WR = *x;
    }
    if (keys.count("orientation")) {
      auto q = readNumbers(keys.at("orientation"), 4, where + ".orientation");
      if (!q) return Error{q.error()};
      if (auto refused = quaternionRule((*q)[3], (*q)[0], (*q)[1], (*q)[2]))
        return Error{where + ".orientation: [x, y, z, w] " + *refused};
      q_WR = Eigen::Quaterniond((*q)[3], (*q)[0], (*q)[1], (*q)[2]).normalized();
    }
    if (keys.count("rpy")) {
      auto rpy = readNumbers(keys.at("rpy"), 3, where + ".rpy");
      if (!rpy) return Error{rpy.error()};
      // Fixed-axis roll, pitch, yaw as in URDF: R = Rz(y) Ry(p) Rx(r).
      q_WR = Eigen::AngleAxisd((*rpy)[2], Eigen::Vector3d::UnitZ()) *
             Eigen::AngleAxisd((*rpy)[1], Eigen::Vector3d::UnitY()) *
             Eigen::AngleAxisd((*rpy)[0], Eigen::Vector3d::UnitX());
    }
    for (const char* key : {"linear_velocity", "angular_velocity"}) {
      if (!keys.count(key)) continue;
      auto v = readNumbers(keys.at(key), 3, where + "." + key);
      if (!v) return Error{v.error()};
      (key[0] == 'l' ? v_W : w_W) = *v;
    }
    for (const char* key : {"linear_velocity_body", "angular_velocity_body"}) {
      if (!keys.count(key)) continue;
      auto v = readNumbers(keys.at(key), 3, where + "." + key);
      if (!v) return Error{v.error()};
      (key[0] == 'l' ? v_W : w_W) = q_WR * Eigen::Vector3d(*v);
    }

    updates.push_back({it->second, placedState(M_BR, q_WR, x_WR, v_W, w_W, lambda)});
  }
  for (const Update& u : updates) {
    scene.bodies[u.body].M_WB0 = u.state0.M_WB;
    scene.bodies[u.body].omega_B0 = u.state0.omega_B;
  }
  for (const JointUpdate& u : joint_updates) {
    scene.joints[u.joint].initial_position = u.q0;
    scene.joints[u.joint].initial_velocity = u.v0;
  }
  placeJointChildren(scene);
  scene.warnings.insert(scene.warnings.end(), warnings.begin(), warnings.end());
  return true;
}

}  // namespace scene
}  // namespace cga_rigid_sim
