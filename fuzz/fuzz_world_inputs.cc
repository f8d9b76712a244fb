// Fuzz target: the input validation of the core (sim/world.h, sim/input/inputs.h). The first byte
// chooses a small fixed scene and an integrator, a World is made from it, and the rest of the
// bytes are decoded into a sequence of calls — applyWrench, applyImpulse, setBodyState,
// setJointEfforts, applyJointEffort, step, clearWrenches, reset, spawnUrdf, deleteBody,
// getBodyState — with names picked among the scene's bodies, links, joints and a few wrong
// ones, and numbers that are often NaN, ±inf, huge, tiny or just over a limit.
//
// Checks after every call: no crash or sanitizer report; a refused call has a message and
// leaves the world bit-identical (step count, topology version, queue and wrench counts, every
// body's motor and bivelocity, every joint's position, velocity, effort and clamp count); the
// states of every body and joint, and the momentum reports, stay finite (after a step of the
// baselines euler and rk4, which blow up on fast spins, a non-finite state ends the input).
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/world.h"
#include "common/finite_scene.h"

using namespace cga_rigid_sim;

namespace {

// Free bodies with merged links and a static table; free bodies with collision shapes over a
// ground plane; a chain of continuous joints; an arm of revolute joints with effort limits.
const char* const kScenes[] = {"test/ros/bodies.urdf", "test/ros/contact_bodies.urdf",
                               "urdf/double_pendulum.urdf", "urdf/arm7.urdf"};
const char* const kIntegrators[] = {"auto", "exact", "cga2", "cga4", "euler", "rk4"};
constexpr int kMaxCalls = 32;
constexpr std::uint64_t kMaxSteps = 8;  // per input (speed: trees step slowly under ASan)

struct Fixture {
  std::vector<scene::Scene> scenes;
  std::string ball_urdf;  // spawned by spawnUrdf
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) fuzz::fail("cannot read " + path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Numbers a validator has to get right: non-finite, huge, tiny, negative zero, and the
// neighbours of the limits (max_force 1e6, max_impulse 1e4, kMaxPointDistance 1e9, the
// rotation rule's 1e-3, kMaxSteps 1e15 steps at dt 1e-3).
const double kSpecial[] = {0.0,
                           -0.0,
                           1.0,
                           -1.0,
                           0.5,
                           std::numeric_limits<double>::quiet_NaN(),
                           -std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::lowest(),
                           std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::min(),
                           std::numeric_limits<double>::epsilon(),
                           1e6,
                           std::nextafter(1e6, 2e6),
                           1e4,
                           std::nextafter(1e4, 2e4),
                           1e9,
                           std::nextafter(1e9, 2e9),
                           1e12,
                           std::nextafter(1e12, 2e12),
                           1.001,
                           0.999,
                           1e-3,
                           1e300,
                           -1e300,
                           0.0005,
                           2.5e-3};

class Decoder {
 public:
  explicit Decoder(FuzzedDataProvider& in) : in_(in) {}

  double number() {
    const std::uint8_t kind = in_.ConsumeIntegral<std::uint8_t>();
    if (kind < 96) return kSpecial[kind % (sizeof kSpecial / sizeof kSpecial[0])];
    if (kind < 192) return static_cast<double>(in_.ConsumeIntegralInRange<int>(-1000, 1000)) / 8;
    double d = 0.0;  // any bit pattern: every NaN payload, subnormals, …
    const std::uint64_t bits = in_.ConsumeIntegral<std::uint64_t>();
    std::memcpy(&d, &bits, sizeof d);
    return d;
  }
  Eigen::Vector3d vector() {
    const double x = number(), y = number(), z = number();
    return {x, y, z};
  }
  Eigen::Isometry3d pose() {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = vector();
    switch (in_.ConsumeIntegralInRange<int>(0, 2)) {
      case 0:  // a proper rotation, from a quaternion
        if (const Eigen::Vector4d q(number(), number(), number(), number()); q.norm() > 0.0)
          pose.linear() =
              Eigen::Quaterniond(q(3), q(0), q(1), q(2)).normalized().toRotationMatrix();
        break;
      case 1:  // any 3×3 matrix: mirrors, shears, NaN
        for (int k = 0; k < 9; ++k) pose.linear()(k / 3, k % 3) = number();
        break;
      default:
        break;
    }
    return pose;
  }
  // A body, link, joint or frame name of the scene, or a wrong one.
  std::string name(const std::vector<std::string>& names) {
    const std::uint8_t k = in_.ConsumeIntegral<std::uint8_t>();
    if (k < 200 && !names.empty()) return names[k % names.size()];
    if (k < 220) return "";
    if (k < 240) return "no_such_body";
    return in_.ConsumeRandomLengthString(16);
  }
  double stamp(double now, double dt) {
    const std::uint8_t k = in_.ConsumeIntegral<std::uint8_t>();
    if (k < 64) return 0.0;
    if (k < 128) return now + dt * in_.ConsumeIntegralInRange<int>(-2, 5);
    return number();
  }

 private:
  FuzzedDataProvider& in_;
};

// CGA_RIGID_SIM_FUZZ_TRACE=1 prints every call and its outcome (to read a reproducer).
bool trace() {
  static const bool on = std::getenv("CGA_RIGID_SIM_FUZZ_TRACE") != nullptr;
  return on;
}

// Numbers in full (17 digits): a reproducer's calls can be typed into a regression test.
std::string str(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}
std::string str(const Eigen::Vector3d& v) {
  return "(" + str(v.x()) + " " + str(v.y()) + " " + str(v.z()) + ")";
}

// Everything a refused call must leave as it was, as bytes.
std::string snapshot(const sim::World& world) {
  std::string out;
  auto add = [&out](const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); };
  const std::uint64_t counts[4] = {world.stepCount(), world.topologyVersion(),
                                   world.queuedInputCount(), world.activeWrenchCount()};
  add(counts, sizeof counts);
  // Every moving body's motor and bivelocity (tree bodies included: the trees write them), as
  // World::data() holds them (cheaper than the reports, which make isometries).
  for (const sim::MovingBodyData& b : world.data().bodies) {
    const auto m = b.state.M_WB.coefficients();
    const auto o = b.state.omega_B.coefficients();
    add(m.data(), sizeof(double) * m.size());
    add(o.data(), sizeof(double) * o.size());
  }
  for (const sim::JointStateReport& j : world.jointStates()) {
    const double q[3] = {j.position, j.velocity, j.effort};
    add(q, sizeof q);
    add(&j.clamped_steps, sizeof j.clamped_steps);
  }
  return out;
}

bool finite(const sim::World& world) {
  for (const sim::MovingBodyData& b : world.data().bodies)
    if (!b.state.allFinite()) return false;
  for (const sim::JointStateReport& j : world.jointStates())
    if (!std::isfinite(j.position) || !std::isfinite(j.velocity)) return false;
  for (const sim::MomentumReport& m : world.momentum())
    if (!std::isfinite(m.kinetic_energy) || !std::isfinite(m.potential_energy)) return false;
  return true;
}

void checkFinite(const sim::World& world, const std::string& after) {
  const auto& bodies = world.data().bodies;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (!bodies[i].state.allFinite())
      fuzz::fail("moving body " + std::to_string(i) + " not finite after " + after);
  for (const sim::JointStateReport& j : world.jointStates())
    if (!std::isfinite(j.position) || !std::isfinite(j.velocity) || !std::isfinite(j.effort))
      fuzz::fail("joint '" + j.name + "' not finite after " + after);
  for (const sim::MomentumReport& m : world.momentum())
    if (!m.linear.allFinite() || !m.angular.allFinite() || !std::isfinite(m.kinetic_energy) ||
        !std::isfinite(m.potential_energy))
      fuzz::fail("momentum of '" + m.body + "' not finite after " + after);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  for (const char* file : kScenes) {
    const std::string path = std::string(CGA_RIGID_SIM_SOURCE_DIR "/") + file;
    Result<scene::Scene> s = scene::loadUrdfFile(path, scene::SceneOptions());
    if (!s.ok()) fuzz::fail("cannot load " + path + ": " + s.error());
    fixture().scenes.push_back(std::move(*s));
  }
  fixture().ball_urdf = readFile(CGA_RIGID_SIM_SOURCE_DIR "/test/ros/ball.urdf");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  Decoder decode(in);
  const std::uint8_t setup = in.ConsumeIntegral<std::uint8_t>();
  const std::size_t scene_index = setup % fixture().scenes.size();
  sim::WorldConfig config;
  config.integrator = kIntegrators[(setup / 4) % 6];
  if (scene_index == 1) config.ground_plane = sim::GroundPlane();
  Result<std::unique_ptr<sim::World>> created =
      sim::World::create(fixture().scenes[scene_index], config);
  if (!created.ok()) {  // e.g. 'exact' has no form for trees: a refusal, with a message
    if (created.error().empty()) fuzz::fail("World::create refused without a message");
    return 0;
  }
  sim::World& world = **created;
  if (trace())
    std::fprintf(stderr, "scene %s, integrator %s\n", kScenes[scene_index],
                 config.integrator.c_str());

  // Names the decoder picks from: bodies, links (including the world frame), joints.
  std::vector<std::string> bodies, frames, joints;
  auto collectNames = [&] {
    bodies.clear();
    frames = {config.world_frame};
    joints.clear();
    for (const scene::BodyModel& b : world.scene().bodies) {
      bodies.push_back(b.name);
      for (const scene::LinkFrame& l : b.links) frames.push_back(l.link);
    }
    for (const scene::JointModel& j : world.scene().joints) joints.push_back(j.name);
  };
  collectNames();

  std::uint64_t steps = 0;
  for (int call = 0; call < kMaxCalls && in.remaining_bytes() > 0; ++call) {
    const std::string before = snapshot(world);
    const double dt = config.dt, now = world.time();
    const int op = in.ConsumeIntegralInRange<int>(0, 10);
    Result<bool> result = true;
    std::string what, detail;
    switch (op) {
      case 0: {
        what = "applyWrench";
        sim::WrenchInput w;
        w.body = decode.name(bodies);
        w.frame = decode.name(frames);
        w.F.f = decode.vector();
        w.F.alpha = decode.number();
        w.point = decode.vector();
        w.couple = decode.vector();
        w.start_time = decode.stamp(now, dt);
        w.duration = decode.number();
        detail = w.body + " in '" + w.frame + "' f " + str(w.F.f) + " alpha " + str(w.F.alpha) +
                 " at " + str(w.point) + " couple " + str(w.couple) + " start " +
                 str(w.start_time) + " duration " + str(w.duration);
        result = world.applyWrench(w);
        break;
      }
      case 1: {
        what = "applyImpulse";
        sim::ImpulseInput j;
        j.body = decode.name(bodies);
        j.frame = decode.name(frames);
        j.J.f = decode.vector();
        j.J.alpha = decode.number();
        j.point = decode.vector();
        j.angular = decode.vector();
        j.start_time = decode.stamp(now, dt);
        detail = j.body + " in '" + j.frame + "' J " + str(j.J.f) + " alpha " + str(j.J.alpha) +
                 " at " + str(j.point) + " L " + str(j.angular) + " start " + str(j.start_time);
        result = world.applyImpulse(j);
        break;
      }
      case 2: {
        what = "setBodyState";
        const std::string body = decode.name(bodies);
        const Eigen::Isometry3d pose = decode.pose();
        const Eigen::Vector3d v = decode.vector(), w = decode.vector();
        detail = body + " x " + str(pose.translation()) + " v " + str(v) + " w " + str(w);
        result = world.setBodyState(body, pose, v, w);
        break;
      }
      case 3: {
        what = "setJointEfforts";
        sim::JointEffortInput e;
        const int n = in.ConsumeIntegralInRange<int>(0, 4);
        for (int k = 0; k < n; ++k) e.names.push_back(decode.name(joints));
        const int m = in.ConsumeBool() ? n : in.ConsumeIntegralInRange<int>(0, 4);
        for (int k = 0; k < m; ++k) e.efforts.push_back(decode.number());
        e.stamp = decode.stamp(now, dt);
        result = world.setJointEfforts(e);
        break;
      }
      case 4: {
        what = "applyJointEffort";
        sim::TimedJointEffortInput e;
        e.joint = decode.name(joints);
        e.effort = decode.number();
        e.start_time = decode.stamp(now, dt);
        e.duration = decode.number();
        result = world.applyJointEffort(e);
        break;
      }
      case 5: {
        what = "step";
        const std::uint64_t n = in.ConsumeIntegralInRange<std::uint64_t>(1, 4);
        if (steps + n > kMaxSteps) return 0;
        world.step(n);
        steps += n;
        break;
      }
      case 6:
        what = "clearWrenches";
        world.clearWrenches();
        break;
      case 7:
        what = "reset";
        world.reset();
        break;
      case 8: {
        what = "spawnUrdf";
        const std::string name = decode.name(frames);
        const Eigen::Isometry3d pose = decode.pose();
        const Eigen::Vector3d v = decode.vector(), w = decode.vector();
        result = world.spawnUrdf(name, fixture().ball_urdf, pose, v, w);
        if (result.ok()) collectNames();
        break;
      }
      case 9:
        what = "deleteBody";
        result = world.deleteBody(decode.name(bodies));
        if (result.ok()) collectNames();
        break;
      default: {
        what = "getBodyState";
        const Result<sim::BodyStateReport> report = world.getBodyState(decode.name(frames));
        if (report.ok() && !report->state.allFinite()) fuzz::fail("getBodyState not finite");
        if (snapshot(world) != before) fuzz::fail("getBodyState changed the world");
        break;
      }
    }
    if (trace())
      std::fprintf(stderr, "call %d: %s %s -> %s\n", call, what.c_str(), detail.c_str(),
                   result.ok() ? "accepted" : result.error().c_str());
    if (!result.ok()) {
      if (result.error().empty()) fuzz::fail(what + " refused without a message");
      if (snapshot(world) != before)
        fuzz::fail(what + " was refused (" + result.error() + ") but changed the world");
    }
    // The baselines euler and rk4 blow up on fast spins (doc/integrators.md; the bounds allow
    // 1e9 rad/s at any dt): a step that overflows ends the input for them, not for the others.
    if (what == "step" && (config.integrator == "euler" || config.integrator == "rk4") &&
        !finite(world))
      return 0;
    checkFinite(world, what);
  }
  return 0;
}
