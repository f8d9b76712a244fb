// The keyword options of cga_rigid_sim.World (doc/python.md) → sim::WorldConfig, and gravity
// into the scene. An unknown option, a value of the wrong type or shape is a ValueError naming
// it; the ranges (dt > 0, μ ≥ 0, e in [0, 1], …) are the core's to check (World::create).
#pragma once

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/sim/world_config.h"

namespace cga_rigid_sim {
namespace python {

namespace py = pybind11;

inline double number(const py::handle& h, const std::string& key) {
  try {
    return h.cast<double>();
  } catch (const py::cast_error&) {
    throw py::value_error(key + ": expected a number");
  }
}

// {height, mu, restitution} (each optional) or a number (the height); None: no plane.
inline std::optional<sim::GroundPlane> groundPlane(const py::handle& h) {
  if (h.is_none()) return std::nullopt;
  sim::GroundPlane plane;
  if (!py::isinstance<py::dict>(h)) {
    plane.height = number(h, "ground_plane");
    return plane;
  }
  for (const auto& kv : h.cast<py::dict>()) {
    const std::string key = py::str(kv.first);
    if (key == "height")
      plane.height = number(kv.second, "ground_plane.height");
    else if (key == "mu")
      plane.surface.mu = number(kv.second, "ground_plane.mu");
    else if (key == "restitution")
      plane.surface.restitution = number(kv.second, "ground_plane.restitution");
    else
      throw py::value_error("ground_plane." + key + ": unknown key (height, mu, restitution)");
  }
  return plane;
}

// The contact model's extensions (sim::ContactModel, doc/contact_model.md), by field name.
inline void contactModel(const py::handle& h, sim::ContactModel& out) {
  if (h.is_none()) return;
  if (!py::isinstance<py::dict>(h))
    throw py::value_error("contact_model: expected a dict of the fields of doc/contact_model.md");
  for (const auto& kv : h.cast<py::dict>()) {
    const std::string key = py::str(kv.first);
    double* field = key == "static_friction_ratio"         ? &out.static_friction_ratio
                    : key == "stribeck_speed"              ? &out.stribeck_speed
                    : key == "rolling_resistance"          ? &out.rolling_resistance
                    : key == "torsional_resistance"        ? &out.torsional_resistance
                    : key == "restitution_speed_exponent"  ? &out.restitution_speed_exponent
                    : key == "restitution_reference_speed" ? &out.restitution_reference_speed
                    : key == "box_edge_radius"             ? &out.box_edge_radius
                    : key == "normal_stiffness"            ? &out.normal_stiffness
                    : key == "normal_dissipation"          ? &out.normal_dissipation
                    : key == "tangential_restitution"      ? &out.tangential_restitution
                    : key == "face_friction_ratio"         ? &out.face_friction_ratio
                    : key == "impact_friction_ratio"       ? &out.impact_friction_ratio
                    : key == "face_restitution_ratio"      ? &out.face_restitution_ratio
                                                           : nullptr;
    if (!field)
      throw py::value_error("contact_model." + key +
                            ": unknown field (static_friction_ratio, stribeck_speed, "
                            "rolling_resistance, torsional_resistance, "
                            "restitution_speed_exponent, restitution_reference_speed, "
                            "box_edge_radius, normal_stiffness, normal_dissipation, "
                            "tangential_restitution, face_friction_ratio, "
                            "impact_friction_ratio, face_restitution_ratio)");
    *field = number(kv.second, "contact_model." + key);
  }
}

inline sim::WorldConfig worldConfig(const py::kwargs& options, scene::Scene& scene) {
  sim::WorldConfig c;
  c.threads = 1;
  for (const auto& kv : options) {
    const std::string key = py::str(kv.first);
    const py::handle v = kv.second;
    if (key == "dt") {
      c.dt = number(v, key);
    } else if (key == "integrator") {
      c.integrator = v.cast<std::string>();
    } else if (key == "gravity") {
      const std::vector<double> g = v.cast<std::vector<double>>();
      if (g.size() != 3) throw py::value_error("gravity: expected 3 numbers");
      scene.gravity_W = Eigen::Vector3d(g[0], g[1], g[2]);
      if (!scene.gravity_W.allFinite()) throw py::value_error("gravity: not finite");
    } else if (key == "ground_plane") {
      c.ground_plane = groundPlane(v);
    } else if (key == "contact_mu") {
      c.contact_mu = number(v, key);
    } else if (key == "contact_restitution") {
      c.contact_restitution = number(v, key);
    } else if (key == "contact_sleeping") {
      c.contact_sleeping = v.cast<bool>();
    } else if (key == "contact_model") {
      contactModel(v, c.contact_model);
    } else if (key == "threads") {
      c.threads = v.cast<int>();
    } else if (key == "world_frame") {
      c.world_frame = v.cast<std::string>();
    } else if (key == "max_force") {
      c.max_force = number(v, key);
    } else if (key == "max_impulse") {
      c.max_impulse = number(v, key);
    } else {
      throw py::value_error(
          key +
          ": unknown option (dt, integrator, gravity, ground_plane, contact_mu, "
          "contact_restitution, contact_sleeping, contact_model, threads, world_frame, "
          "max_force, max_impulse)");
    }
  }
  return c;
}

}  // namespace python
}  // namespace cga_rigid_sim
