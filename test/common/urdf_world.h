// A World made from a URDF string, for tests: the loader's and World::create's errors fail the
// test where they happen (gtest's EXPECT, so the message says which).
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace test {

inline std::unique_ptr<sim::World> worldFromUrdf(const std::string& urdf,
                                                 sim::WorldConfig config = {},
                                                 scene::ParamValue initial_state = {},
                                                 scene::SceneOptions options = {}) {
  options.initial_state = std::move(initial_state);
  auto scene = scene::loadUrdfString(urdf, "test.urdf", options);
  EXPECT_TRUE(scene) << scene.error();
  if (!scene) return nullptr;
  auto world = sim::World::create(std::move(*scene), config);
  EXPECT_TRUE(world) << world.error();
  if (!world) return nullptr;
  return std::move(*world);
}

}  // namespace test
}  // namespace cga_rigid_sim
