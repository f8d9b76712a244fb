// Scene and the URDF loaders in Python (doc/python.md): a scene's properties and collision
// shapes, and load_urdf_file / load_urdf_string with the scene options.
#include <string>
#include <vector>

#include "bindings.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace python {
namespace {

// A Python value (None, bool, int, float, str, list/tuple/array, dict) as a ParamValue, the
// type the core's initial-state dictionary is written in.
scene::ParamValue paramValue(const py::handle& h, const std::string& where) {
  if (h.is_none()) return scene::ParamValue();
  if (py::isinstance<py::bool_>(h)) return scene::ParamValue(h.cast<bool>());
  if (py::isinstance<py::int_>(h) || py::isinstance<py::float_>(h))
    return scene::ParamValue(h.cast<double>());
  if (py::isinstance<py::str>(h)) return scene::ParamValue(h.cast<std::string>());
  if (py::isinstance<py::dict>(h)) {
    scene::ParamValue::Map map;
    for (const auto& kv : h.cast<py::dict>()) {
      const std::string key = py::str(kv.first);
      map.emplace(key, paramValue(kv.second, where + "." + key));
    }
    return scene::ParamValue(std::move(map));
  }
  if (py::isinstance<py::array>(h) || py::isinstance<py::list>(h) || py::isinstance<py::tuple>(h)) {
    scene::ParamValue::List list;
    int k = 0;
    for (const auto& item : py::iter(h))
      list.push_back(paramValue(item, where + "[" + std::to_string(k++) + "]"));
    return scene::ParamValue(std::move(list));
  }
  // numpy scalars and anything else that converts to a float
  try {
    return scene::ParamValue(h.cast<double>());
  } catch (const py::cast_error&) {
    throw py::type_error(where + ": cannot use a " +
                         std::string(py::str(h.get_type().attr("__name__"))) + " here");
  }
}

scene::SceneOptions sceneOptions(const py::object& gravity, const py::object& initial_state,
                                 double lambda, bool relax_inertia) {
  scene::SceneOptions o;
  o.lambda = lambda;
  if (!gravity.is_none()) o.gravity_W = vector3(gravity, "gravity");
  o.initial_state = paramValue(initial_state, "initial_state");
  o.triangle_policy = relax_inertia ? dynamics::TrianglePolicy::kNearestPhysical
                                    : dynamics::TrianglePolicy::kRefuse;
  return o;
}

}  // namespace

void bindScene(py::module_& m) {
  py::class_<scene::Scene>(m, "Scene",
                           "A URDF loaded and validated (constant); worlds are made from it.")
      .def_property_readonly("source", [](const scene::Scene& s) { return s.source; })
      .def_property_readonly("robot_name", [](const scene::Scene& s) { return s.robot_name; })
      .def_property_readonly(
          "gravity",
          [](const scene::Scene& s) {
            return std::vector<double>{s.gravity_W.x(), s.gravity_W.y(), s.gravity_W.z()};
          })
      .def_property_readonly("body_names",
                             [](const scene::Scene& s) {
                               std::vector<std::string> out;
                               for (const auto& b : s.bodies) out.push_back(b.name);
                               return out;
                             })
      .def_property_readonly("warnings", [](const scene::Scene& s) { return s.warnings; })
      .def(
          "collision_shapes",
          [](const scene::Scene& s, const std::string& body) {
            const int j = s.findBody(body);
            if (j < 0) throw py::value_error("body: unknown body '" + body + "'");
            py::list out;
            for (const auto& c : s.bodies[j].shapes) {
              py::dict d;
              d["kind"] = scene::toString(c.kind);
              d["size"] = std::vector<double>{c.size.x(), c.size.y(), c.size.z()};
              d["radius"] = c.radius;
              d["length"] = c.length;
              d["name"] = c.name;
              out.append(d);
            }
            return out;
          },
          py::arg("body"), "The collision shapes of a body: kind, size, radius, length, name.");

  m.def(
      "load_urdf_file",
      [](const std::string& path, const py::object& gravity, const py::object& initial_state,
         double lambda, bool relax_inertia) {
        return orRaise(
            scene::loadUrdfFile(path, sceneOptions(gravity, initial_state, lambda, relax_inertia)));
      },
      py::arg("path"), py::arg("gravity") = py::none(), py::arg("initial_state") = py::none(),
      py::arg("lambda_") = 1.0, py::arg("relax_inertia") = false,
      "Loads a URDF file into a Scene (raises ValueError naming file, link and rule).");
  m.def(
      "load_urdf_string",
      [](const std::string& xml, const std::string& source, const py::object& gravity,
         const py::object& initial_state, double lambda, bool relax_inertia) {
        return orRaise(scene::loadUrdfString(
            xml, source, sceneOptions(gravity, initial_state, lambda, relax_inertia)));
      },
      py::arg("xml"), py::arg("source") = "urdf_string", py::arg("gravity") = py::none(),
      py::arg("initial_state") = py::none(), py::arg("lambda_") = 1.0,
      py::arg("relax_inertia") = false, "Loads URDF text into a Scene.");
}

}  // namespace python
}  // namespace cga_rigid_sim
