// Parameters of the simulator node: read from the parameter server, type-checked, converted to
// the core's options (scene::SceneOptions, sim::WorldConfig). Values the core owns (dt, the
// integrator name, limits, λ) are validated by the core when the scene and World are built;
// this file checks types and the node's own settings (rates, real-time factor).
#pragma once

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <cstdint>
#include <string>
#include <vector>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/ros/markers.h"
#include "cga_rigid_sim/scene/param_value.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace node {

struct NodeParams {
  /// Where the URDF comes from: `~urdf_file` (a path) when set, else the string parameter
  /// `robot_description` (resolved in the node's namespace, the ROS convention).
  bool urdf_from_file = false;
  std::string urdf_file;         ///< path, when urdf_from_file
  std::string urdf_xml;          ///< the XML, when !urdf_from_file
  std::string urdf_source_name;  ///< resolved parameter name or path, for messages
  /// The SRDF (self-collision rules, scene/urdf/srdf.h): `~srdf_file` (a path) when set, else the
  /// string parameter `robot_description_semantic` (MoveIt's name), else none (empty).
  std::string srdf_file;
  std::string srdf_xml;
  std::string srdf_source_name;

  scene::SceneOptions scene;  ///< ~lambda, ~gravity, ~relax_inertia, ~world_frame,
                              ///< ~initial_state
  sim::WorldConfig world;     ///< ~dt, ~integrator, ~world_frame, ~max_force, ~max_impulse,
                              ///< ~threads, ~ground_plane, ~contact_mu, ~contact_restitution,
                              ///< ~self_collision

  double real_time_factor = 1.0;  ///< ~real_time_factor: sim s per wall s; 0 = max speed
  double publish_rate = 100.0;    ///< ~publish_rate: tf, momentum, body states, contacts,
                                  ///< Hz (sim)
  bool publish_clock = true;      ///< ~publish_clock
  double clock_rate = 0.0;        ///< ~clock_rate: Hz (sim); 0 = every step
  bool paused = false;            ///< ~paused: start paused
  /// ~sensor_seed: keys the sensors' noise (doc/sensors.md#noise); same seed, same noise.
  std::uint64_t sensor_seed = 0;
  MarkerScale markers;  ///< ~marker_length, ~marker_{angular_momentum,angular_velocity,force}_ref
};

/// The private parameters the node knows (without "~"), for the unknown-parameter warning.
const std::vector<std::string>& knownPrivateParams();

/// Reads every parameter. `nh` is the node's namespace handle (for robot_description), `pnh`
/// the private one. Errors name the parameter and the rule ("~dt: expected a number, got
/// string"). `warnings` gets non-fatal remarks (unknown private parameters, both URDF sources
/// set).
Result<NodeParams> readNodeParams(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh,
                                  std::vector<std::string>* warnings);

/// XmlRpcValue → ParamValue (bool, int and double → number, string, array → list, struct →
/// map). Date/time and binary values are refused; `path` names the value in errors
/// ("~initial_state.racket.omega[2]").
Result<scene::ParamValue> toParamValue(const XmlRpc::XmlRpcValue& value, const std::string& path);

}  // namespace node
}  // namespace cga_rigid_sim
