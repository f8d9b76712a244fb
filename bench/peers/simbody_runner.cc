// Simbody peer runner (Debian libsimbody-dev 3.7).
//
// Setup: MultibodySystem + SimbodyMatterSubsystem + GeneralForceSubsystem;
// one MobilizedBody::Free (quaternion orientation coordinates, Simbody's
// default) carrying Body::Rigid(MassProperties(m, CoM 0, Inertia(J1, J2, J3)));
// Force::UniformGravity with the case gravity; Force::ConstantTorque (a torque
// fixed in Ground axes, i.e. the world torque) when the case has one. No
// damping elements, no contact subsystem. Initial state via setQToFitTransform
// (identity), setUToFitAngularVelocity(w0) and setUToFitLinearVelocity(v0).
//
// Integrators: each Simbody fixed-step-capable integrator, with
// setFixedStepSize(h) (min = max = initial step = h: error-controlled methods
// then accept every step, their error estimate only decides whether the
// quaternion/constraint projection is attempted), setAllowInterpolation(false)
// so the state at the report time is a real step, default accuracy (1e-3) and
// constraint tolerance. run(n) = one integ.stepTo(t + n h) call: Simbody's own
// stepping loop. CPodesIntegrator (variable-step BDF/Adams) has no meaningful
// fixed-step mode and is not measured.
//
// Time budget (the whole peer sweep must fit in ~6 min on 2 cores): Simbody
// costs ~14-80 us of CPU per step here (medians: SemiExplicitEuler 14,
// ExplicitEuler ~17, Verlet 23, RungeKutta3 37, RungeKuttaMerson 59), i.e.
// 10-60x the other engines; h = 1e-4 alone would take 1e6 steps x 5 cases =
// 70-300 s per integrator. The default sweep below costs ~2.7 min of CPU. So, unlike the other runners, the default Simbody sweep
//   * uses h in {1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 1e-1} (7 sizes, 2 decades),
//   * times min(T/h, 2000) steps (median of 3 fresh runs; errors still from a
//     separate full run to T = 100 s, see peer_common.h),
//   * runs SemiExplicitEuler, Verlet, RungeKutta3 and RungeKuttaMerson; the
//     other four integrators (ExplicitEuler, SemiExplicitEuler2, RungeKutta2,
//     RungeKuttaFeldberg) run with --all-configs (or --configs);
//   * skips h < 1e-3 even if a caller passes them with --hs (budget floor,
//     noted in the log); --min-h 0 lifts it.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include <Simbody.h>

#include "peer_common.h"

namespace {

using bench::BodyState;
using bench::Case;

enum class Method { ExplicitEuler, SemiExplicitEuler, SemiExplicitEuler2, Verlet, RK2, RK3, RKMerson, RKFeldberg };

class SimbodySim : public bench::peers::PeerSim {
 public:
  SimbodySim(const Case& c, double h, Method method)
      : matter_(system_), forces_(system_), h_(h) {
    SimTK::Force::UniformGravity(forces_, matter_, SimTK::Vec3(c.gravity[0], c.gravity[1], c.gravity[2]), 0);
    const SimTK::Body::Rigid info(SimTK::MassProperties(
        c.mass, SimTK::Vec3(0), SimTK::Inertia(c.inertia[0], c.inertia[1], c.inertia[2])));
    body_ = SimTK::MobilizedBody::Free(matter_.Ground(), SimTK::Transform(), info, SimTK::Transform());
    if (c.torque_world[0] != 0 || c.torque_world[1] != 0 || c.torque_world[2] != 0)
      SimTK::Force::ConstantTorque(forces_, body_,
                                   SimTK::Vec3(c.torque_world[0], c.torque_world[1], c.torque_world[2]));
    SimTK::State s = system_.realizeTopology();
    body_.setQToFitTransform(s, SimTK::Transform());
    // body = world axes at t = 0, so the body angular velocity is the world one.
    body_.setUToFitAngularVelocity(s, SimTK::Vec3(c.w0_body[0], c.w0_body[1], c.w0_body[2]));
    body_.setUToFitLinearVelocity(s, SimTK::Vec3(c.v0_world[0], c.v0_world[1], c.v0_world[2]));
    switch (method) {
      case Method::ExplicitEuler: integ_ = std::make_unique<SimTK::ExplicitEulerIntegrator>(system_); break;
      case Method::SemiExplicitEuler:
        integ_ = std::make_unique<SimTK::SemiExplicitEulerIntegrator>(system_, h);
        break;
      case Method::SemiExplicitEuler2:
        integ_ = std::make_unique<SimTK::SemiExplicitEuler2Integrator>(system_);
        break;
      case Method::Verlet: integ_ = std::make_unique<SimTK::VerletIntegrator>(system_); break;
      case Method::RK2: integ_ = std::make_unique<SimTK::RungeKutta2Integrator>(system_); break;
      case Method::RK3: integ_ = std::make_unique<SimTK::RungeKutta3Integrator>(system_); break;
      case Method::RKMerson: integ_ = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system_); break;
      case Method::RKFeldberg: integ_ = std::make_unique<SimTK::RungeKuttaFeldbergIntegrator>(system_); break;
    }
    integ_->setFixedStepSize(h);
    integ_->setAllowInterpolation(false);
    integ_->initialize(s);
  }

  void run(long steps) override {
    done_ += steps;
    const double target = static_cast<double>(done_) * h_;
    // The first stepTo() after initialize() returns at once (start of the
    // continuous interval), hence the loop.
    while (integ_->getTime() < target) {
      const SimTK::Integrator::SuccessfulStepStatus st = integ_->stepTo(target);
      if (st == SimTK::Integrator::EndOfSimulation) throw std::runtime_error("Simbody: end of simulation");
    }
  }

  BodyState state() override {
    const SimTK::State& s = integ_->getState();
    system_.realize(s, SimTK::Stage::Velocity);
    BodyState out;
    const SimTK::Quaternion q = body_.getBodyRotation(s).convertRotationToQuaternion();
    for (int i = 0; i < 4; ++i) out.q[i] = q[i];
    const SimTK::Vec3& w = body_.getBodyAngularVelocity(s);
    const SimTK::Vec3& x = body_.getBodyOriginLocation(s);
    const SimTK::Vec3& v = body_.getBodyOriginVelocity(s);
    for (int i = 0; i < 3; ++i) {
      out.w_world[i] = w[i];
      out.x[i] = x[i];
      out.v[i] = v[i];
    }
    return out;
  }

 private:
  SimTK::MultibodySystem system_;
  SimTK::SimbodyMatterSubsystem matter_;
  SimTK::GeneralForceSubsystem forces_;
  SimTK::MobilizedBody::Free body_;
  std::unique_ptr<SimTK::Integrator> integ_;
  double h_;
  long done_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  using bench::peers::PeerConfig;
  auto make = [](Method m) {
    return [m](const Case& c, double h) -> std::unique_ptr<bench::peers::PeerSim> {
      return std::make_unique<SimbodySim>(c, h, m);
    };
  };
  std::vector<PeerConfig> configs = {
      {"SemiExplicitEuler", make(Method::SemiExplicitEuler), true},
      {"Verlet", make(Method::Verlet), true},
      {"RungeKutta3", make(Method::RK3), true},
      {"RungeKuttaMerson", make(Method::RKMerson), true},
      {"ExplicitEuler", make(Method::ExplicitEuler), false},
      {"SemiExplicitEuler2", make(Method::SemiExplicitEuler2), false},
      {"RungeKutta2", make(Method::RK2), false},
      {"RungeKuttaFeldberg", make(Method::RKFeldberg), false},
  };
  bench::peers::SweepDefaults defaults;
  defaults.hs = {1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 1e-1};
  defaults.timing_steps = 2000;
  defaults.min_h = 1e-3;
  int major = 0, minor = 0, build = 0;
  SimTK_version_SimTKcommon(&major, &minor, &build);
  const std::string version =
      "Simbody " + std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(build);
  return bench::peers::runSweep("simbody", version, configs, argc, argv, defaults);
}
