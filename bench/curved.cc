// bench_curved: the "1 up" curved-space integrators against the "2 up" Euclidean ones on the
// same bodies (doc/benchmarks-curved.md, doc/curved_space.md).
//
// For each body (an asymmetric racket, an isotropic ball), radius R (±1e2, ±1e3, ±1e4 m) and
// step h, it runs T = 10 s and reports:
//   - ns per step (thread CPU time, the best of 3 runs, so other processes do not count);
//   - the error at T against the Euclidean exact flow (free_flow.h): for 2 up the integrator's
//     own error; for 1 up, read in the stereographic chart, the integrator's error plus the
//     physical O(1/R²) difference between curved and flat space;
//   - for 1 up, its error against the curved motion itself (the closed form for the ball, curved2
//     at h/16 for the racket): the integrator's own error.
// Errors are position (m) plus attitude (rad). Writes bench/out/curved.csv and prints a table.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "bench_clock.h"
#include "cga_rigid_sim/body/free_flow.h"
#include "cga_rigid_sim/body/integrator.h"
#include "cga_rigid_sim/curved/curved_integrator.h"

using namespace cga_rigid_sim;
using namespace cga_rigid_sim::dynamics;

namespace {

struct Body {
  const char* name;
  double mass;
  Eigen::Vector3d J, w, v;
};

const Eigen::Vector3d kX0(0.5, -0.3, 0.2);
const Eigen::Quaterniond kQ0 = Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized();
constexpr double kT = 10.0;

double angle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

BodyState flatStart(const Body& b) {
  BodyState s;
  s.M_WB = cga::Motor::fromPose(kQ0, kX0, 1.0);
  s.omega_B = cga::Bivelocity::fromVelocities(b.w, b.v, 1.0);
  return s;
}
CurvedBodyState curvedStart(const Body& b, const CurvedSpace& S) {
  CurvedBodyState s;
  s.psi = S.poseFromChart(kX0, kQ0).value();
  s.omega_B = cga::Bivector4(b.w, b.v / S.rho());
  return s;
}
double flatError(const BodyState& s, const BodyState& ref) {
  return (s.M_WB.translation(1.0) - ref.M_WB.translation(1.0)).norm() +
         angle(s.M_WB.rotation(), ref.M_WB.rotation());
}
double chartError(const CurvedSpace& S, const CurvedBodyState& c, const BodyState& ref) {
  Eigen::Vector3d x;
  Eigen::Quaterniond q;
  S.chartPose(c.psi, x, q);
  return (x - ref.M_WB.translation(1.0)).norm() + angle(q, ref.M_WB.rotation());
}
double curvedError(const CurvedSpace& S, const CurvedBodyState& a, const CurvedBodyState& b) {
  Eigen::Vector3d xa, xb;
  Eigen::Quaterniond qa, qb;
  S.chartPose(a.psi, xa, qa);
  S.chartPose(b.psi, xb, qb);
  return (xa - xb).norm() + angle(qa, qb);
}

template <class StepFn>
double nsPerStep(int n, StepFn step) {
  double best = 1e30;
  for (int rep = 0; rep < 3; ++rep) {
    const double t0 = benchmark::threadCpuSeconds();
    step();
    best = std::min(best, (benchmark::threadCpuSeconds() - t0) / n * 1e9);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
  const std::vector<Body> bodies = {
      {"racket", 0.4, {0.004, 0.008, 0.012}, {0.2, 10.0, 0.3}, {0.5, -0.3, 0.2}},
      {"ball", 1.0, {0.004, 0.004, 0.004}, {1.0, 2.0, 3.0}, {0.5, -0.2, 0.3}}};
  const std::vector<double> radii =
      quick ? std::vector<double>{1e3} : std::vector<double>{1e2, 1e3, 1e4, -1e2, -1e3, -1e4};
  const std::vector<double> steps =
      quick ? std::vector<double>{1e-2} : std::vector<double>{1e-3, 1e-2};

  std::ofstream csv(std::string(BENCH_OUT_DIR) + "/curved.csv");
  csv << "body,integrator,R,h,ns_per_step,error_vs_flat_exact,error_vs_curved_truth\n";
  std::printf("%-7s %-13s %9s %7s %10s %14s %14s\n", "body", "integrator", "R (m)", "h (s)",
              "ns/step", "err vs flat", "err vs curved");
  for (const Body& b : bodies) {
    const Inertia E = Inertia::fromPrincipal(b.name, b.mass, b.J).value();
    BodyState truth = flatStart(b);
    FreeFlowCache cache;
    exactFreeFlow(E, 1.0, kT, truth, cache);
    for (double h : steps) {
      const int n = static_cast<int>(std::lround(kT / h));
      // 2 up.
      for (const char* name : {"cga2", "exact"}) {
        BodyState s;
        const double ns = nsPerStep(n, [&] {
          auto it = makeIntegrator(name).value();
          s = flatStart(b);
          for (int i = 0; i < n; ++i) it->step(E, Loads(), 1.0, h, s);
        });
        const double err = flatError(s, truth);
        std::printf("%-7s %-13s %9s %7g %10.1f %14.3e %14s\n", b.name, name, "flat", h, ns, err,
                    "");
        csv << b.name << "," << name << ",inf," << h << "," << ns << "," << err << ",\n";
      }
      // 1 up.
      for (double R : radii) {
        const CurvedSpace S = CurvedSpace::fromRadius(R).value();
        const CurvedInertia I = CurvedInertia::fromEuclidean(b.name, E, S).value();
        CurvedBodyState ref;
        if (I.isotropic()) {
          ref = curvedIsotropicFlow(I, curvedStart(b, S), kT);
        } else {
          ref = curvedStart(b, S);
          CurvedSplittingIntegrator fine;
          for (int i = 0; i < 16 * n; ++i) fine.step(I, CurvedLoads(), h / 16, ref);
        }
        for (const char* name : {"curved2", "curved_exact"}) {
          if (std::string(name) == "curved_exact" && !I.isotropic()) continue;
          CurvedBodyState s;
          const double ns = nsPerStep(n, [&] {
            auto it = makeCurvedIntegrator(name, I).value();
            s = curvedStart(b, S);
            for (int i = 0; i < n; ++i) it->step(I, CurvedLoads(), h, s);
          });
          const double err = chartError(S, s, truth), own = curvedError(S, s, ref);
          std::printf("%-7s %-13s %9g %7g %10.1f %14.3e %14.3e\n", b.name, name, R, h, ns, err,
                      own);
          csv << b.name << "," << name << "," << R << "," << h << "," << ns << "," << err << ","
              << own << "\n";
        }
      }
    }
  }
  return 0;
}
