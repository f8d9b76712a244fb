// Shared driver of the articulated runners (peer_articulated_<engine>, and our bench_articulated,
// which compiles it in without any peer engine): the sweep over articulated cases x configs x
// step sizes, timing, the error evaluation against the truth (bench/cases/articulated_*.h) and
// the CSV writer.
//
// Timing protocol (the peers' one, peer_common.h, with the thread-CPU clock as the headline):
//   * ns_per_step = median over `reps` (default 3) fresh simulations of the thread-CPU time of
//     min(T/h, timing_steps) steps (default 20000) without any state read-back, divided by that
//     number of steps; construction excluded. wall_ns_per_step: the wall time (steady_clock) of
//     the same runs.
//   * the errors come from a separate complete run to T that reads the joint state after every
//     step: err_q_rad = max over the joints of |q(T) - q_ref(T)| (angles wrapped to (-pi, pi]),
//     err_qd = the same for the joint velocities (rad/s); with a floating base also its
//     orientation error (angle, rad) and |w_b - w_b,ref| enter the maxima; energy_drift_rel = max
//     over all steps of |E(t) - E(0)| / E(0), E = kinetic + potential measured from q = 0
//     (articulated_cases.h), E(0) the exact initial energy. The run stops at a blow-up: a
//     non-finite state, a joint speed above 1e3 rad/s, or an engine-reported failure; its errors
//     are then inf.
//   * every run executes in a forked child, so an engine abort loses only that run.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "articulated_cases.h"

namespace bench {
namespace articulated {

class ArticulatedSim {
 public:
  virtual ~ArticulatedSim() = default;
  virtual void step(long n) = 0;
  // Joint positions (rad, the engine's own coordinate or angle) and velocities, case order.
  virtual void joints(std::vector<double>* q, std::vector<double>* qd) = 0;
  // A floating base's state (world frame; v = velocity of the base frame origin). Runners of
  // floating-base cases must override it; false: the engine has no floating base here.
  virtual bool base(BaseState<double>* /*b*/) { return false; }
  // Engines in maximal coordinates override this with the energy of their bodies' state
  // (EnergyMeter::fromBodies): it then is what they conserve or not, not a projection of it.
  virtual bool bodyEnergy(double* /*E*/) { return false; }
  // True when the engine itself detected divergence (e.g. MuJoCo's reset on a bad qacc).
  virtual bool failed() { return false; }
  // Engine facts worth a note (no commas needed; they are replaced).
  virtual std::string events() { return ""; }
};

using ArticulatedFactory =
    std::function<std::unique_ptr<ArticulatedSim>(const ArticulatedCase&, double h)>;

struct ArticulatedConfig {
  std::string name;
  ArticulatedFactory make;
  bool in_default_sweep = true;  // false: only with --all-configs or --configs
};

struct ArticulatedDefaults {
  std::vector<double> hs;  // empty: defaultArticulatedSteps()
  long timing_steps = 20000;
  int reps = 3;
  double min_h = 0;  // budget floor: smaller h skipped (noted) unless --min-h overrides
};

// 1e-2 ... 1e-5, 10 values (1, 2, 5 per decade).
std::vector<double> defaultArticulatedSteps();

// bench/out/articulated_<engine>.csv
class ArticulatedCsv {
 public:
  explicit ArticulatedCsv(const std::string& path);
  ~ArticulatedCsv();
  ArticulatedCsv(const ArticulatedCsv&) = delete;
  ArticulatedCsv& operator=(const ArticulatedCsv&) = delete;
  static const char* header() {
    return "engine,config,case,h,ns_per_step,wall_ns_per_step,err_q_rad,err_qd_rad_s,energy_drift_"
           "rel,blew_up,"
           "notes";
  }
  void row(const std::string& engine, const std::string& config, const std::string& case_name,
           double h, double cpu_ns, double wall_ns, double err_q, double err_qd, double drift,
           bool blew, const std::string& notes);

 private:
  void* file_;
};

int runArticulatedSweep(const std::string& engine, const std::string& version,
                        const std::vector<ArticulatedConfig>& configs, int argc, char** argv,
                        const ArticulatedDefaults& defaults = ArticulatedDefaults());

}  // namespace articulated
}  // namespace bench
