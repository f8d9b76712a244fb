// The initial-state dictionary (schema: top of urdf_loader.cc and doc/initial_state.md).
//
// Poses are given for the root link R (the frame users know from the URDF); the scene keeps the
// body frame B (centre of mass, principal axes), related by the constant M_BR (the root link's
// LinkFrame). So M_WB = M_WR M_BR⁻¹. Velocities are given in world or root link axes and stored
// as the body bivelocity Ω_B = (w_B, v_B/λ) with w_B = R_WBᵀ w_W, v_B = R_WBᵀ v_W
// (doc/conventions.md (E6)).
#include "cga_rigid_sim/scene/initial_state.h"

#include <Eigen/Geometry>
#include <cmath>
#include <unordered_map>

#include "cga_rigid_sim/format.h"
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

std::string allowedKeys() {
  std::string s;
  for (const char* k : kKeys) s += (s.empty() ? "" : ", ") + std::string(k);
  return s;
}

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

}  // namespace

Result<bool> applyInitialState(Scene& scene, const ParamValue& initial_state) {
  const std::string prefix = scene.source + ": initial_state";
  if (initial_state.isNone()) return true;
  if (!initial_state.isMap())
    return Error{prefix + ": expected a map from body name to its initial state, got a " +
                 initial_state.typeName()};
  const double lambda = scene.lambda;
  std::unordered_map<std::string, int> index;
  for (std::size_t k = 0; k < scene.bodies.size(); ++k)
    index.emplace(scene.bodies[k].name, static_cast<int>(k));

  struct Update {
    int body;
    dynamics::BodyState state0;
  };
  std::vector<Update> updates;  // applied only when every entry is valid
  for (const auto& [name, entry] : initial_state.asMap()) {
    const std::string where = prefix + "." + name;
    const auto it = index.find(name);
    if (it == index.end()) {
      std::string names;
      for (std::size_t k = 0; k < scene.bodies.size() && k < 10; ++k)
        names += (k ? ", " : "") + scene.bodies[k].name;
      if (scene.bodies.size() > 10) names += ", …";
      return Error{where + ": no body named '" + name + "' (bodies: " + names + ")"};
    }
    const BodyModel& body = scene.bodies[it->second];
    if (body.is_static)
      return Error{where + ": body '" + name +
                   "' is static (fixed to the world frame): it never moves and takes no initial "
                   "state"};
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
  return true;
}

}  // namespace scene
}  // namespace cga_rigid_sim
