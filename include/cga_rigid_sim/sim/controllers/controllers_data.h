// The World's joint controllers (doc/control.md#in-the-world): ros_control controllers on the
// trees' joints, the commands waiting for their step, and what the control stage keeps from
// step to step. Part of the Data: commands are inputs like any other, stamped in simulation
// time and applied at their step, so a run with commands replays bit for bit.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cga_rigid_sim/control/controller_config.h"
#include "cga_rigid_sim/control/joint_trajectory.h"
#include "cga_rigid_sim/control/pid_integral.h"
#include "cga_rigid_sim/control/trajectory_controller.h"

namespace cga_rigid_sim {
namespace sim {

/// One running controller.
struct ControllerData {
  control::ControllerConfig config;
  /// A spawned robot's controller: the robot's namespace, which prefixes its name and joints
  /// (doc/control.md#spawned-robots); empty otherwise.
  std::string name_space;
  int tree = -1;            ///< the tree of its joints (−1: the joint state controller)
  std::vector<int> joints;  ///< their indices in the tree, in config.joints' order
  std::vector<control::ServoGains> gains;      ///< per joint: the servo law it drives
  std::vector<control::PidGains> pid;          ///< per joint: the integral term's gains and clamps
  std::vector<control::PidIntegral> integral;  ///< per joint
  std::optional<control::TrajectoryController> trajectory;  ///< trajectory controllers
  /// Group controllers: the last command per joint (positions: the pose at load; velocities
  /// and efforts: 0 until commanded).
  std::vector<double> command;
};

/// A command waiting for its step.
struct ControllerCommand {
  std::uint64_t step = 0;     ///< the step it takes effect at
  std::uint64_t arrival = 0;  ///< arrival order, for equal steps
  int controller = -1;
  control::JointTrajectory trajectory;  ///< trajectory controllers
  std::vector<double> values;           ///< group controllers
};

struct ControllersData {
  std::vector<ControllerData> running;
  std::vector<ControllerCommand> waiting;  ///< ordered by (step, arrival)
  std::uint64_t arrivals = 0;
  /// Commands refused at their step (a trajectory whose every point had passed by then), and
  /// the last reason.
  std::uint64_t refused_at_step = 0;
  std::string last_refusal;
};

}  // namespace sim
}  // namespace cga_rigid_sim
