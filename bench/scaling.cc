// bench_scaling: cost per body-step against the number of free bodies.
//
// N free asymmetric boxes (random half-sizes in [0.05, 0.5] m, masses in [0.5, 5] kg, random
// attitudes, spins of 1–10 rad/s about random axes, CoM velocities of ~1 m/s; no gravity, no
// contacts; fixed seed) are advanced at dt = 1 ms by one integrator (auto, cga2, cga4) in two
// ways:
//   world     sim::World::step() on a scene::Scene built in code (what the node runs: per-body
//             loads, the at-rest test, one integrator object per body);
//   dynamics  the bare loop over contiguous arrays of Inertia and BodyState with one integrator
//             object per body and one shared (empty) Loads — the floor the World can reach.
// The integrators are warmed up (two steps, which build per-body caches), then `steps` steps
// are timed, steps = max(5, ⌈body_steps / N⌉); the median over --reps repetitions is reported.
// ns per body-step rising with N shows the working set leaving the caches (a body's state,
// inertia and integrator object take a few hundred bytes to a kilobyte).
//
// CSV (bench/out/scaling.csv): layer,integrator,n_bodies,steps,ns_per_body_step,ms_per_step,
// real_time_factor,cpu_ns_per_body_step,threads,read_every — real_time_factor is dt over the
// wall time of one step (≥ 1: real time); cpu_ns_per_body_step is the calling thread's CPU time
// per body-step (with several threads, only its own share); threads is WorldConfig::threads;
// read_every the steps between reads of every state (world layer; 0 never; the dynamics layer
// has every state current after every step: 1); bytes_per_body the heap the layer holds per
// body after the timing (everything it allocated — states, integrators and their caches, the
// World's copy of the scene — from before its scene was built, divided by N).

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_clock.h"
#include "cga_rigid_sim/body/integrator.h"
#include "cga_rigid_sim/cga/motor.h"
#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/sim/world.h"
#include "peers/sweep_util.h"

namespace cga_rigid_sim {
namespace benchmark {
namespace {

// One free body as generated: inertia (principal frame B) and initial state.
struct Body {
  std::string name;
  dynamics::Inertia inertia;
  cga::Motor M_BL;  // the box's own frame in B
  dynamics::BodyState state0;
};

std::vector<Body> makeBodies(int n, double lambda, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> half(0.05, 0.5), mass(0.5, 5.0), spin(1.0, 10.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const int side = static_cast<int>(std::ceil(std::cbrt(double(n))));
  std::vector<Body> bodies;
  bodies.reserve(n);
  for (int i = 0; i < n; ++i) {
    const double a = half(rng), b = half(rng), c = half(rng), m = mass(rng);
    const Eigen::Vector3d J_L(m / 3 * (b * b + c * c), m / 3 * (a * a + c * c),
                              m / 3 * (a * a + b * b));
    const std::string name = "box_" + std::to_string(i);
    auto inertia = dynamics::Inertia::fromPrincipal(name, m, J_L);
    if (!inertia) {
      std::fprintf(stderr, "%s\n", inertia.error().c_str());
      std::exit(2);
    }
    // Attitude of the box frame L: a uniform random rotation; B = L turned by R_LB.
    Eigen::Quaterniond R_WL(gauss(rng), gauss(rng), gauss(rng), gauss(rng));
    R_WL.normalize();
    const Eigen::Quaterniond R_LB = inertia->rotationFromPrincipal();
    const Eigen::Vector3d x_W(2.0 * (i % side), 2.0 * ((i / side) % side),
                              2.0 * (i / (side * side)));
    const Eigen::Vector3d w_B =
        spin(rng) * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const Eigen::Vector3d v_B(gauss(rng), gauss(rng), gauss(rng));
    dynamics::BodyState s;
    s.M_WB = cga::Motor::fromPose(R_WL * R_LB, x_W, lambda);
    s.omega_B = cga::Bivelocity::fromVelocities(w_B, v_B, lambda);
    bodies.push_back({name, *inertia, cga::Motor::rotor(R_LB.conjugate()), s});
  }
  return bodies;
}

scene::Scene makeScene(const std::vector<Body>& bodies, double lambda) {
  scene::Scene sc;
  sc.source = "bench_scaling";
  sc.robot_name = "scaling";
  sc.lambda = lambda;
  sc.gravity_W = Eigen::Vector3d::Zero();
  sc.bodies.reserve(bodies.size());
  for (const Body& b : bodies) {
    scene::BodyModel m;
    m.name = b.name;
    m.inertia = b.inertia;
    m.links = {scene::LinkFrame{b.name, b.M_BL}};
    m.M_WB0 = b.state0.M_WB;
    m.omega_B0 = b.state0.omega_B;
    sc.bodies.push_back(std::move(m));
  }
  return sc;
}

// The bare dynamics loop: what World::step() does for free bodies, without the World.
class BareLoop {
 public:
  BareLoop(const std::vector<Body>& bodies, const std::string& integrator, double lambda, double dt)
      : lambda_(lambda), dt_(dt) {
    inertia_.reserve(bodies.size());
    state_.reserve(bodies.size());
    integrator_.reserve(bodies.size());
    for (const Body& b : bodies) {
      inertia_.push_back(b.inertia);
      state_.push_back(b.state0);
      auto integ = dynamics::makeIntegrator(integrator);
      if (!integ) {
        std::fprintf(stderr, "%s\n", integ.error().c_str());
        std::exit(2);
      }
      integrator_.push_back(std::move(integ.value()));
    }
  }
  void step(long n) {
    const std::size_t count = state_.size();
    for (long k = 0; k < n; ++k)
      for (std::size_t i = 0; i < count; ++i)
        integrator_[i]->step(inertia_[i], loads_, lambda_, dt_, state_[i]);
  }
  bool allFinite() const {
    for (const auto& s : state_)
      if (!s.allFinite()) return false;
    return true;
  }

 private:
  double lambda_, dt_;
  dynamics::Loads loads_;
  std::vector<dynamics::Inertia> inertia_;
  std::vector<dynamics::BodyState> state_;
  std::vector<std::unique_ptr<dynamics::Integrator>> integrator_;
};

using bench::sweep::splitList;  // "a,b,c" → {a, b, c} (peers/sweep_util.h)

// Bytes of heap in use (glibc's main arena and its mmapped blocks: every allocation here is
// made by the main thread — the World's worker threads allocate nothing).
std::size_t heapInUse() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
#else
  const struct mallinfo m = mallinfo();
  return static_cast<std::size_t>(static_cast<unsigned>(m.uordblks)) +
         static_cast<std::size_t>(static_cast<unsigned>(m.hblkhd));
#endif
}

struct Timing {
  double wall_ns = 0;  // median over the repetitions
  double cpu_ns = 0;   // thread CPU time, median (robust to other load on the machine)
};

// Wall and CPU time (ns) of `steps` steps, median over reps.
template <class Stepper>
Timing timeSteps(Stepper& stepper, long steps, int reps) {
  stepper.step(2);  // warm-up: per-body caches are built on the first step
  std::vector<double> wall, cpu;
  for (int r = 0; r < reps; ++r) {
    const double c0 = threadCpuSeconds();
    const auto t0 = Clock::now();
    stepper.step(steps);
    wall.push_back(std::chrono::duration<double, std::nano>(Clock::now() - t0).count());
    cpu.push_back((threadCpuSeconds() - c0) * 1e9);
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

// The World's steps, with every state made current every `read_every` steps (0: never) by
// World::data(), as any report does: coasting bodies (src/sim/coasting.h) take no step and are
// evaluated only when read, so the cost depends on how often the states are read.
struct WorldStepper {
  sim::World& world;
  long read_every;
  void step(long n) {
    for (long k = 0; k < n; ++k) {
      world.step();
      if (read_every > 0 && world.stepCount() % static_cast<std::uint64_t>(read_every) == 0)
        (void)world.data();
    }
  }
};

void usage() {
  std::printf(
      "usage: bench_scaling [options]\n"
      "  --out DIR            output directory (default %s)\n"
      "  --csv PATH           CSV file (default DIR/scaling.csv)\n"
      "  --ns 1,10,100        body counts (default 1,10,100,1000,10000,100000)\n"
      "  --integrators a,b    (default auto,cga2,cga4)\n"
      "  --layers a,b         world, dynamics (default both)\n"
      "  --threads 1,2        threads of the world layer (default 1; the dynamics layer: 1)\n"
      "  --read-every 1,10    world layer: states read every K steps, 0 = never (default 10:\n"
      "                       the node's ~publish_rate 100 Hz at dt = 1 ms)\n"
      "  --body-steps S       body-steps per timing run (default 1000000)\n"
      "  --reps R             timing repetitions, median (default 3)\n"
      "  --dt DT              step, s (default 0.001)\n"
      "  --seed S             random seed (default 20240611)\n",
      BENCH_OUT_DIR);
}

int run(int argc, char** argv) {
  std::string out_dir = BENCH_OUT_DIR, csv_path;
  std::vector<int> ns = {1, 10, 100, 1000, 10000, 100000};
  std::vector<std::string> integrators = {"auto", "cga2", "cga4"};
  std::vector<std::string> layers = {"world", "dynamics"};
  std::vector<int> thread_counts = {1};
  std::vector<long> read_everys = {10};
  long body_steps = 1000000;
  int reps = 3;
  double dt = 1e-3;
  unsigned seed = 20240611;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        usage();
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--out") {
      out_dir = next();
    } else if (a == "--csv") {
      csv_path = next();
    } else if (a == "--ns") {
      ns.clear();
      for (const std::string& t : splitList(next())) ns.push_back(std::atoi(t.c_str()));
    } else if (a == "--integrators") {
      integrators = splitList(next());
    } else if (a == "--layers") {
      layers = splitList(next());
    } else if (a == "--threads") {
      thread_counts.clear();
      for (const std::string& t : splitList(next()))
        thread_counts.push_back(std::max(1, std::atoi(t.c_str())));
    } else if (a == "--read-every") {
      read_everys.clear();
      for (const std::string& t : splitList(next()))
        read_everys.push_back(std::max(0L, std::atol(t.c_str())));
    } else if (a == "--body-steps") {
      body_steps = std::max(1L, std::atol(next().c_str()));
    } else if (a == "--reps") {
      reps = std::max(1, std::atoi(next().c_str()));
    } else if (a == "--dt") {
      dt = std::strtod(next().c_str(), nullptr);
    } else if (a == "--seed") {
      seed = static_cast<unsigned>(std::strtoul(next().c_str(), nullptr, 10));
    } else {
      usage();
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (csv_path.empty()) csv_path = out_dir + "/scaling.csv";
  FILE* csv = std::fopen(csv_path.c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "cannot write %s\n", csv_path.c_str());
    return 2;
  }
  std::fprintf(csv,
               "layer,integrator,n_bodies,steps,ns_per_body_step,ms_per_step,real_time_factor,"
               "cpu_ns_per_body_step,threads,read_every,bytes_per_body\n");
  const double lambda = 1.0;
  const auto t_start = Clock::now();
  for (int n : ns) {
    const std::vector<Body> bodies = makeBodies(n, lambda, seed);
    const long steps = std::max(5L, (body_steps + n - 1) / n);
    for (const std::string& integrator : integrators) {
      for (const std::string& layer : layers) {
        for (int threads : layer == "world" ? thread_counts : std::vector<int>{1})
          for (long read_every : layer == "world" ? read_everys : std::vector<long>{1}) {
            Timing t;
            bool finite = true;
            const std::size_t heap0 = heapInUse();
            std::size_t heap1 = heap0;
            if (layer == "world") {
              sim::WorldConfig config;
              config.dt = dt;
              config.integrator = integrator;
              config.threads = threads;
              auto world = sim::World::create(makeScene(bodies, lambda), config);
              if (!world) {
                std::fprintf(stderr, "World::create: %s\n", world.error().c_str());
                return 2;
              }
              WorldStepper stepper{**world, read_every};
              t = timeSteps(stepper, steps, reps);
              heap1 = heapInUse();
            } else if (layer == "dynamics") {
              BareLoop loop(bodies, integrator, lambda, dt);
              t = timeSteps(loop, steps, reps);
              heap1 = heapInUse();
              finite = loop.allFinite();
            } else {
              std::fprintf(stderr, "unknown layer '%s' (world, dynamics)\n", layer.c_str());
              return 2;
            }
            const double ns_step = t.wall_ns / double(steps);
            const double cpu_body = t.cpu_ns / double(steps) / double(n);
            const double ns_body = ns_step / double(n);
            const double rtf = dt / (ns_step * 1e-9);
            const double bytes_body = heap1 > heap0 ? double(heap1 - heap0) / n : 0.0;
            std::fprintf(csv, "%s,%s,%d,%ld,%.6g,%.6g,%.6g,%.6g,%d,%ld,%.6g\n", layer.c_str(),
                         integrator.c_str(), n, steps, ns_body, ns_step * 1e-6, rtf, cpu_body,
                         threads, read_every, bytes_body);
            std::fflush(csv);
            std::fprintf(
                stderr,
                "[scaling] %-8s %-5s N=%-6d T=%d read/%-3ld %8.1f ns/body-step (cpu %8.1f)  "
                "%9.4f ms/step  RTF %.3g%s\n",
                layer.c_str(), integrator.c_str(), n, threads, read_every, ns_body, cpu_body,
                ns_step * 1e-6, rtf, finite ? "" : "  NOT FINITE");
          }
      }
    }
  }
  std::fclose(csv);
  std::fprintf(stderr, "[scaling] done in %.1f s -> %s\n",
               std::chrono::duration<double>(Clock::now() - t_start).count(), csv_path.c_str());
  return 0;
}

}  // namespace
}  // namespace benchmark
}  // namespace cga_rigid_sim

int main(int argc, char** argv) { return cga_rigid_sim::benchmark::run(argc, argv); }
