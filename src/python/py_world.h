// Internal to the Python module: PyWorld, one sim::World as Python holds it, and its readers,
// each filling one numpy array for all moving bodies (module.cc says the layout).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "bindings.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace python {

// One world and what Python needs beside it.
class PyWorld {
 public:
  PyWorld(std::unique_ptr<sim::World> w) : world_(std::move(w)) {}
  sim::World& world() { return *world_; }
  const sim::World& world() const { return *world_; }

  int movingCount() const { return static_cast<int>(world_->model().moving.size()); }

  std::vector<std::string> bodyNames() const;

  // Root-link poses [x y z qw qx qy qz] of every moving body into out (n × 7).
  void posesInto(double* out) const;

  Array poses() const;
  Array com() const;
  Array velocities() const;
  Array motors() const;
  Array bivelocities() const;
  py::dict momentum() const;
  py::dict contacts() const;
  py::dict jointStates() const;

 private:
  // An (n, width) array, row i filled from moving body i's state by fill(state, row).
  template <class Fill>
  Array perBody(py::ssize_t width, Fill&& fill) const;

  std::unique_ptr<sim::World> world_;
};

/// Every moving body's state is finite.
bool finiteState(const sim::World& w);

}  // namespace python
}  // namespace cga_rigid_sim
