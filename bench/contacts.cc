// bench_contacts: our side of the contact benchmark (doc/benchmarks-contacts.md).
//
// Every case of bench/cases/contact_cases.h is built as a sim::World: each body a moving
// scene::BodyModel (solid sphere or cube: mass, isotropic principal moments, the case's centre
// and velocity, unrotated) with one CollisionShape (sphere or box) at its centre; the ground is
// WorldConfig::ground_plane (z = 0); the case's μ and e are WorldConfig::contact_mu and
// contact_restitution, which every surface (ground, bodies, walls) takes because none sets its
// own, so every pair has exactly μ and e; gravity is the case's (the incline tilts it); the
// pile's open bin is one static body with four box shapes (the walls, placed as the peers place
// them). One thread (WorldConfig::threads = 1).
//
// The sweep, the timing protocol and the CSV are the peers' (bench/peers/contact_common.h,
// compiled in, no peer engine linked): median over 3 fresh runs of the wall time of
// world->step(N) without read-back, errors from a separate run that reads bodyStates() after
// every step, pile1000 once at 1 ms. Output: bench/out/contacts_cga_rigid_sim.csv and
// cpu_contacts_cga_rigid_sim.csv; config = the integrator (--configs, default `auto`; any name
// of dynamics::integratorNames()).
//
// With --robots, the real robots of bench/peers/robot_cases.h instead (driver
// bench/peers/robot_common.h): each URDF loaded by scene::loadUrdfFile (default SceneOptions),
// in a sim::World with WorldConfig dt = the case's h, integrator `auto`, one thread, and for a
// contact case the ground plane at the case's height, μ 0.5 and e 0 (the defaults) and
// self_collision `auto`; for a case without contacts every collision shape dropped. Configs:
// `auto` (the defaults, contact sleeping on) and, for contact cases, `auto_awake` (contact
// sleeping off: every body in contact solved every step, as the peers do). The pairs our World
// lets collide are written to bench/out/robot_pairs_<case>.txt for the peers' `our_pairs`.
// --starts K --start-shift DZ (the driver's, the same in the peers): start k of a contact case
// lowers the plane by k·DZ, so that K landings are averaged instead of one chaotic one; the
// observations of a start include whether the robot sleeps at a phase's end (every tree
// asleep: `auto` only, `auto_awake` never sleeps and is the config to set against the peers,
// which do not sleep either).
// Output: bench/out/robots_cga_rigid_sim.csv, with K > 1 also robots_cga_rigid_sim_starts.csv.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/body/integrator.h"
#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/motor.h"
#include "cga_rigid_sim/contact/contact.h"
#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/world.h"
#include "contact_common.h"
#include "robot_common.h"

namespace cga_rigid_sim {
namespace benchmark {
namespace {

using ::bench::contacts::BodyObs;
using ::bench::contacts::BodySpec;
using ::bench::contacts::ContactCase;
using ::bench::contacts::Shape;

constexpr double kLambda = 1.0;

Eigen::Vector3d vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

scene::CollisionShape boxShape(const std::string& name, const Eigen::Vector3d& size,
                               const Eigen::Vector3d& centre_B) {
  scene::CollisionShape s;
  s.kind = scene::CollisionShape::Kind::kBox;
  s.size = size;
  s.M_BS = cga::Motor::fromPose(Eigen::Quaterniond::Identity(), centre_B, kLambda);
  s.name = name;
  return s;
}

scene::BodyModel movingBody(const std::string& name, const BodySpec& b) {
  scene::BodyModel m;
  m.name = name;
  const double J = b.inertia();
  auto I = dynamics::Inertia::fromPrincipal(name, b.mass, {J, J, J});
  if (!I.ok()) {
    std::fprintf(stderr, "bench_contacts: %s\n", I.error().c_str());
    std::exit(2);
  }
  m.inertia = *I;
  m.links.push_back({name, cga::Motor::identity()});
  m.M_WB0 = cga::Motor::fromPose(Eigen::Quaterniond::Identity(), vec(b.x0), kLambda);
  // Unrotated: body axes = world axes, so v_B = v_W.
  m.omega_B0 = cga::Bivelocity::fromVelocities(Eigen::Vector3d::Zero(), vec(b.v0), kLambda);
  if (b.shape == Shape::Sphere) {
    scene::CollisionShape s;
    s.kind = scene::CollisionShape::Kind::kSphere;
    s.radius = b.size;
    s.name = name + "#0";
    m.shapes.push_back(s);
  } else {
    m.shapes.push_back(boxShape(name + "#0", Eigen::Vector3d::Constant(2 * b.size), {0, 0, 0}));
  }
  return m;
}

// The open bin's walls: inner faces at |x|, |y| = half_width, from z = 0 to wall_height.
scene::BodyModel binWalls(const ::bench::contacts::Bin& bin) {
  scene::BodyModel m;
  m.name = "bin";
  m.is_static = true;
  m.links.push_back({"bin", cga::Motor::identity()});
  m.M_WB0 = cga::Motor::identity();
  const double w = bin.half_width, t = bin.wall_thickness, hz = bin.wall_height;
  const double o = w + 0.5 * t, l = 2 * (w + t);
  m.shapes.push_back(boxShape("bin#x+", {t, l, hz}, {o, 0, 0.5 * hz}));
  m.shapes.push_back(boxShape("bin#x-", {t, l, hz}, {-o, 0, 0.5 * hz}));
  m.shapes.push_back(boxShape("bin#y+", {l, t, hz}, {0, o, 0.5 * hz}));
  m.shapes.push_back(boxShape("bin#y-", {l, t, hz}, {0, -o, 0.5 * hz}));
  return m;
}

class CgaContactSim : public ::bench::contacts::ContactSim {
 public:
  CgaContactSim(const ContactCase& c, double h, const std::string& integrator) {
    scene::Scene s;
    s.source = "bench_contacts";
    s.robot_name = c.name;
    s.lambda = kLambda;
    s.gravity_W = vec(c.gravity);
    for (size_t i = 0; i < c.bodies.size(); ++i)
      s.bodies.push_back(movingBody("b" + std::to_string(i), c.bodies[i]));
    if (c.bin.present) s.bodies.push_back(binWalls(c.bin));
    sim::WorldConfig config;
    config.dt = h;
    config.integrator = integrator;
    config.threads = 1;
    config.ground_plane = sim::GroundPlane{};  // z = 0, surface parameters unset
    config.contact_mu = c.mu;
    config.contact_restitution = c.e;
    auto w = sim::World::create(std::move(s), config);
    if (!w.ok()) {
      std::fprintf(stderr, "bench_contacts: %s: %s\n", c.name.c_str(), w.error().c_str());
      std::exit(2);
    }
    world_ = std::move(w.value());
  }
  void step(long n) override { world_->step(static_cast<std::uint64_t>(n)); }
  // Read after the error run only (never in a timed run): the size of the problem at the end.
  std::string events() override {
    return "contacts in the last step " + std::to_string(world_->contacts().size());
  }
  // bodyStates(): the moving bodies in scene order = the order of ContactCase::bodies.
  void observe(std::vector<BodyObs>* out) override {
    const std::vector<sim::BodyStateReport> states = world_->bodyStates();
    out->resize(states.size());
    for (size_t i = 0; i < states.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        (*out)[i].x[k] = states[i].com[k];
        (*out)[i].v[k] = states[i].linear_velocity[k];
        (*out)[i].w[k] = states[i].angular_velocity[k];
      }
  }

 private:
  std::unique_ptr<sim::World> world_;
};

// A real robot (bench/peers/robot_cases.h) in a World; see the header comment.
class CgaRobotSim : public ::bench::robots::RobotSim {
 public:
  CgaRobotSim(const ::bench::robots::RobotCase& c, const ::bench::robots::PreparedRobot& p,
              bool sleeping, const std::string& integrator)
      : root_(c.root_link) {
    Result<scene::Scene> loaded = scene::loadUrdfFile(p.urdf, scene::SceneOptions());
    if (!loaded) throw std::runtime_error("loading " + p.urdf + ": " + loaded.error());
    scene::Scene s = std::move(loaded).value();
    if (!c.contacts)
      for (scene::BodyModel& b : s.bodies) b.shapes.clear();
    sim::WorldConfig config;
    config.dt = c.h;
    config.integrator = integrator;
    config.threads = 1;
    config.contact_sleeping = sleeping;
    if (c.contacts) config.ground_plane = sim::GroundPlane{c.ground_z, {}};
    auto w = sim::World::create(std::move(s), config);
    if (!w) throw std::runtime_error("World::create: " + w.error());
    world_ = std::move(w).value();
    if (c.contacts) {
      std::ofstream pairs(::bench::robots::pairsFile(p, c));
      for (const auto& [a, b] : world_->selfCollisionPairs()) pairs << a << " " << b << "\n";
    }
    e0_ = energy();
  }
  void step(long n) override { world_->step(static_cast<std::uint64_t>(n)); }
  ::bench::robots::RobotObs observe() override {
    ::bench::robots::RobotObs o;
    const std::vector<sim::MomentumReport> m = world_->momentum();
    o.kinetic = m.back().kinetic_energy;
    if (!root_.empty()) {
      Result<sim::BodyStateReport> r = world_->getBodyState(root_);
      if (r) o.root_z = r->pose_root.translation().z();
    }
    const std::vector<sim::ContactReport> contacts = world_->contacts();
    o.contacts = static_cast<int>(contacts.size());
    double depth = 0;
    std::string deepest;
    int self = 0;
    for (const sim::ContactReport& k : contacts) {
      if (k.body_b != sim::kGroundPlaneName) ++self;
      if (k.depth > depth) depth = k.depth, deepest = k.link_a + "/" + k.link_b;
    }
    o.max_depth = depth;
    o.energy = energy() - e0_;
    // Every tree asleep (one robot: one tree); data().trees is read outside the timed steps.
    const std::vector<sim::TreeData>& trees = world_->data().trees;
    o.asleep = !trees.empty() && std::all_of(trees.begin(), trees.end(),
                                             [](const sim::TreeData& t) { return t.asleep; });
    char b[300];
    std::snprintf(b, sizeof b,
                  "self %d; max depth %.3g m (%s); energy balance %.3g J (dissipated %.4g J)", self,
                  depth, deepest.c_str(), o.energy, m.back().dissipated_energy);
    o.note = b;
    if (world_->treeFaultCount() > 0)
      o.note += "; " + std::to_string(world_->treeFaultCount()) +
                " tree faults: " + world_->lastTreeFault()->message().substr(0, 400);
    return o;
  }

 private:
  // Kinetic + potential + dissipated: constant but for the work of inputs (none here).
  double energy() const {
    const sim::MomentumReport t = world_->momentum().back();
    return t.kinetic_energy + t.potential_energy + t.dissipated_energy;
  }
  std::unique_ptr<sim::World> world_;
  std::string root_;
  double e0_ = 0;
};

}  // namespace
}  // namespace benchmark
}  // namespace cga_rigid_sim

int main(int argc, char** argv) {
  using cga_rigid_sim::benchmark::CgaContactSim;
  if (bench::robots::robotsRequested(argc, argv)) {
    using cga_rigid_sim::benchmark::CgaRobotSim;
    auto make = [](bool sleeping, const std::string& integrator) {
      return
          [sleeping, integrator](
              const bench::robots::RobotCase& c,
              const bench::robots::PreparedRobot& p) -> std::unique_ptr<bench::robots::RobotSim> {
            return std::make_unique<CgaRobotSim>(c, p, sleeping, integrator);
          };
    };
    std::vector<bench::robots::RobotConfig> robot_configs = {
        {"auto", make(true, "auto")},
        {"auto_awake", make(false, "auto"),
         [](const bench::robots::RobotCase& c) { return c.contacts; }},
        {"euler", make(true, "euler")},
    };
    return bench::robots::runRobotSweep("cga_rigid_sim", "cga_rigid_sim (this build)",
                                        robot_configs, argc, argv);
  }
  // One config per integrator; without --configs only `auto` runs (the default integrator).
  bool configs_given = false;
  for (int i = 1; i < argc; ++i)
    configs_given = configs_given || std::strcmp(argv[i], "--configs") == 0;
  std::vector<bench::contacts::ContactConfig> configs;
  for (const std::string& name : cga_rigid_sim::dynamics::integratorNames()) {
    if (!configs_given && name != "auto") continue;
    configs.push_back({name,
                       [name](const bench::contacts::ContactCase& c,
                              double h) -> std::unique_ptr<bench::contacts::ContactSim> {
                         return std::make_unique<CgaContactSim>(c, h, name);
                       },
                       {},
                       ""});
  }
  return bench::contacts::runContactSweep("cga_rigid_sim", "cga_rigid_sim (this build)", configs,
                                          argc, argv);
}
