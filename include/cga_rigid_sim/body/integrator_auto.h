// auto (the default): per body and per step, the cheapest path that is exact, or accurate enough,
// for the body's inertia class and the loads it has this step.
//
//   no loads and Ω_B = 0             → "at-rest": not stepped (the state is left untouched);
//   no torque (no loads, gravity, or
//   forces through the centre of mass) → "exact-spherical" / "exact-symmetric" /
//                                        "exact-asymmetric": the exact free flow (free_flow.h),
//                                        with the forces as kicks, K(h/2) F(h) K(h/2) — exact
//                                        to round-off when the forces are fixed in the world
//                                        (uniform acceleration), second order for forces fixed
//                                        in the body;
//   torques                          → "exact+kicks": the same Strang splitting, second order
//                                        (integrator_exact.h), for every inertia class.
//
// Asymmetric bodies under torque: the kick changes w, so the exact flow rebuilds its elliptic
// cache every step (≈ 1.6× the cost of cga4). It is kept because its error comes from the torque
// alone, not from the spin; the measurements are in the .cc.
#pragma once

#include "cga_rigid_sim/body/integrator.h"
#include "cga_rigid_sim/body/integrator_exact.h"

namespace cga_rigid_sim {
namespace dynamics {

class AutoIntegrator : public Integrator {
 public:
  const char* name() const override { return "auto"; }
  /// The path of the last step: "at-rest", "exact-spherical", "exact-symmetric",
  /// "exact-asymmetric", "exact+kicks"; name() before the first step.
  const char* path() const override { return path_; }
  void step(const Inertia& inertia, const Loads& loads, double lambda, double h,
            BodyState& state) override;
  void reset() override { exact_.reset(); }
  /// Without applied loads: the exact flow's closed form (ExactIntegrator::coast).
  bool coasts(const Loads& loads) const override { return exact_.coasts(loads); }
  void coast(const Inertia& inertia, const Loads& loads, double lambda, double h, double steps,
             const BodyState& from, BodyState& out) override;

 private:
  ExactIntegrator exact_;
  const char* path_ = "auto";
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
