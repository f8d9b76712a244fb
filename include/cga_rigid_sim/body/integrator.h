// Integrator: advances one body's state (M_WB, Ω_B) by one step h under its loads.
//
// One interface, chosen by name (makeIntegrator): `cga2`, `cga4`, `exact`, `auto` (default),
// and the baselines `euler`, `rk4`. An integrator object belongs to one body: it may cache
// per-body data that depends only on the inertia and the state (e.g. the elliptic parameters
// of a torque-free asymmetric body) and must check that cache itself; reset() drops it (the
// simulator calls it after impulses and state overrides).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/body/loads.h"
#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace dynamics {

class Integrator {
 public:
  virtual ~Integrator() = default;
  /// The name it is chosen by.
  virtual const char* name() const = 0;
  /// For `auto`: the path it took for the last step (e.g. "exact-symmetric"); else name().
  virtual const char* path() const { return name(); }
  /// Advances `state` by h. Loads are those active during the step; an integrator evaluates
  /// pose-dependent loads where its method needs them.
  virtual void step(const Inertia& inertia, const Loads& loads, double lambda, double h,
                    BodyState& state) = 0;
  /// Drops any cached per-body data.
  virtual void reset() {}
  /// Whether the motion under `loads` is a closed form in the elapsed time (exact, auto: no
  /// applied load; gravity allowed). The World then lets the body coast: it takes no step and
  /// evaluates the state by coast() only when it is read (sim/data.h, Coast).
  virtual bool coasts(const Loads& /*loads*/) const { return false; }
  /// Only where coasts(loads): the state `steps` steps of h after `from`, a function of
  /// (from, steps) alone (no other call changes it), equal to `steps` calls of step() from
  /// `from` to round-off. May cache what depends on `from` only.
  virtual void coast(const Inertia& /*inertia*/, const Loads& /*loads*/, double /*lambda*/,
                     double /*h*/, double /*steps*/, const BodyState& from, BodyState& out) {
    out = from;
  }
};

/// The names makeIntegrator accepts, in documentation order.
const std::vector<std::string>& integratorNames();
/// A new integrator for one body, or an error naming the unknown integrator and the valid ones.
Result<std::unique_ptr<Integrator>> makeIntegrator(const std::string& name);

}  // namespace dynamics
}  // namespace cga_rigid_sim
