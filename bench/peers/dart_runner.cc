// DART peer runner (Debian libdart-dev 6.12.1).
//
// Setup: a Skeleton with one FreeJoint + BodyNode, Inertia(mass, CoM 0,
// diag(J1, J2, J3)) (body frame = principal frame at the CoM), no shape
// nodes (so nothing can collide), joint damping/spring/friction 0 (defaults),
// no position limits; world gravity from the case. The world torque is set
// with BodyNode::setExtTorque(tau, isLocal = false) before every step
// (World::step clears external forces after each step). FreeJoint velocity =
// spatial velocity of the body in body coordinates (angular, linear); at t = 0
// body = world axes so (w0_body, v0_world) is used directly.
//
// Configs:
//   world_step   dart::simulation::World::step() -- the only time stepping
//                World has in 6.12: semi-implicit Euler (velocities updated
//                from the forward dynamics, then positions with the new
//                velocities via the FreeJoint exponential map), plus its
//                (here idle) collision detection and constraint solver.
//   Not measured: DART 6.12 has no other time stepping for a World. The
//   headers do ship dart::integration::{Euler,SemiImplicitEuler,RK4}Integrator,
//   but nothing in DART uses them (World::step does not take an integrator,
//   no class implements their IntegrableSystem interface) and in 6.12
//   RK4Integrator is even abstract (integratePos/integrateVel are pure virtual
//   and not overridden), so there is no DART RK4 to configure.
//
// Timing: see peer_common.h -- median of 3 fresh runs of min(T/h, 20000)
// steps; errors from a separate full run to T = 100 s.
#include <memory>
#include <string>

#include <dart/config.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/Inertia.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/simulation/World.hpp>

#include "peer_common.h"

namespace {

using bench::BodyState;
using bench::Case;

// Skeleton + one free body.
struct FreeBody {
  dart::dynamics::SkeletonPtr skel;
  dart::dynamics::FreeJoint* joint = nullptr;
  dart::dynamics::BodyNode* body = nullptr;
  Eigen::Vector3d tau;

  explicit FreeBody(const Case& c) {
    skel = dart::dynamics::Skeleton::create("free_body");
    auto pair = skel->createJointAndBodyNodePair<dart::dynamics::FreeJoint>();
    joint = pair.first;
    body = pair.second;
    Eigen::Matrix3d I = Eigen::Vector3d(c.inertia[0], c.inertia[1], c.inertia[2]).asDiagonal();
    body->setInertia(dart::dynamics::Inertia(c.mass, Eigen::Vector3d::Zero(), I));
    skel->setGravity(Eigen::Vector3d(c.gravity[0], c.gravity[1], c.gravity[2]));
    Eigen::Matrix<double, 6, 1> v;
    v << c.w0_body[0], c.w0_body[1], c.w0_body[2], c.v0_world[0], c.v0_world[1], c.v0_world[2];
    skel->setPositions(Eigen::Matrix<double, 6, 1>::Zero());
    skel->setVelocities(v);
    tau = Eigen::Vector3d(c.torque_world[0], c.torque_world[1], c.torque_world[2]);
  }

  BodyState state() const {
    BodyState s;
    const Eigen::Isometry3d& T = body->getWorldTransform();
    const Eigen::Quaterniond q(T.linear());
    s.q = {q.w(), q.x(), q.y(), q.z()};
    const Eigen::Vector3d w = body->getAngularVelocity();
    const Eigen::Vector3d x = body->getCOM();
    const Eigen::Vector3d v = body->getCOMLinearVelocity();
    for (int i = 0; i < 3; ++i) {
      s.w_world[i] = w[i];
      s.x[i] = x[i];
      s.v[i] = v[i];
    }
    return s;
  }
};

class DartWorldSim : public bench::peers::PeerSim {
 public:
  DartWorldSim(const Case& c, double h) : fb_(c) {
    world_ = dart::simulation::World::create();
    world_->setGravity(Eigen::Vector3d(c.gravity[0], c.gravity[1], c.gravity[2]));
    world_->setTimeStep(h);
    world_->addSkeleton(fb_.skel);
    has_torque_ = !fb_.tau.isZero();
  }
  void run(long steps) override {
    for (long i = 0; i < steps; ++i) {
      if (has_torque_) fb_.body->setExtTorque(fb_.tau, false);
      world_->step();
    }
  }
  BodyState state() override { return fb_.state(); }

 private:
  FreeBody fb_;
  dart::simulation::WorldPtr world_;
  bool has_torque_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  using bench::peers::PeerConfig;
  std::vector<PeerConfig> configs = {
      {"world_step",
       [](const Case& c, double h) -> std::unique_ptr<bench::peers::PeerSim> {
         return std::make_unique<DartWorldSim>(c, h);
       }},
  };
  return bench::peers::runSweep("dart", std::string("DART ") + DART_VERSION, configs, argc, argv);
}
