// The `simulator` node: reads its parameters, loads the URDF scene, builds the World and runs
// it (simulator.h). A load failure exits with status 1 and the loader's message (ROS_FATAL).
#include <ros/ros.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cga_rigid_sim/ros/controller_params.h"
#include "cga_rigid_sim/ros/parameters.h"
#include "cga_rigid_sim/scene/scene_summary.h"
#include "cga_rigid_sim/scene/urdf/srdf.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"
#include "simulator.h"

int main(int argc, char** argv) {
  using namespace cga_rigid_sim;  // NOLINT: main only
  ::ros::init(argc, argv, "simulator");
  ::ros::NodeHandle nh;
  ::ros::NodeHandle pnh("~");

  std::vector<std::string> warnings;
  auto params = node::readNodeParams(nh, pnh, &warnings);
  for (const auto& w : warnings) ROS_WARN("simulator: %s", w.c_str());
  if (!params) {
    ROS_FATAL("simulator: %s", params.error().c_str());
    return 1;
  }
  auto controllers = node::readControllerParams(nh, pnh);
  if (!controllers) {
    ROS_FATAL("simulator: %s", controllers.error().c_str());
    return 1;
  }

  auto scene =
      params->urdf_from_file
          ? scene::loadUrdfFile(params->urdf_file, params->scene)
          : scene::loadUrdfString(params->urdf_xml, params->urdf_source_name, params->scene);
  if (!scene) {
    ROS_FATAL("simulator: cannot load the scene: %s", scene.error().c_str());
    return 1;
  }
  // The SRDF's collision rules (~srdf_file or robot_description_semantic), before the World
  // decides which pairs of a robot's links collide.
  if (!params->srdf_source_name.empty()) {
    std::string srdf = params->srdf_xml;
    if (!params->srdf_file.empty()) {
      std::ifstream file(params->srdf_file, std::ios::binary);
      if (!file) {
        ROS_FATAL("simulator: ~srdf_file: cannot read '%s': %s", params->srdf_file.c_str(),
                  std::strerror(errno));
        return 1;
      }
      std::ostringstream text;
      text << file.rdbuf();
      srdf = text.str();
    }
    if (auto err = scene::applySrdf(*scene, srdf, params->srdf_source_name)) {
      ROS_FATAL("simulator: %s", err->message().c_str());
      return 1;
    }
  }
  for (const auto& w : scene->warnings) ROS_WARN("simulator: %s", w.c_str());
  const std::size_t scene_warnings = scene->warnings.size();
  // A robot's links and joints are listed whole up to 60 each; past that the summary says where
  // the whole list is.
  scene::SummaryOptions summary;
  summary.whole_list =
      params->urdf_from_file
          ? "rosrun cga_rigid_sim scene_summary " + params->urdf_file + " --all lists every entry"
          : "rosparam get " + params->urdf_source_name +
                " > robot.urdf; rosrun cga_rigid_sim scene_summary robot.urdf --all lists every "
                "entry";
  node::logInfoLines(scene::sceneSummary(*scene, params->world.integrator, summary));

  auto world = sim::World::create(std::move(*scene), params->world);
  if (!world) {
    // The core's configuration fields are the node's parameters: name them so
    // ("~contact_mu: must be ...", not "config.contact_mu: must be ...").
    const Error& e = world.failure();
    const std::string text = e.input == "config" ? "~" + e.field + ": " + e.rule : e.message();
    ROS_FATAL("simulator: %s", text.c_str());
    return 1;
  }

  // Warnings the world adds (bodies that start overlapping), after the scene's own.
  const auto& all = (*world)->scene().warnings;
  for (std::size_t k = scene_warnings; k < all.size(); ++k)
    ROS_WARN("simulator: %s", all[k].c_str());
  // Which pairs of a robot's links collide: summarised in the log, listed in full as the
  // parameter ~self_collision_pairs ("link1 link2" per pair).
  for (const auto& line : (*world)->selfCollisionSummary()) ROS_INFO("%s", line.c_str());
  std::vector<std::string> pairs;
  for (const auto& [a, b] : (*world)->selfCollisionPairs()) pairs.push_back(a + " " + b);
  pnh.setParam("self_collision_pairs", pairs);
  if (!node::startControllers(**world, *controllers)) return 1;

  node::Simulator simulator(nh, pnh, *params, std::move(*controllers), std::move(*world));
  return simulator.run();
}
