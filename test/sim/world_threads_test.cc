// The step on several threads (sim/worker_pool.h): the same states, bit for bit, as on one.
#include <gtest/gtest.h>

#include <random>

#include "sim/world_fixtures.h"

namespace cga_rigid_sim {
namespace world_threads_test {

using testing::makeScene;
using testing::movingBody;

std::unique_ptr<sim::World> makeThreadedWorld(const scene::Scene& scene, int threads) {
  sim::WorldConfig config;
  config.threads = threads;
  auto w = sim::World::create(scene, config);
  EXPECT_TRUE(w.ok()) << w.error();
  return w.ok() ? std::move(w.value()) : nullptr;
}

// Truth: a second method — the serial step. Every body's integration reads only its own data
// and the constant model, so splitting the bodies between threads must not change a single
// bit, whatever the count (1 to 4, also counts that do not divide the number of bodies) and
// whatever happens in between: wrenches in world and link frames starting and ending, impulses,
// gravity, bodies at rest, every inertia class, a spawn and a delete. Compared after every
// 50 steps, bit for bit.
TEST(WorldThreads, StatesAreBitIdenticalForAnyThreadCount) {
  const int n = 1201;  // above kMinBodiesPerThread · 4, and odd
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::vector<scene::BodyModel> bodies = testing::tumblingBodies(n, 21, 5, 0);
  const scene::Scene scene = makeScene(bodies, Eigen::Vector3d(0, 0, -9.81));
  std::vector<std::unique_ptr<sim::World>> worlds;
  for (int threads : {1, 2, 3, 4}) worlds.push_back(makeThreadedWorld(scene, threads));
  const char* kBallUrdf = R"(<robot name="ball"><link name="ball"><inertial><mass value="2"/>
      <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>)";
  for (int round = 0; round < 6; ++round) {
    // The same inputs for every world.
    std::mt19937 inputs(100 + round);
    for (int k = 0; k < 60; ++k) {
      const std::string body = "b" + std::to_string(inputs() % n);
      sim::WrenchInput in;
      in.body = body;
      in.frame = k % 2 ? "world" : body;
      in.F = cga::Force(Eigen::Vector3d(u(inputs), u(inputs), u(inputs)));
      in.point = Eigen::Vector3d(u(inputs), u(inputs), u(inputs)) * 0.1;
      in.couple = Eigen::Vector3d(u(inputs), u(inputs), u(inputs)) * 0.1;
      in.duration = (k % 9) * 0.001;
      sim::ImpulseInput j;
      j.body = body;
      j.J = cga::Force(Eigen::Vector3d(u(inputs), u(inputs), u(inputs)) * 0.1);
      for (auto& w : worlds) {
        ASSERT_TRUE(w->applyWrench(in).ok());
        ASSERT_TRUE(w->applyImpulse(j).ok());
      }
    }
    if (round == 2)
      for (auto& w : worlds) {
        ASSERT_TRUE(w->deleteBody("b7").ok());
        ASSERT_TRUE(
            w->spawnUrdf("ball", kBallUrdf, Eigen::Isometry3d::Identity(), {1, 0, 0}, {0, 2, 0})
                .ok());
      }
    for (auto& w : worlds) w->step(50);
    for (std::size_t k = 1; k < worlds.size(); ++k)
      ASSERT_TRUE(testing::sameStates(*worlds[0], *worlds[k]))
          << k + 1 << " threads, round " << round;
  }
}

// Truth: the configuration rule of model.h — at least one thread, at most kMaxThreads.
TEST(WorldThreads, ThreadCountOutsideItsRangeIsRefused) {
  for (int threads : {0, -1, sim::kMaxThreads + 1}) {
    sim::WorldConfig config;
    config.threads = threads;
    auto w = sim::World::create(makeScene({}), config);
    ASSERT_FALSE(w.ok()) << threads;
    EXPECT_EQ(w.failure().input, "config");
    EXPECT_EQ(w.failure().field, "threads");
  }
}

}  // namespace world_threads_test
}  // namespace cga_rigid_sim
