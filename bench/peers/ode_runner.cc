// ODE peer runner (Debian libode-dev 0.16.2, double precision build: dDOUBLE).
//
// Setup: one dBody, dMassSetParameters(mass, CoM 0, I = diag(J1, J2, J3)),
// no geoms (so no collision at all), world and body damping 0, auto-disable
// off (world and body), max angular speed dInfinity (world and body),
// gravity from the case. The world torque is added with dBodyAddTorque before
// every step (ODE zeroes the force/torque accumulators after each step).
//
// Configs (the integrator/gyroscopic options ODE offers for a free body):
//   step              dWorldStep, gyroscopic mode on (ODE default), infinitesimal rotation update (default)
//   step_nogyro       dWorldStep, dBodySetGyroscopicMode(0)
//   quickstep         dWorldQuickStep, gyroscopic on
//   quickstep_nogyro  dWorldQuickStep, gyroscopic off
//   step_finiterot    dWorldStep, gyroscopic on, dBodySetFiniteRotationMode(1) with axis (0,0,0)
//                     (full finite-rotation orientation update)
//   quickstep_finiterot  same with dWorldQuickStep
//
// Timing: see peer_common.h -- median of 3 fresh runs of min(T/h, 20000)
// steps (dBodyAddTorque + dWorld[Quick]Step); errors from a separate full run
// to T = 100 s.
#include <memory>
#include <string>

#include <ode/ode.h>

#include "peer_common.h"

namespace {

using bench::BodyState;
using bench::Case;

struct OdeOptions {
  bool quick;
  bool gyro;
  bool finite_rotation;
};

class OdeSim : public bench::peers::PeerSim {
 public:
  OdeSim(const Case& c, double h, OdeOptions o) : h_(h), opt_(o), tau_(c.torque_world) {
    world_ = dWorldCreate();
    dWorldSetGravity(world_, c.gravity[0], c.gravity[1], c.gravity[2]);
    dWorldSetDamping(world_, 0, 0);
    dWorldSetAutoDisableFlag(world_, 0);
    dWorldSetMaxAngularSpeed(world_, dInfinity);
    body_ = dBodyCreate(world_);
    dMass m;
    dMassSetParameters(&m, c.mass, 0, 0, 0, c.inertia[0], c.inertia[1], c.inertia[2], 0, 0, 0);
    dBodySetMass(body_, &m);
    dBodySetAutoDisableFlag(body_, 0);
    dBodySetLinearDamping(body_, 0);
    dBodySetAngularDamping(body_, 0);
    dBodySetMaxAngularSpeed(body_, dInfinity);
    dBodySetGyroscopicMode(body_, o.gyro ? 1 : 0);
    dBodySetFiniteRotationMode(body_, o.finite_rotation ? 1 : 0);
    if (o.finite_rotation) dBodySetFiniteRotationAxis(body_, 0, 0, 0);
    dBodySetPosition(body_, 0, 0, 0);
    dQuaternion q = {1, 0, 0, 0};
    dBodySetQuaternion(body_, q);
    dBodySetLinearVel(body_, c.v0_world[0], c.v0_world[1], c.v0_world[2]);
    // body = world axes at t = 0, so the body angular velocity is the world one.
    dBodySetAngularVel(body_, c.w0_body[0], c.w0_body[1], c.w0_body[2]);
    has_torque_ = c.torque_world[0] != 0 || c.torque_world[1] != 0 || c.torque_world[2] != 0;
  }
  ~OdeSim() override { dWorldDestroy(world_); }

  void run(long steps) override {
    for (long i = 0; i < steps; ++i) {
      if (has_torque_) dBodyAddTorque(body_, tau_[0], tau_[1], tau_[2]);
      if (opt_.quick)
        dWorldQuickStep(world_, h_);
      else
        dWorldStep(world_, h_);
    }
  }
  BodyState state() override {
    BodyState s;
    const dReal* q = dBodyGetQuaternion(body_);
    const dReal* w = dBodyGetAngularVel(body_);
    const dReal* x = dBodyGetPosition(body_);
    const dReal* v = dBodyGetLinearVel(body_);
    for (int i = 0; i < 4; ++i) s.q[i] = q[i];
    for (int i = 0; i < 3; ++i) {
      s.w_world[i] = w[i];
      s.x[i] = x[i];
      s.v[i] = v[i];
    }
    return s;
  }

 private:
  double h_;
  OdeOptions opt_;
  std::array<double, 3> tau_;
  bool has_torque_ = false;
  dWorldID world_;
  dBodyID body_;
};

}  // namespace

int main(int argc, char** argv) {
  using bench::peers::PeerConfig;
  dInitODE2(0);
  auto make = [](OdeOptions o) {
    return [o](const Case& c, double h) -> std::unique_ptr<bench::peers::PeerSim> {
      return std::make_unique<OdeSim>(c, h, o);
    };
  };
  std::vector<PeerConfig> configs = {
      {"step", make({false, true, false})},
      {"step_nogyro", make({false, false, false})},
      {"quickstep", make({true, true, false})},
      {"quickstep_nogyro", make({true, false, false})},
      {"step_finiterot", make({false, true, true})},
      {"quickstep_finiterot", make({true, true, true})},
  };
  const std::string version = std::string("ODE 0.16 (") + dGetConfiguration() + ")";
  const int rc = bench::peers::runSweep("ode", version, configs, argc, argv);
  dCloseODE();
  return rc;
}
