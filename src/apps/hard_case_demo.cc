// hard_case_demo <case> <integrator> <h> [T]: runs one of the hard cases with an integrator at
// step h for T seconds (default 100) and prints, at 20 regular intervals, the time, the energy
// error, the |L| error, the attitude error and the centre-of-mass error against the truth.
//
// Cases: the benchmarks' table, bench/cases/cases.h (tennis_racket, thin_rod, symmetric_top,
// projectile, constant_torque; body frame = world frame at t = 0, principal moments given along
// the world axes).
// Truth: the attitude of the torque-free cases is the `exact` integrator (closed-form Euler–
// Poinsot flow) at the same h; with the couple, classical RK4 with 16 substeps per step; the
// centre of mass is the parabola x0 + v0 t + g t²/2. Errors: energy (T + V) relative to the
// truth's, |L| relative to the truth's, attitude as the rotation angle between the two (rad),
// centre of mass as a distance (m). ROS-free.
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "cases/cases.h"
#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/body/integrator.h"

namespace {

using Eigen::Vector3d;

Vector3d toVector(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

int usage(const char* message) {
  if (message) std::cerr << "hard_case_demo: " << message << "\n";
  std::cerr << "usage: hard_case_demo <case> <integrator> <h> [T]\n  case:";
  for (const bench::Case& c : bench::allCases()) std::cerr << " " << c.name;
  std::cerr << "\n  integrator:";
  for (const auto& n : cga_rigid_sim::dynamics::integratorNames()) std::cerr << " " << n;
  std::cerr << "\n  h: step (s, > 0); T: simulated time (s, > 0, default 100)\n";
  return message ? 1 : 0;
}

bool parsePositive(const char* text, double* out) {
  char* end = nullptr;
  *out = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(*out) && *out > 0;
}

double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

}  // namespace

int main(int argc, char** argv) {
  using namespace cga_rigid_sim;
  using namespace cga_rigid_sim::dynamics;
  if (argc == 2 && (std::string(argv[1]) == "-h" || std::string(argv[1]) == "--help"))
    return usage(nullptr);
  if (argc < 4 || argc > 5) return usage("expected 3 or 4 arguments");
  const std::vector<bench::Case> cases = bench::allCases();
  const bench::Case* c = nullptr;
  for (const bench::Case& k : cases)
    if (argv[1] == k.name) c = &k;
  if (!c) return usage(("unknown case '" + std::string(argv[1]) + "'").c_str());
  const Vector3d w0 = toVector(c->w0_body), v0 = toVector(c->v0_world), g = toVector(c->gravity),
                 torque = toVector(c->torque_world);
  auto integrator = makeIntegrator(argv[2]);
  if (!integrator) return usage(integrator.error().c_str());
  double h = 0, T = c->T;
  if (!parsePositive(argv[3], &h)) return usage("h must be a positive number of seconds");
  if (argc == 5 && !parsePositive(argv[4], &T))
    return usage("T must be a positive number of seconds");

  const double lambda = 1.0;
  const auto inertia = Inertia::fromPrincipal(c->name, c->mass, toVector(c->inertia));
  if (!inertia) {
    std::cerr << inertia.error() << "\n";
    return 1;
  }
  // B is the principal frame; at t = 0 it is turned from the world (= the case's axes) by R_FB.
  const Eigen::Quaterniond R0 = inertia->rotationFromPrincipal();
  BodyState s;
  s.M_WB = cga::Motor::fromPose(R0, Vector3d::Zero(), lambda);
  s.omega_B = cga::Bivelocity::fromVelocities(R0.conjugate() * w0, R0.conjugate() * v0, lambda);
  Loads loads;
  loads.setGravity(g);
  if (!torque.isZero()) {
    AppliedLoad couple;
    couple.axes = Axes::kWorld;
    couple.couple = torque;
    loads.add(couple);
  }
  const bool torque_free = !loads.hasTorque();
  auto truth_integrator = makeIntegrator(torque_free ? "exact" : "rk4");
  const int substeps = torque_free ? 1 : 16;
  BodyState truth = s;

  auto energy = [&](const BodyState& b) {
    return kineticEnergy(*inertia, b, lambda) + potentialEnergy(*inertia, b, g, lambda);
  };
  auto angularMomentum = [&](const BodyState& b) {
    return angularMomentumCom_W(*inertia, b).norm();
  };

  const long n = std::max(1L, std::lround(T / h));
  const long every = std::max(1L, n / 20);
  std::printf(
      "# %s with %s, h = %g s, T = %g s; truth: %s; errors relative except attitude "
      "(rad) and centre of mass (m)\n",
      c->name.c_str(), argv[2], h, n * h,
      torque_free ? "exact flow at the same h, parabola" : "rk4 with 16 substeps, parabola");
  std::printf("# %10s  %12s  %12s  %12s  %12s  %s\n", "t[s]", "energy", "|L|", "attitude", "com",
              "path");
  for (long k = 1; k <= n; ++k) {
    (*integrator)->step(*inertia, loads, lambda, h, s);
    for (int j = 0; j < substeps; ++j)
      (*truth_integrator)->step(*inertia, loads, lambda, h / substeps, truth);
    if (k % every && k != n) continue;
    if (!s.allFinite()) {
      std::printf("%12.4f  the state is no longer finite (blow-up)\n", k * h);
      return 0;
    }
    const double t = k * h;
    const Vector3d x = v0 * t + 0.5 * t * t * g;
    std::printf("%12.4f  %12.3e  %12.3e  %12.3e  %12.3e  %s\n", t,
                std::abs(energy(s) - energy(truth)) / std::abs(energy(truth)),
                std::abs(angularMomentum(s) - angularMomentum(truth)) / angularMomentum(truth),
                angleBetween(s.M_WB.rotation(), truth.M_WB.rotation()),
                (comPosition_W(s, lambda) - x).norm(), (*integrator)->path());
  }
  return 0;
}
