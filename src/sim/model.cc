// compileModel: scene::Scene + WorldConfig → Model, and the name look-ups.
#include "cga_rigid_sim/sim/model.h"

#include <cmath>
#include <utility>

#include "cga_rigid_sim/body/integrator.h"
#include "contact/self_collision_rules.h"
#include "sim/curved_bodies.h"
#include "sim/input/input_rules.h"
#include "sim/tree_compile.h"

namespace cga_rigid_sim {
namespace sim {

int Model::findBody(const std::string& name) const {
  const auto b = body_by_name.find(name);
  return b == body_by_name.end() ? -1 : b->second;
}

int Model::resolveBody(const std::string& name) const {
  const int j = findBody(name);
  if (j >= 0) return j;
  const auto l = link_owner.find(name);
  return l != link_owner.end() ? l->second.first : -1;
}

int Model::findRobot(const std::string& name) const {
  for (std::size_t r = 0; r < robots.size(); ++r)
    if (robots[r].name == name) return static_cast<int>(r);
  return -1;
}

int Model::robotOfBody(int j) const {
  for (std::size_t r = 0; r < robots.size(); ++r)
    if (j >= robots[r].first_body && j < robots[r].first_body + robots[r].body_count)
      return static_cast<int>(r);
  return -1;
}

int appendBody(Model& model, scene::BodyModel body) {
  const int j = static_cast<int>(model.scene.bodies.size());
  model.body_by_name[body.name] = j;
  for (int li = 0; li < static_cast<int>(body.links.size()); ++li)
    model.link_owner[body.links[li].link] = {j, li};
  model.self_collision.appendBody();
  if (body.is_static) {
    model.moving_of_body.push_back(-1);
  } else {
    model.moving_of_body.push_back(static_cast<int>(model.moving.size()));
    model.tree_of_moving.push_back(-1);
    model.tree_body_of_moving.push_back(-1);
    model.moving.push_back(
        {j, *body.inertia, dynamics::BodyState{body.M_WB0, body.omega_B0}, std::nullopt});
  }
  model.scene.bodies.push_back(std::move(body));
  return j;
}

namespace {

// A surface's rules: μ finite and ≥ 0, e in [0, 1]. Fields are <prefix>mu, <prefix>restitution
// ("contact_mu", "ground_plane.mu").
std::optional<Error> checkSurface(const std::string& prefix, double mu, double e) {
  const std::string sep = prefix.back() == '.' ? "" : "_";
  if (!std::isfinite(mu) || mu < 0)
    return Error("config", prefix + sep + "mu", "must be finite and >= 0 (got " + num(mu) + ")");
  if (!std::isfinite(e) || e < 0 || e > 1)
    return Error("config", prefix + sep + "restitution", "must be in [0, 1] (got " + num(e) + ")");
  return std::nullopt;
}

// The contact model's extensions (doc/contact_model.md): every number finite, a static
// friction at least the kinetic one, a Stribeck speed > 0, patch levers ≥ 0, a restitution
// exponent ≥ 0 and its reference speed > 0.
std::optional<Error> checkContactModel(const ContactModel& m) {
  const auto field = [](const char* name) { return std::string("contact_model.") + name; };
  if (!std::isfinite(m.static_friction_ratio) || m.static_friction_ratio < 1)
    return Error("config", field("static_friction_ratio"),
                 "must be finite and >= 1: static friction is at least the kinetic one (got " +
                     num(m.static_friction_ratio) + ")");
  if (!std::isfinite(m.tangential_restitution) || m.tangential_restitution < 0 ||
      m.tangential_restitution > 1)
    return Error("config", field("tangential_restitution"),
                 "must be in [0, 1] (got " + num(m.tangential_restitution) + ")");
  if (!std::isfinite(m.face_restitution_ratio) || m.face_restitution_ratio < 0 ||
      m.face_restitution_ratio > 1)
    return Error("config", field("face_restitution_ratio"),
                 "must be in [0, 1]: a face bounces at most as a corner (got " +
                     num(m.face_restitution_ratio) + ")");
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"stribeck_speed", m.stribeck_speed},
        {"restitution_reference_speed", m.restitution_reference_speed},
        {"face_friction_ratio", m.face_friction_ratio},
        {"impact_friction_ratio", m.impact_friction_ratio}})
    if (!std::isfinite(value) || !(value > 0))
      return Error("config", field(name), "must be finite and > 0 (got " + num(value) + ")");
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"rolling_resistance", m.rolling_resistance},
        {"torsional_resistance", m.torsional_resistance},
        {"restitution_speed_exponent", m.restitution_speed_exponent},
        {"box_edge_radius", m.box_edge_radius},
        {"normal_stiffness", m.normal_stiffness},
        {"normal_dissipation", m.normal_dissipation}})
    if (!std::isfinite(value) || value < 0)
      return Error("config", field(name), "must be finite and >= 0 (got " + num(value) + ")");
  return std::nullopt;
}

// The configuration's rules (input "config").
std::optional<Error> checkConfig(const WorldConfig& config) {
  if (!std::isfinite(config.dt) || !(config.dt > 0))
    return Error("config", "dt", "must be finite and > 0 (got " + num(config.dt) + ")");
  if (!std::isfinite(config.max_force) || !(config.max_force > 0))
    return Error("config", "max_force",
                 "must be finite and > 0 (got " + num(config.max_force) + ")");
  if (!std::isfinite(config.max_impulse) || !(config.max_impulse > 0))
    return Error("config", "max_impulse",
                 "must be finite and > 0 (got " + num(config.max_impulse) + ")");
  if (config.world_frame.empty()) return Error("config", "world_frame", "must not be empty");
  for (const auto& [name, bound] :
       {std::pair<const char*, int>{"max_queued_inputs", config.max_queued_inputs},
        {"max_queued_inputs_per_body", config.max_queued_inputs_per_body},
        {"max_active_wrenches", config.max_active_wrenches},
        {"max_active_wrenches_per_body", config.max_active_wrenches_per_body}})
    if (bound < 1) return Error("config", name, "must be ≥ 1 (got " + std::to_string(bound) + ")");
  if (config.threads < 1 || config.threads > kMaxThreads)
    return Error("config", "threads",
                 "must be from 1 to " + std::to_string(kMaxThreads) + " (got " +
                     std::to_string(config.threads) + ")");
  if (auto e = checkSurface("contact", config.contact_mu, config.contact_restitution)) return e;
  if (auto e = checkContactModel(config.contact_model)) return e;
  if (config.ground_plane) {
    const GroundPlane& g = *config.ground_plane;
    if (!std::isfinite(g.height))
      return Error("config", "ground_plane.height", "must be finite (got " + num(g.height) + ")");
    if (auto e = checkSurface("ground_plane.", g.surface.mu.value_or(0.0),
                              g.surface.restitution.value_or(0.0)))
      return e;
  }
  // An unknown integrator is refused even when there is no moving body.
  if (config.curvature) return checkCurvedConfig(config);
  auto integ = dynamics::makeIntegrator(config.integrator);
  if (!integ) return Error("config", "integrator", integ.error());
  return std::nullopt;
}

// One scene body against the bodies before it (input "scene").
std::optional<Error> checkBody(const Model& model, const scene::BodyModel& b, int j) {
  if (b.name.empty()) return Error("scene", "body " + std::to_string(j), "has no name");
  const std::string where = "body '" + b.name + "'";
  if (model.body_by_name.count(b.name)) return Error("scene", where, "name used twice");
  if (b.links.empty()) return Error("scene", where, "has no link");
  for (std::size_t li = 0; li < b.links.size(); ++li) {
    const scene::LinkFrame& l = b.links[li];
    if (l.link == model.config.world_frame)
      return Error("scene", where, "link '" + l.link + "' has the name of the world frame");
    if (model.link_owner.count(l.link))
      return Error("scene", where, "link '" + l.link + "' used twice");
    for (std::size_t lj = 0; lj < li; ++lj)
      if (b.links[lj].link == l.link)
        return Error("scene", where, "link '" + l.link + "' used twice");
    if (!l.M_BL.allFinite()) return Error("scene", where, "link '" + l.link + "': M_BL not finite");
  }
  if (!b.M_WB0.allFinite()) return Error("scene", where, "initial pose not finite");
  if (b.is_static) return std::nullopt;
  if (!b.inertia) return Error("scene", where, "moving body without inertia");
  if (!b.omega_B0.allFinite()) return Error("scene", where, "initial velocity not finite");
  return std::nullopt;
}

}  // namespace

Result<Model> compileModel(scene::Scene scene, const WorldConfig& config) {
  if (auto e = checkConfig(config)) return *e;
  if (!std::isfinite(scene.lambda) || !(scene.lambda > 0))
    return Error("scene", "lambda", "must be finite and > 0 (got " + num(scene.lambda) + ")");
  if (auto e = checkFinite("scene", "gravity_W", scene.gravity_W)) return *e;

  Model model;
  model.config = config;
  model.lambda = scene.lambda;
  std::vector<scene::BodyModel> bodies = std::move(scene.bodies);
  scene.bodies.clear();
  model.scene = std::move(scene);
  for (std::size_t j = 0; j < bodies.size(); ++j) {
    if (auto e = checkBody(model, bodies[j], static_cast<int>(j))) return *e;
    appendBody(model, std::move(bodies[j]));
  }
  if (auto e = compileTrees(model)) return *e;
  compileSelfCollision(model);
  if (config.curvature)
    if (auto e = compileCurvedBodies(model)) return *e;
  return model;
}

}  // namespace sim
}  // namespace cga_rigid_sim
