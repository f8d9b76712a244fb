// Internal to the Python module (module.cc): what its bind… files share — the array type, the
// refusal of the core raised as ValueError, 3-vectors from Python — and the bind… functions that
// PYBIND11_MODULE calls in order.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace python {

namespace py = pybind11;

using Array = py::array_t<double, py::array::c_style>;

template <class T>
T orRaise(Result<T> r) {
  if (!r.ok()) throw py::value_error(r.error());
  return std::move(r).value();
}

inline Eigen::Vector3d vector3(const py::handle& h, const char* what) {
  const std::vector<double> v = py::cast<std::vector<double>>(h);
  if (v.size() != 3)
    throw py::value_error(std::string(what) + ": expected 3 numbers, got " +
                          std::to_string(v.size()));
  return {v[0], v[1], v[2]};
}

/// Scene and the URDF loaders (bind_scene.cc).
void bindScene(py::module_& m);
/// World: stepping, readers, inputs (bind_world.cc).
void bindWorld(py::module_& m);
/// Many worlds stepped in parallel with the GIL released (bind_batch.cc).
void bindBatch(py::module_& m);

}  // namespace python
}  // namespace cga_rigid_sim
