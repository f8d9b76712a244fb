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
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/world.h"
#include "world_options.h"

namespace py = pybind11;

namespace cga_rigid_sim {
namespace python {
namespace {

using Array = py::array_t<double, py::array::c_style>;

template <class T>
T orRaise(Result<T> r) {
  if (!r.ok()) throw py::value_error(r.error());
  return std::move(r).value();
}

Eigen::Vector3d vector3(const py::handle& h, const char* what) {
  const std::vector<double> v = py::cast<std::vector<double>>(h);
  if (v.size() != 3)
    throw py::value_error(std::string(what) + ": expected 3 numbers, got " +
                          std::to_string(v.size()));
  return {v[0], v[1], v[2]};
}

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

// Row k of an (n, 3) array: the vector v.
void setRow(Array& a, py::ssize_t k, const Eigen::Vector3d& v) {
  std::copy(v.data(), v.data() + 3, a.mutable_data() + 3 * k);
}

// One world and what Python needs beside it.
class PyWorld {
 public:
  PyWorld(std::unique_ptr<sim::World> w) : world_(std::move(w)) {}
  sim::World& world() { return *world_; }
  const sim::World& world() const { return *world_; }

  int movingCount() const { return static_cast<int>(world_->model().moving.size()); }

  std::vector<std::string> bodyNames() const {
    std::vector<std::string> out;
    const sim::Model& m = world_->model();
    for (std::size_t i = 0; i < m.moving.size(); ++i)
      out.push_back(m.bodyOf(static_cast<int>(i)).name);
    return out;
  }

  // Root-link poses [x y z qw qx qy qz] of every moving body into out (n × 7).
  void posesInto(double* out) const {
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

  Array poses() const {
    Array a({movingCount(), 7});
    posesInto(a.mutable_data());
    return a;
  }

  // An (n, width) array, row i filled from moving body i's state by fill(state, row).
  template <class Fill>
  Array perBody(py::ssize_t width, Fill&& fill) const {
    const sim::Data& d = world_->data();
    Array a({py::ssize_t(movingCount()), width});
    for (std::size_t i = 0; i < d.bodies.size(); ++i)
      fill(d.bodies[i].state, a.mutable_data() + width * static_cast<py::ssize_t>(i));
    return a;
  }

  Array com() const {
    const double lambda = world_->model().lambda;
    return perBody(3, [lambda](const dynamics::BodyState& s, double* row) {
      const Eigen::Vector3d x = dynamics::comPosition_W(s, lambda);
      std::copy(x.data(), x.data() + 3, row);
    });
  }

  Array velocities() const {
    const double lambda = world_->model().lambda;
    return perBody(6, [lambda](const dynamics::BodyState& s, double* row) {
      const Eigen::Vector3d v = dynamics::comVelocity_W(s, lambda);
      const Eigen::Vector3d w = dynamics::angularVelocity_W(s);
      std::copy(v.data(), v.data() + 3, row);
      std::copy(w.data(), w.data() + 3, row + 3);
    });
  }

  Array motors() const {
    return perBody(8, [](const dynamics::BodyState& s, double* row) {
      const auto c = s.M_WB.coefficients();
      std::copy(c.begin(), c.end(), row);
    });
  }

  Array bivelocities() const {
    return perBody(6, [](const dynamics::BodyState& s, double* row) {
      const auto c = s.omega_B.coefficients();
      std::copy(c.begin(), c.end(), row);
    });
  }

  py::dict momentum() const {
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

  py::dict contacts() const {
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
                    py::arg("body_b") = body_b, py::arg("link_b") = link_b,
                    py::arg("point") = point, py::arg("normal") = normal, py::arg("depth") = depth,
                    py::arg("normal_impulse") = impulse, py::arg("friction_impulse") = friction);
  }

  py::dict jointStates() const {
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

 private:
  std::unique_ptr<sim::World> world_;
};

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

// Steps every world of `worlds` by `steps`, `threads` at a time (0 = the cores available).
// Each world is stepped by one thread from start to end, so its states are the ones a plain
// loop over the worlds gives, bit for bit; the order in which threads take worlds changes no
// result.
template <class PerWorld>
void forWorlds(std::size_t count, int threads, PerWorld&& f) {
  int t = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  t = std::max(1, std::min<int>(t, static_cast<int>(count)));
  if (t == 1) {
    for (std::size_t k = 0; k < count; ++k) f(k);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> pool;
  for (int i = 0; i < t; ++i)
    pool.emplace_back([&] {
      for (std::size_t k = next++; k < count; k = next++) f(k);
    });
  for (std::thread& th : pool) th.join();
}

bool finiteState(const sim::World& w) {
  for (const sim::MovingBodyData& b : w.data().bodies)
    if (!b.state.allFinite()) return false;
  return true;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "cga_rigid_sim core: worlds loaded from URDF, stepped from Python (doc/python.md)";

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

  m.def(
      "step_worlds",
      [](const std::vector<PyWorld*>& worlds, std::uint64_t n, int threads) {
        py::gil_scoped_release release;
        forWorlds(worlds.size(), threads, [&](std::size_t k) { worlds[k]->world().step(n); });
      },
      py::arg("worlds"), py::arg("n") = 1, py::arg("threads") = 0,
      "Steps each world n steps, worlds in parallel on `threads` threads (0: the cores), the "
      "GIL released; the same states as stepping them one by one.");

  m.def(
      "rollout_worlds",
      [](const std::vector<PyWorld*>& worlds, const std::vector<std::int64_t>& increments,
         int threads) {
        for (std::size_t s = 0; s < increments.size(); ++s)
          if (increments[s] < 0)
            throw py::value_error("increments[" + std::to_string(s) + "]: must be >= 0 steps");
        const py::ssize_t W = static_cast<py::ssize_t>(worlds.size());
        const py::ssize_t S = static_cast<py::ssize_t>(increments.size());
        py::ssize_t B = 0;
        for (PyWorld* w : worlds) B = std::max<py::ssize_t>(B, w->movingCount());
        Array out({W, S + 1, B, py::ssize_t(7)});
        py::array_t<bool> ok(W);
        std::fill(out.mutable_data(), out.mutable_data() + out.size(),
                  std::numeric_limits<double>::quiet_NaN());
        double* base = out.mutable_data();
        bool* okp = ok.mutable_data();
        {
          py::gil_scoped_release release;
          forWorlds(worlds.size(), threads, [&](std::size_t k) {
            PyWorld& w = *worlds[k];
            double* dst = base + k * (S + 1) * B * 7;
            w.posesInto(dst);
            bool finite = true;
            for (py::ssize_t s = 0; s < S && finite; ++s) {
              w.world().step(static_cast<std::uint64_t>(increments[s]));
              finite = finiteState(w.world());
              if (finite) w.posesInto(dst + (s + 1) * B * 7);
            }
            okp[k] = finite;
          });
        }
        return py::make_tuple(out, ok);
      },
      py::arg("worlds"), py::arg("increments"), py::arg("threads") = 0,
      "Steps each world through the samples: increments[s] steps before sample s + 1, "
      "recording its root-link poses at each: returns (poses (W, S + 1, bodies, 7), ok (W,)), "
      "sample 0 the state before; a world whose state became non-finite stops there, its later "
      "samples NaN, ok False. Worlds in parallel, the GIL released.");
}

}  // namespace python
}  // namespace cga_rigid_sim
