// step() must not allocate: it runs at the simulation rate for up to 100 000 bodies. This file
// replaces the global operator new of the test_sim executable with a counting one (it only
// counts while a test asks it to, so the other tests are unaffected). Under AddressSanitizer,
// which owns operator new itself, the replacement is left out and the test is skipped.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "common/real_like_robots.h"
#include "sim/world_fixtures.h"

#if defined(__SANITIZE_ADDRESS__)
#define CGA_RIGID_SIM_COUNT_ALLOCATIONS 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CGA_RIGID_SIM_COUNT_ALLOCATIONS 0
#endif
#endif
#ifndef CGA_RIGID_SIM_COUNT_ALLOCATIONS
#define CGA_RIGID_SIM_COUNT_ALLOCATIONS 1
#endif

namespace allocation_counter {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
void* countedAlloc(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* countedAlignedAlloc(std::size_t n, std::size_t align) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  void* p = nullptr;
  if (posix_memalign(&p, std::max(align, sizeof(void*)), n ? n : 1) == 0) return p;
  throw std::bad_alloc();
}
}  // namespace allocation_counter

#if CGA_RIGID_SIM_COUNT_ALLOCATIONS
// Eigen's dynamic matrices take their memory from malloc, not from operator new: malloc and
// realloc are replaced too (an executable's definitions take precedence over the C library's
// for the whole process, shared libraries included), forwarding to glibc's own.
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
extern "C" void* malloc(std::size_t n) {
  if (allocation_counter::g_counting.load(std::memory_order_relaxed))
    allocation_counter::g_allocations.fetch_add(1);
  return __libc_malloc(n);
}
extern "C" void* realloc(void* p, std::size_t n) {
  if (allocation_counter::g_counting.load(std::memory_order_relaxed))
    allocation_counter::g_allocations.fetch_add(1);
  return __libc_realloc(p, n);
}
void* operator new(std::size_t n) { return allocation_counter::countedAlloc(n); }
void* operator new[](std::size_t n) { return allocation_counter::countedAlloc(n); }
void* operator new(std::size_t n, std::align_val_t a) {
  return allocation_counter::countedAlignedAlloc(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return allocation_counter::countedAlignedAlloc(n, static_cast<std::size_t>(a));
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
#endif

namespace cga_rigid_sim {
namespace world_alloc_test {

using testing::makeScene;
using testing::makeWorld;
using testing::movingBody;

// Truth: the performance contract of world.h — no heap allocation inside step(), counted by the
// replaced operator new, while wrenches (world and link frame, finite and until-cleared) start
// and end and impulses land, for bodies of every inertia class, some at rest, some under load.
TEST(WorldAllocation, StepDoesNotAllocate) {
  if (!CGA_RIGID_SIM_COUNT_ALLOCATIONS) GTEST_SKIP() << "operator new belongs to the sanitizer";
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<scene::BodyModel> bodies;
  const Eigen::Vector3d classes[3] = {{0.2, 0.2, 0.2}, {0.2, 0.2, 0.3}, {0.1, 0.2, 0.25}};
  for (int i = 0; i < 300; ++i) {
    const bool resting = i % 4 == 0;
    bodies.push_back(movingBody(
        "b" + std::to_string(i), 1.0 + i % 3, classes[i % 3],
        Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized(), {u(rng), u(rng), u(rng)},
        resting ? Eigen::Vector3d::Zero() : Eigen::Vector3d(u(rng), u(rng), u(rng)),
        resting ? Eigen::Vector3d::Zero() : Eigen::Vector3d(u(rng), u(rng), u(rng))));
  }
  for (const bool gravity : {false, true}) {
    auto w = makeWorld(
        makeScene(bodies, gravity ? Eigen::Vector3d(0, 0, -9.81) : Eigen::Vector3d::Zero()));
    const double dt = w->config().dt;
    for (int k = 0; k < 400; ++k) {
      const std::string body = "b" + std::to_string((k * 37) % 300);
      sim::WrenchInput in;
      in.body = body;
      in.frame = k % 2 ? "world" : body;
      in.F = cga::Force(Eigen::Vector3d(u(rng), u(rng), u(rng)));
      in.point = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1;
      in.couple = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1;
      in.start_time = (k % 50) * dt;
      in.duration = k % 7 == 0 ? -1.0 : (k % 11) * dt;
      ASSERT_TRUE(w->applyWrench(in).ok());
      sim::ImpulseInput j;
      j.body = body;
      j.frame = in.frame;
      j.J = cga::Force(Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1);
      j.start_time = (k % 60) * dt;
      ASSERT_TRUE(w->applyImpulse(j).ok());
    }
    w->step();  // the integrators' first step may set up per-body caches
    allocation_counter::g_allocations = 0;
    allocation_counter::g_counting = true;
    w->step(100);
    allocation_counter::g_counting = false;
    EXPECT_EQ(allocation_counter::g_allocations.load(), 0)
        << (gravity ? "with" : "without") << " gravity";
    EXPECT_EQ(w->queuedInputCount(), 0u);
  }
}

// Truth: the same contract at the bounds on inputs (world_config.h): a queue of 2000 inputs
// (a heap popped in place), until-cleared wrenches past the bounds on active wrenches per body
// and in all, refused in the step when they are due — nothing allocates.
TEST(WorldAllocation, StepAtTheInputBoundsDoesNotAllocate) {
  if (!CGA_RIGID_SIM_COUNT_ALLOCATIONS) GTEST_SKIP() << "operator new belongs to the sanitizer";
  std::vector<scene::BodyModel> bodies;
  for (int i = 0; i < 50; ++i)
    bodies.push_back(movingBody("b" + std::to_string(i), 1.0, {0.1, 0.2, 0.25},
                                Eigen::Quaterniond::Identity(), {0, 0, 0}, {0.3, 1.0, 2.0}));
  sim::WorldConfig config;
  config.max_queued_inputs = 2000;
  config.max_queued_inputs_per_body = 100;
  config.max_active_wrenches = 60;
  config.max_active_wrenches_per_body = 3;
  auto made = sim::World::create(makeScene(bodies), config);
  ASSERT_TRUE(made.ok()) << made.error();
  sim::World& w = *made.value();
  const double dt = config.dt;
  for (int k = 0; k < 2000; ++k) {
    const std::string body = "b" + std::to_string(k % 50);
    if (k % 2) {
      sim::WrenchInput in;
      in.body = body;
      in.F = cga::Force(Eigen::Vector3d(0.01 * (k % 7), 0.1, 0));
      in.point = Eigen::Vector3d(0, 0.1, 0);
      in.start_time = ((k / 50) % 80) * dt;
      in.duration = k % 3 ? -1.0 : 5 * dt;
      ASSERT_TRUE(w.applyWrench(in).ok()) << k;
    } else {
      sim::ImpulseInput j;
      j.body = body;
      j.J = cga::Force(Eigen::Vector3d(0.001 * (k % 5), 0, 0));
      j.start_time = ((k / 50) % 90) * dt;
      ASSERT_TRUE(w.applyImpulse(j).ok()) << k;
    }
  }
  EXPECT_FALSE(w.applyImpulse([] {
                  sim::ImpulseInput j;
                  j.body = "b0";
                  return j;
                }())
                   .ok());  // the queue is full
  w.step();                 // the integrators' first step may set up per-body caches
  allocation_counter::g_allocations = 0;
  allocation_counter::g_counting = true;
  w.step(100);
  allocation_counter::g_counting = false;
  EXPECT_EQ(allocation_counter::g_allocations.load(), 0);
  EXPECT_EQ(w.queuedInputCount(), 0u);
  EXPECT_GT(w.startRefusalCount(), 0u);
  EXPECT_LE(w.activeWrenchCount(), 60u);
}

// Truth: the same contract with the bodies split between two threads (sim/worker_pool.h): the
// pool's hand-over (mutex, condition variables) allocates nothing either.
TEST(WorldAllocation, ParallelStepDoesNotAllocate) {
  if (!CGA_RIGID_SIM_COUNT_ALLOCATIONS) GTEST_SKIP() << "operator new belongs to the sanitizer";
  std::vector<scene::BodyModel> bodies;
  for (int i = 0; i < 1000; ++i)
    bodies.push_back(movingBody("b" + std::to_string(i), 1.0, {0.1, 0.2, 0.25},
                                Eigen::Quaterniond::Identity(), {0, 0, 0}, {0.3, 1.0, 2.0}));
  sim::WorldConfig config;
  config.threads = 2;
  auto w = sim::World::create(makeScene(bodies), config);
  ASSERT_TRUE(w.ok()) << w.error();
  (*w)->step(2);  // the integrators' first steps set up per-body caches
  allocation_counter::g_allocations = 0;
  allocation_counter::g_counting = true;
  (*w)->step(50);
  allocation_counter::g_counting = false;
  EXPECT_EQ(allocation_counter::g_allocations.load(), 0);
}

// Truth: the same contract for articulated trees (stage_trees.cc): a fixed-base arm with its
// limits and a floating satellite step with held and timed efforts and wrenches on links, and the
// double pendulum — nothing allocates (operator new or malloc, which Eigen uses) once the first
// step has sized the integrators' scratch (the midpoint's extrapolation history and its saved
// slots for halving included).
TEST(WorldAllocation, TreeStepDoesNotAllocate) {
  if (!CGA_RIGID_SIM_COUNT_ALLOCATIONS) GTEST_SKIP() << "operator new belongs to the sanitizer";
  for (const char* name : {"double_pendulum", "arm7", "satellite"}) {
    for (const char* integrator : {"auto", "cga4", "rk4", "euler"}) {
      scene::SceneOptions options;
      auto scene = scene::loadUrdfFile(
          std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/" + name + ".urdf", options);
      ASSERT_TRUE(scene.ok()) << scene.error();
      sim::WorldConfig config;
      config.integrator = integrator;
      auto world = sim::World::create(std::move(scene.value()), config);
      ASSERT_TRUE(world.ok()) << world.error();
      sim::World& w = *world.value();
      const auto joints = w.jointStates();
      sim::JointEffortInput held;
      for (const auto& j : joints) {
        held.names.push_back(j.name);
        held.efforts.push_back(0.5);
      }
      held.stamp = 0.01;
      ASSERT_TRUE(w.setJointEfforts(held).ok());
      sim::TimedJointEffortInput timed;
      timed.joint = joints.back().name;
      timed.effort = -0.3;
      timed.start_time = 0.02;
      timed.duration = 0.03;
      ASSERT_TRUE(w.applyJointEffort(timed).ok());
      sim::WrenchInput wrench;
      wrench.body = w.bodyStates().back().name;
      wrench.F = cga::Force(Eigen::Vector3d(0.0, 1.0, 0.0));
      wrench.start_time = 0.015;
      wrench.duration = 0.02;
      ASSERT_TRUE(w.applyWrench(wrench).ok());
      w.step();  // the first step sizes the integrators' scratch
      allocation_counter::g_allocations = 0;
      allocation_counter::g_counting = true;
      w.step(100);
      allocation_counter::g_counting = false;
      EXPECT_EQ(allocation_counter::g_allocations.load(), 0) << name << " with " << integrator;
    }
  }
}

// A tree in contact: the rover stands on the ground plane and drives (eight wheel contacts every
// step, each tree side with its Jacobian and response). Once the first steps have sized the
// solver's rows and the tree's scratch, a step allocates nothing while the contacts stay as many.
TEST(WorldAllocation, TreeContactStepDoesNotAllocate) {
  if (!CGA_RIGID_SIM_COUNT_ALLOCATIONS) GTEST_SKIP() << "operator new belongs to the sanitizer";
  for (const char* integrator : {"auto", "rk4"}) {
    scene::SceneOptions options;
    options.gravity_W = {0, 0, -9.81};
    scene::ParamValue::Map chassis, initial;
    chassis["position"] = scene::ParamValue(std::vector<scene::ParamValue>{
        scene::ParamValue(0.0), scene::ParamValue(0.0), scene::ParamValue(0.16)});
    initial["chassis"] = scene::ParamValue(chassis);
    options.initial_state = scene::ParamValue(initial);
    auto scene =
        scene::loadUrdfFile(std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/rover.urdf", options);
    ASSERT_TRUE(scene.ok()) << scene.error();
    sim::WorldConfig config;
    config.integrator = integrator;
    config.ground_plane = sim::GroundPlane();
    auto world = sim::World::create(std::move(scene.value()), config);
    ASSERT_TRUE(world.ok()) << world.error();
    sim::World& w = *world.value();
    sim::JointEffortInput held;
    for (const auto& j : w.jointStates()) {
      held.names.push_back(j.name);
      held.efforts.push_back(0.5);
    }
    ASSERT_TRUE(w.setJointEfforts(held).ok());
    w.step(10);
    ASSERT_EQ(w.contacts().size(), 8u);
    allocation_counter::g_allocations = 0;
    allocation_counter::g_counting = true;
    w.step(100);
    allocation_counter::g_counting = false;
    EXPECT_EQ(allocation_counter::g_allocations.load(), 0) << integrator;
    EXPECT_EQ(w.contacts().size(), 8u);
  }
}

// A tree of mesh links in contact: the generated humanoid (test/common/real_like_robots.h, ten
// chamfered-box hulls) stands on its soles on the ground plane, and the pairs of its hulls whose
// bounding spheres overlap go to the narrow phase of two hulls (contact_convex_pairs.cc) every
// step. While the contacts stay as many, a step allocates nothing (through FCL's Convex it
// allocated 66 times a step: a visit list per support query and a libccd object per shape).
TEST(WorldAllocation, MeshTreeContactStepDoesNotAllocate) {
  if (!CGA_RIGID_SIM_COUNT_ALLOCATIONS) GTEST_SKIP() << "operator new belongs to the sanitizer";
  const std::string dir = test::meshFolder("alloc_humanoid");
  auto scene = scene::loadUrdfString(test::humanoidUrdf(dir), "robot", scene::SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  sim::WorldConfig config;
  config.threads = 1;
  config.ground_plane = sim::GroundPlane{-0.70, {}};
  auto world = sim::World::create(std::move(scene.value()), config);
  ASSERT_TRUE(world.ok()) << world.error();
  sim::World& w = *world.value();
  w.step(500);  // landed at ~0.05 s, standing on its soles from then until ~1.9 s (measured)
  const std::size_t standing = w.contacts().size();
  ASSERT_GT(standing, 0u);
  allocation_counter::g_allocations = 0;
  allocation_counter::g_counting = true;
  w.step(500);
  allocation_counter::g_counting = false;
  EXPECT_EQ(allocation_counter::g_allocations.load(), 0);
  EXPECT_EQ(w.contacts().size(), standing);
}

}  // namespace world_alloc_test
}  // namespace cga_rigid_sim
