// PyWorld's readers (py_world.h): the World's state, momentum, contacts and joint states as
// numpy arrays, one array per quantity for all moving bodies (doc/python.md).
#include "py_world.h"

#include <algorithm>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace python {
namespace {

// Row k of an (n, 3) array: the vector v.
void setRow(Array& a, py::ssize_t k, const Eigen::Vector3d& v) {
  std::copy(v.data(), v.data() + 3, a.mutable_data() + 3 * k);
}

}  // namespace

std::vector<std::string> PyWorld::bodyNames() const {
  std::vector<std::string> out;
  const sim::Model& m = world_->model();
  for (std::size_t i = 0; i < m.moving.size(); ++i)
    out.push_back(m.bodyOf(static_cast<int>(i)).name);
  return out;
}

void PyWorld::posesInto(double* out) const {
  const sim::Data& d = world_->data();
  const sim::Model& m = world_->model();
  for (std::size_t i = 0; i < d.bodies.size(); ++i) {
    const cga::Motor M_WL =
        d.bodies[i].state.M_WB * m.bodyOf(static_cast<int>(i)).links.front().M_BL;
    const Eigen::Vector3d x = M_WL.translation(m.lambda);
    const Eigen::Quaterniond& q = M_WL.rotation();
    double* row = out + 7 * i;
    row[0] = x.x(), row[1] = x.y(), row[2] = x.z();
    row[3] = q.w(), row[4] = q.x(), row[5] = q.y(), row[6] = q.z();
  }
}

Array PyWorld::poses() const {
  Array a({movingCount(), 7});
  posesInto(a.mutable_data());
  return a;
}

template <class Fill>
Array PyWorld::perBody(py::ssize_t width, Fill&& fill) const {
  const sim::Data& d = world_->data();
  Array a({py::ssize_t(movingCount()), width});
  for (std::size_t i = 0; i < d.bodies.size(); ++i)
    fill(d.bodies[i].state, a.mutable_data() + width * static_cast<py::ssize_t>(i));
  return a;
}

Array PyWorld::com() const {
  const double lambda = world_->model().lambda;
  return perBody(3, [lambda](const dynamics::BodyState& s, double* row) {
    const Eigen::Vector3d x = dynamics::comPosition_W(s, lambda);
    std::copy(x.data(), x.data() + 3, row);
  });
}

Array PyWorld::velocities() const {
  const double lambda = world_->model().lambda;
  return perBody(6, [lambda](const dynamics::BodyState& s, double* row) {
    const Eigen::Vector3d v = dynamics::comVelocity_W(s, lambda);
    const Eigen::Vector3d w = dynamics::angularVelocity_W(s);
    std::copy(v.data(), v.data() + 3, row);
    std::copy(w.data(), w.data() + 3, row + 3);
  });
}

Array PyWorld::motors() const {
  return perBody(8, [](const dynamics::BodyState& s, double* row) {
    const auto c = s.M_WB.coefficients();
    std::copy(c.begin(), c.end(), row);
  });
}

Array PyWorld::bivelocities() const {
  return perBody(6, [](const dynamics::BodyState& s, double* row) {
    const auto c = s.omega_B.coefficients();
    std::copy(c.begin(), c.end(), row);
  });
}

py::dict PyWorld::momentum() const {
  const std::vector<sim::MomentumReport> r = world_->momentum();
  const py::ssize_t n = static_cast<py::ssize_t>(r.size());
  Array linear({n, py::ssize_t(3)}), angular({n, py::ssize_t(3)}), origin({n, py::ssize_t(3)}),
      kinetic(n), potential(n);
  std::vector<std::string> names;
  for (py::ssize_t k = 0; k < n; ++k) {
    const sim::MomentumReport& m = r[k];
    names.push_back(m.body);
    setRow(linear, k, m.linear);
    setRow(angular, k, m.angular);
    setRow(origin, k, m.angular_origin);
    kinetic.mutable_data()[k] = m.kinetic_energy;
    potential.mutable_data()[k] = m.potential_energy;
  }
  return py::dict(py::arg("names") = names, py::arg("linear") = linear,
                  py::arg("angular") = angular, py::arg("angular_origin") = origin,
                  py::arg("kinetic_energy") = kinetic, py::arg("potential_energy") = potential,
                  py::arg("dissipated_energy") = r.back().dissipated_energy);
}

py::dict PyWorld::contacts() const {
  const std::vector<sim::ContactReport> r = world_->contacts();
  const py::ssize_t n = static_cast<py::ssize_t>(r.size());
  Array point({n, py::ssize_t(3)}), normal({n, py::ssize_t(3)}), friction({n, py::ssize_t(3)}),
      depth(n), impulse(n);
  std::vector<std::string> body_a, link_a, body_b, link_b;
  for (py::ssize_t k = 0; k < n; ++k) {
    const sim::ContactReport& c = r[k];
    body_a.push_back(c.body_a), link_a.push_back(c.link_a);
    body_b.push_back(c.body_b), link_b.push_back(c.link_b);
    setRow(point, k, c.point);
    setRow(normal, k, c.normal);
    setRow(friction, k, c.friction_impulse);
    depth.mutable_data()[k] = c.depth;
    impulse.mutable_data()[k] = c.normal_impulse;
  }
  return py::dict(py::arg("body_a") = body_a, py::arg("link_a") = link_a,
                  py::arg("body_b") = body_b, py::arg("link_b") = link_b, py::arg("point") = point,
                  py::arg("normal") = normal, py::arg("depth") = depth,
                  py::arg("normal_impulse") = impulse, py::arg("friction_impulse") = friction);
}

py::dict PyWorld::jointStates() const {
  const std::vector<sim::JointStateReport> r = world_->jointStates();
  const py::ssize_t n = static_cast<py::ssize_t>(r.size());
  Array position(n), velocity(n), effort(n);
  std::vector<std::string> names;
  for (py::ssize_t k = 0; k < n; ++k) {
    names.push_back(r[k].name);
    position.mutable_data()[k] = r[k].position;
    velocity.mutable_data()[k] = r[k].velocity;
    effort.mutable_data()[k] = r[k].effort;
  }
  return py::dict(py::arg("names") = names, py::arg("position") = position,
                  py::arg("velocity") = velocity, py::arg("effort") = effort);
}

bool finiteState(const sim::World& w) {
  for (const sim::MovingBodyData& b : w.data().bodies)
    if (!b.state.allFinite()) return false;
  return true;
}

}  // namespace python
}  // namespace cga_rigid_sim
