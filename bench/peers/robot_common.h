// Shared driver of the real-robot cases of the contact benchmark (bench/peers/robot_cases.h),
// run by `bench_contacts --robots` (ours) and `peer_contacts_<engine> --robots`.
//
// Timing protocol:
//   * for each phase of the case (atlas_fall: the fall, [0, 1) s, and the lying, [1, 5) s),
//     the thread-CPU and the wall time of the steps of that phase, without state read-back,
//     divided by its number of steps; construction excluded. The reported figures are the
//     medians over `reps` (default 3) fresh simulations, each in a forked child.
//   * at every phase's end, outside the timed region, the state is observed (the root link's
//     height, the kinetic energy, the contacts of the last step, the deepest contact, the
//     energy figure, whether the robot sleeps, engine notes); these come from the first
//     repetition (all repetitions of one start are the same deterministic run).
//   * the real-time factor is h / (CPU time per step).
//
// Perturbed starts (--starts K, --start-shift DZ): a falling robot's landing depends
// chaotically on round-off, so one run compares two landings more than two engines. Start
// k = 0..K-1 runs a contact case with its ground plane lowered by k·DZ (default 3e-4 m): the
// robot falls a little further and lands differently, in every engine alike (the driver hands
// the factories the shifted RobotCase). Start 0 is the case as written. The repetitions run
// the starts in turn (rep 0 of every start, then rep 1, ...), so that the machine's load
// drifts over all starts alike. A case without contacts has no plane to lower: it runs start 0
// only. K = 1 (the default) is exactly the single run, with the same CSV.
//
// Output: bench/out/robots_<engine>.csv, one row per (config, case, phase). With K > 1 its
// ms/step and RTF columns are the mean over the starts of each start's median over the
// repetitions, its root_z/kinetic_J/contacts start 0's, and its notes begin with the spread
// ("mean of K starts ...; cpu [min, max] ...; wall [min, max] ...; asleep at the phase's end in
// n of K; start 0: <notes>"). With K > 1 also robots_<engine>_starts.csv (next to the CSV, its
// name with _starts before .csv), one row per (config, case, phase, start):
//   engine,config,case,phase,start,ground_z,t_start,t_end,h,cpu_ms_per_step,wall_ms_per_step,
//   rtf_cpu,root_z,kinetic_J,contacts,max_depth_m,energy_J,asleep,notes
// with energy_J the engine's energy figure (RobotObs::energy) and asleep 1/0, or -1 for an
// engine without sleeping.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "robot_cases.h"

namespace bench {
namespace robots {

// The files a case needs at run time, in a temporary directory removed at the end of the
// sweep: a package directory of symlinks on ROS_PACKAGE_PATH (for package:// URIs), and the
// URDF copy MuJoCo reads: visuals removed (MuJoCo 2.2 cannot read Collada), for cases without
// contacts the collisions too, every collision mesh a symlink meshes/m<k>_<name>.stl (MuJoCo
// reads STL by a lower-case extension, resolves no package:// and strips directories; an ASCII
// STL, which MuJoCo 2.2 cannot read, is written there as binary STL instead) and
// <mujoco><compiler meshdir=... discardvisual="true" fusestatic="false"/></mujoco> in <robot>.
struct PreparedRobot {
  std::string dir;
  std::string urdf;  // the case's URDF (RobotCase::urdf, or the one written by `generate`)
  std::string mujoco_urdf;
  std::string out_dir;  // bench/out (files one runner leaves for another: robot_pairs_<case>.txt)
};

struct RobotObs {
  double root_z = 0;   // m, the root link's origin (0 for a fixed base)
  double kinetic = 0;  // J
  int contacts = 0;    // in the last step
  double max_depth = std::numeric_limits<double>::quiet_NaN();  // m, the deepest contact's
  // J, the energy figure the engine's note gives: ours the balance kinetic + potential +
  // dissipated - initial (0 for an exact energy book), MuJoCo the change of kinetic + potential.
  double energy = std::numeric_limits<double>::quiet_NaN();
  int asleep = -1;   // 1 the robot sleeps (every tree asleep), 0 awake, -1 the engine cannot
  std::string note;  // engine facts (faults, sleeping, energy balance, warnings); no commas
};

class RobotSim {
 public:
  virtual ~RobotSim() = default;
  virtual void step(long n) = 0;
  virtual RobotObs observe() = 0;
};

using RobotFactory =
    std::function<std::unique_ptr<RobotSim>(const RobotCase&, const PreparedRobot&)>;

struct RobotConfig {
  std::string name;
  RobotFactory make;
  // Which cases the config runs (e.g. a self-collision variant: contact cases only).
  std::function<bool(const RobotCase&)> applies = [](const RobotCase&) { return true; };
};

// The allowed self-collision pairs of a case as our World chose them (one "a b" per line),
// written by bench_contacts --robots and read by peers that run "our pairs".
std::string pairsFile(const PreparedRobot& p, const RobotCase& c);

// argv without "--robots"; options --cases, --configs, --reps, --starts, --start-shift, --out,
// --csv (see usage in robot_common.cc and the header comment).
int runRobotSweep(const std::string& engine, const std::string& version,
                  const std::vector<RobotConfig>& configs, int argc, char** argv);

// True when argv holds "--robots" (the runners' switch to this sweep).
bool robotsRequested(int argc, char** argv);

}  // namespace robots
}  // namespace bench
