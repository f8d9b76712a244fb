// The Python module cga_rigid_sim._core (pybind11): the core's World from Python, and a batch of
// independent worlds stepped in parallel with the GIL released (doc/python.md).
//
// Arrays: every reader fills one numpy array for all bodies (row i = moving body i in scene
// order), so reading n bodies makes one allocation, not one object per body. Poses are the root
// link's frame in the world as [x, y, z, qw, qx, qy, qz] (w first, as MuJoCo and the cube-toss
// CSV files write it); velocities are the centre of mass's and the angular velocity, world axes.
//
// Errors: a refusal of the core (an Error naming input, field and rule; result.h) is raised as
// ValueError with the core's message; nothing in the world has changed then.
//
// One file per bound concept, each with its bind… function (bindings.h): bind_scene.cc (Scene
// and the URDF loaders), bind_world.cc (World and its readers, py_world.h) and bind_batch.cc
// (many worlds stepped in parallel, the rollouts the fitting tools run).
#include <pybind11/pybind11.h>

#include "bindings.h"

namespace cga_rigid_sim {
namespace python {

PYBIND11_MODULE(_core, m) {
  m.doc() = "cga_rigid_sim core: worlds loaded from URDF, stepped from Python (doc/python.md)";
  bindScene(m);
  bindWorld(m);
  bindBatch(m);
}

}  // namespace python
}  // namespace cga_rigid_sim
