// World in Python (doc/python.md): made from a Scene and keyword options (world_options.h),
// stepped with the GIL released, read into numpy arrays (py_world.h), and driven by wrenches,
// impulses, body states and joint efforts.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "bindings.h"
#include "py_world.h"
#include "world_options.h"

namespace cga_rigid_sim {
namespace python {
namespace {

Eigen::Isometry3d poseFrom(const py::object& position, const py::object& orientation_wxyz) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = vector3(position, "position");
  const std::vector<double> q = py::cast<std::vector<double>>(orientation_wxyz);
  if (q.size() != 4)
    throw py::value_error("orientation: expected 4 numbers [qw, qx, qy, qz], got " +
                          std::to_string(q.size()));
  const Eigen::Quaterniond Q(q[0], q[1], q[2], q[3]);
  const double norm = Q.norm();
  if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3)
    throw py::value_error("orientation: not a unit quaternion (|q| = " + std::to_string(norm) +
                          ", 1 within 1e-3 expected)");
  T.linear() = Q.normalized().toRotationMatrix();
  return T;
}

}  // namespace

void bindWorld(py::module_& m) {
  py::class_<PyWorld>(m, "World", "One simulated world (sim::World); see doc/python.md.")
      .def(py::init([](const scene::Scene& scene, const py::kwargs& options) {
             scene::Scene copy = scene;
             const sim::WorldConfig config = worldConfig(options, copy);
             return PyWorld(orRaise(sim::World::create(std::move(copy), config)));
           }),
           py::arg("scene"),
           "World(scene, **options): a world of `scene`; options dt, integrator, gravity, "
           "ground_plane, contact_mu, contact_restitution, contact_sleeping, contact_model, "
           "threads, world_frame, max_force, max_impulse (doc/python.md).")
      .def_property_readonly("time", [](const PyWorld& w) { return w.world().time(); })
      .def_property_readonly("step_count", [](const PyWorld& w) { return w.world().stepCount(); })
      .def_property_readonly("dt", [](const PyWorld& w) { return w.world().config().dt; })
      .def_property_readonly("body_names", &PyWorld::bodyNames)
      .def(
          "step",
          [](PyWorld& w, std::uint64_t n) {
            py::gil_scoped_release release;
            w.world().step(n);
          },
          py::arg("n") = 1, "Advances n steps (the GIL is released meanwhile).")
      .def("poses", &PyWorld::poses,
           "(n, 7): per moving body its root link's [x, y, z, qw, qx, qy, qz], world.")
      .def("com", &PyWorld::com, "(n, 3): centres of mass, world, m.")
      .def("velocities", &PyWorld::velocities,
           "(n, 6): per body [vx, vy, vz, wx, wy, wz]: centre-of-mass and angular velocity, "
           "world axes.")
      .def("motors", &PyWorld::motors,
           "(n, 8): M_WB's blade coefficients 1, e23, e31, e12, e1n, e2n, e3n, e123n.")
      .def("bivelocities", &PyWorld::bivelocities,
           "(n, 6): Ω_B's blade coefficients e23, e31, e12, e1n, e2n, e3n (body axes).")
      .def("momentum", &PyWorld::momentum,
           "Per body, per tree, then 'total': linear, angular (about the CoM), "
           "angular_origin (k, 3); kinetic_energy, potential_energy (k,); dissipated_energy.")
      .def("contacts", &PyWorld::contacts,
           "The contacts of the last step: names, point, normal (k, 3), depth, "
           "normal_impulse (k,), friction_impulse (k, 3).")
      .def("joint_states", &PyWorld::jointStates)
      .def(
          "apply_wrench",
          [](PyWorld& w, const std::string& body, const py::object& force, const py::object& point,
             const py::object& couple, const std::string& frame, double start_time, double duration,
             double alpha) {
            sim::WrenchInput in;
            in.body = body;
            in.frame = frame;
            in.F = cga::Force(vector3(force, "force"), alpha);
            in.point = vector3(point, "point");
            in.couple = vector3(couple, "couple");
            in.start_time = start_time;
            in.duration = duration;
            orRaise(w.world().applyWrench(in));
          },
          py::arg("body"), py::arg("force"), py::arg("point") = std::vector<double>{0, 0, 0},
          py::arg("couple") = std::vector<double>{0, 0, 0}, py::arg("frame") = "",
          py::arg("start_time") = 0.0, py::arg("duration") = 0.0, py::arg("alpha") = 0.0,
          "A wrench F = f + αn at `point` with a couple, in `frame` (world or a link), for "
          "`duration` s from `start_time` (0: one step, the next).")
      .def(
          "apply_impulse",
          [](PyWorld& w, const std::string& body, const py::object& impulse,
             const py::object& point, const py::object& angular, const std::string& frame,
             double start_time, double alpha) {
            sim::ImpulseInput in;
            in.body = body;
            in.frame = frame;
            in.J = cga::Force(vector3(impulse, "impulse"), alpha);
            in.point = vector3(point, "point");
            in.angular = vector3(angular, "angular");
            in.start_time = start_time;
            orRaise(w.world().applyImpulse(in));
          },
          py::arg("body"), py::arg("impulse"), py::arg("point") = std::vector<double>{0, 0, 0},
          py::arg("angular") = std::vector<double>{0, 0, 0}, py::arg("frame") = "",
          py::arg("start_time") = 0.0, py::arg("alpha") = 0.0)
      .def(
          "set_body_state",
          [](PyWorld& w, const std::string& body, const py::object& position,
             const py::object& orientation, const py::object& linear_velocity,
             const py::object& angular_velocity) {
            orRaise(w.world().setBodyState(body, poseFrom(position, orientation),
                                           vector3(linear_velocity, "linear_velocity"),
                                           vector3(angular_velocity, "angular_velocity")));
          },
          py::arg("body"), py::arg("position"), py::arg("orientation"),
          py::arg("linear_velocity") = std::vector<double>{0, 0, 0},
          py::arg("angular_velocity") = std::vector<double>{0, 0, 0},
          "Root link pose (orientation [qw, qx, qy, qz]) and the CoM's and angular velocity "
          "(world axes).")
      .def(
          "set_joint_efforts",
          [](PyWorld& w, const std::vector<std::string>& names, const std::vector<double>& efforts,
             double stamp) {
            sim::JointEffortInput in;
            in.names = names;
            in.efforts = efforts;
            in.stamp = stamp;
            orRaise(w.world().setJointEfforts(in));
          },
          py::arg("names"), py::arg("efforts"), py::arg("stamp") = 0.0)
      .def("clear_wrenches", [](PyWorld& w) { w.world().clearWrenches(); })
      .def("reset", [](PyWorld& w) { w.world().reset(); })
      .def("summary", [](const PyWorld& w) { return w.world().summary(); })
      .def(
          "is_finite", [](const PyWorld& w) { return finiteState(w.world()); },
          "Every moving body's state is finite.");
}

}  // namespace python
}  // namespace cga_rigid_sim
