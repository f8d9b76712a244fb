// Shared driver for the peer-engine runners: the sweep over cases x configs x
// step sizes, the timing protocol, the error evaluation against the
// reference solution, and the CSV writer.
//
// Timing protocol (identical for every engine, see runSweep):
//   * ns_per_step = median over `reps` (default 3) fresh simulations of the
//     wall time (steady_clock) of advancing min(N, timing_steps) steps
//     (default timing_steps = 20000; N = T/h), divided by that number of steps
//     (Simbody uses 2000 and a shorter h grid, see simbody_runner.cc).
//     Model construction is excluded; per-step work the user must do (e.g.
//     re-applying the torque) is included. So for h >= 5e-3 the timed run is
//     the whole 100 s run; for smaller h it is the first 20000 steps.
//   * the same timing runs are also measured in thread CPU time and written
//     to cputime_<engine>.csv (wall and CPU ns/step side by side): on
//     a shared, loaded machine the wall time overstates the cost, the CPU
//     time much less so;
//   * every run (timing or error) is executed in a forked child process, so
//     an engine that aborts on a diverged state loses only that run;
//   * the errors always come from a separate, complete run to t = T = 100 s
//     (N steps), which is checked for blow-up every N/100 steps and stopped
//     early if it blew up (then the errors are written as inf). Blow-up =
//     non-finite state, |w| > 1e6 |w0|, or an engine-reported divergence
//     (PeerSim::engineReportedFailure, e.g. MuJoCo's automatic reset).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cases.h"
#include "reference_solution.h"

namespace bench {
namespace peers {

// One simulation of one case at one fixed step size h.
class PeerSim {
 public:
  virtual ~PeerSim() = default;
  // Advance `steps` steps of size h (re-applying the world torque before each
  // step if the engine clears applied loads).
  virtual void run(long steps) = 0;
  // Current state (may be called between run() calls).
  virtual BodyState state() = 0;
  // True if the engine itself detected divergence and changed the state
  // behind our back (MuJoCo resets the simulation when qacc is bad). Such a
  // run is reported as blown up.
  virtual bool engineReportedFailure() { return false; }
};

using Factory = std::function<std::unique_ptr<PeerSim>(const Case&, double h)>;

struct PeerConfig {
  std::string name;  // e.g. "RK4"
  Factory make;
  // false: only run with --all-configs or --configs (time budget).
  bool in_default_sweep = true;
};

// Per-engine defaults of the sweep (overridable on the command line).
struct SweepDefaults {
  std::vector<double> hs;   // empty: defaultStepSizes()
  long timing_steps = 20000;
  int reps = 3;
  // Budget floor: step sizes below it are skipped (with a note in the log)
  // even when requested with --hs, unless --min-h overrides it. Keeps a slow
  // engine inside the suite's time budget when a caller passes the full grid.
  double min_h = 0;
};

// Fixed CSV layout of bench/out/peers_<engine>.csv.
class CsvWriter {
 public:
  explicit CsvWriter(const std::string& path);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;
  static const char* header();
  void row(const std::string& engine, const std::string& config, const std::string& case_name, double h,
           double ns_per_step, const Errors& e, bool blew_up);

 private:
  void* file_;  // FILE*
};

// Parses the common command line (see --help) and runs the sweep; returns the
// process exit code. `version` is printed by --version and to stderr.
int runSweep(const std::string& engine, const std::string& version, const std::vector<PeerConfig>& configs,
             int argc, char** argv, const SweepDefaults& defaults = SweepDefaults());

// Step sizes used by default (10 values, 3 decades).
std::vector<double> defaultStepSizes();

}  // namespace peers
}  // namespace bench
