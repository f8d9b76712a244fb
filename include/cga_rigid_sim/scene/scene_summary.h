// What a loaded scene is, a screen or two (the node logs it on load; the scene_summary app
// prints it).
#pragma once

#include <cstddef>
#include <string>

#include "cga_rigid_sim/scene/scene.h"

namespace cga_rigid_sim {
namespace scene {

/// How much the summary lists. A section cut short ends with "... and N more <entries>" and
/// `whole_list`, which says where the rest is.
struct SummaryOptions {
  /// Bodies outside articulated trees (free and static: a heap of boxes) listed; 0 = all.
  std::size_t max_bodies = 20;
  /// The bodies of articulated trees and the joints, each: a robot's links and joints; 0 = all.
  /// 60 lists a humanoid of 50 joints whole.
  std::size_t max_robot_entries = 60;
  std::string whole_list = "scene_summary <urdf> --all lists every entry";
};

/// The summary printed on load, in sections (each a function in scene_summary.cc, in this
/// order): the scene's line; loads; bodies (mass, principal moments, inertia class, integrator
/// path under `integrator`, links merged into each, collision shapes); joints (limits,
/// dynamics, initial state, mimic); paths; warnings.
std::string sceneSummary(const Scene& scene, const std::string& integrator,
                         const SummaryOptions& options = SummaryOptions());

}  // namespace scene
}  // namespace cga_rigid_sim
