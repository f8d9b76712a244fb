// Shared driver of the real-robot cases of the contact benchmark (bench/peers/robot_cases.h),
// run by `bench_contacts --robots` (ours) and `peer_contacts_<engine> --robots`.
//
// Timing protocol:
//   * for each phase of the case (atlas_fall: the fall, [0, 1) s, and the lying, [1, 5) s),
//     the thread-CPU and the wall time of the steps of that phase, without state read-back,
//     divided by its number of steps; construction excluded. The reported figures are the
//     medians over `reps` (default 3) fresh simulations, each in a forked child.
//   * at every phase's end, outside the timed region, the state is observed (the root link's
//     height, the kinetic energy, the contacts of the last step, engine notes); these come from
//     the first repetition (all repetitions are the same deterministic run).
//   * the real-time factor is h / (CPU time per step).
// Output: bench/out/robots_<engine>.csv, one row per (config, case, phase).
#pragma once

#include <functional>
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
  std::string note;    // engine facts (faults, sleeping, energy balance, warnings); no commas
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

// argv without "--robots"; options --cases, --configs, --reps, --out, --csv.
int runRobotSweep(const std::string& engine, const std::string& version,
                  const std::vector<RobotConfig>& configs, int argc, char** argv);

// True when argv holds "--robots" (the runners' switch to this sweep).
bool robotsRequested(int argc, char** argv);

}  // namespace robots
}  // namespace bench
