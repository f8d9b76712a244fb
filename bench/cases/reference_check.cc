// Validation table for the reference solution (bench/cases/reference_solution.h).
// For every case, at t = T:
//   dq(H,H/2)   orientation difference between macro steps H and H/2 (long double)
//   dq(ld,dbl)  orientation difference long double vs the same scheme in double
//               (how strongly the problem amplifies roundoff)
//   dq(exact)   vs the closed form (axisymmetric torque-free cases only)
//   dL          |L_world(T) - L_expected| / |L_expected|, L_expected = J w0 + tau T
//               (exact for every case: the torque is constant in world axes)
//   dE          |E(T) - E(0)| / |E(0)| for the conservative cases
// Usage: bench_reference_check [case ...]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cases.h"
#include "reference_solution.h"

int main(int argc, char** argv) {
  using namespace bench;
  std::vector<std::string> only(argv + 1, argv + argc);
  std::printf("%-16s %9s %10s %11s %11s %11s %11s %11s %8s\n", "case", "H", "steps", "dq(H,H/2)", "dq(ld,dbl)",
              "dq(exact)", "dL", "dE", "sec");
  for (const Case& c : allCases()) {
    if (!only.empty()) {
      bool found = false;
      for (const auto& o : only) found |= (o == c.name);
      if (!found) continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const long n = defaultMacroSteps(c);
    const Reference a = integrateReference(c, c.T, n, true);
    const Reference b = integrateReference(c, c.T, 2 * n, true);
    const Reference d = integrateReference(c, c.T, 2 * n, false);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    BodyState exact;
    char exact_s[32] = "-";
    if (analyticSymmetricTorqueFree(c, c.T, &exact))
      std::snprintf(exact_s, sizeof exact_s, "%.3e", orientationError(b.state.q, exact.q));
    // Angular momentum check.
    const std::array<double, 3> L = angularMomentumWorld(c, b.state);
    double dL2 = 0, Le2 = 0;
    for (int i = 0; i < 3; ++i) {
      const double le = c.inertia[i] * c.w0_body[i] + c.torque_world[i] * c.T;
      dL2 += (L[i] - le) * (L[i] - le);
      Le2 += le * le;
    }
    char dE_s[32] = "-";
    if (c.torque_world[0] == 0 && c.torque_world[1] == 0 && c.torque_world[2] == 0) {
      BodyState s0;
      s0.q = {1, 0, 0, 0};
      s0.w_world = c.w0_body;
      s0.x = {0, 0, 0};
      s0.v = c.v0_world;
      const double E0 = energyOf(c, s0);
      std::snprintf(dE_s, sizeof dE_s, "%.3e", std::fabs(b.energy - E0) / std::fabs(E0));
    }
    std::printf("%-16s %9.3g %10ld %11.3e %11.3e %11s %11.3e %11s %8.2f\n", c.name.c_str(), b.macro_step,
                b.macro_steps, orientationError(a.state.q, b.state.q), orientationError(b.state.q, d.state.q),
                exact_s, std::sqrt(dL2 / Le2), dE_s, sec);
  }
  return 0;
}
