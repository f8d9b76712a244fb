// Bullet peer runner (Debian libbullet-dev 3.24, the double-precision
// libraries: *-float64, BT_USE_DOUBLE_PRECISION).
//
// Setup: btDiscreteDynamicsWorld (btDefaultCollisionConfiguration,
// btCollisionDispatcher, btDbvtBroadphase, btSequentialImpulseConstraintSolver),
// one btRigidBody with local inertia (J1, J2, J3) and mass m; the collision
// shape (a 0.1 m sphere) only exists because btRigidBody needs one -- there is
// nothing to collide with. setDamping(0, 0), setSleepingThresholds(0, 0),
// DISABLE_DEACTIVATION, no CCD (ccd motion threshold 0 = default), gravity
// from the case; solver info m_maxGyroscopicForce raised from its default 100
// to 1e30 (it clamps the explicit gyroscopic force). The world torque is
// applied with applyTorque before every step (Bullet clears forces after
// each stepSimulation). Each step is stepSimulation(h, 0): maxSubSteps = 0
// means exactly one internal step of size h, no interpolation.
//
// Clamps we cannot switch off (hard-coded in Bullet 3.24): btRigidBody::
// integrateVelocities scales w down so that |w| h <= pi/2, and
// btTransformUtil::integrateTransform limits the rotation angle per step to
// pi/4. With the cases' max|w| (tennis_racket 2.3, thin_rod 100,
// symmetric_top 10.1, projectile 22, constant_torque 16.2 rad/s) the pi/4
// limit is active for thin_rod h >= 1e-2, symmetric_top h = 1e-1,
// projectile and constant_torque h >= 5e-2; the pi/2 one for thin_rod
// h >= 2e-2, projectile and constant_torque h = 1e-1.
//
// Configs = rigid-body gyroscopic flags:
//   gyro_implicit_body   BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY (Bullet's default)
//   gyro_implicit_world  BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD
//   gyro_explicit        BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT
//   no_gyro              none of them
//
// Timing: see peer_common.h -- median of 3 fresh runs of min(T/h, 20000)
// steps (applyTorque + stepSimulation); errors from a separate full run to
// T = 100 s.
#include <memory>
#include <string>

#include <btBulletDynamicsCommon.h>

#include "peer_common.h"

namespace {

using bench::BodyState;
using bench::Case;

class BulletSim : public bench::peers::PeerSim {
 public:
  BulletSim(const Case& c, double h, int gyro_flag) : h_(h) {
    config_ = std::make_unique<btDefaultCollisionConfiguration>();
    dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
    broadphase_ = std::make_unique<btDbvtBroadphase>();
    solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
    world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                                       config_.get());
    world_->setGravity(btVector3(c.gravity[0], c.gravity[1], c.gravity[2]));
    world_->getSolverInfo().m_maxGyroscopicForce = 1e30;
    shape_ = std::make_unique<btSphereShape>(0.1);
    btRigidBody::btRigidBodyConstructionInfo info(c.mass, nullptr, shape_.get(),
                                                  btVector3(c.inertia[0], c.inertia[1], c.inertia[2]));
    info.m_linearDamping = 0;
    info.m_angularDamping = 0;
    info.m_linearSleepingThreshold = 0;
    info.m_angularSleepingThreshold = 0;
    info.m_additionalDamping = false;
    body_ = std::make_unique<btRigidBody>(info);
    body_->setDamping(0, 0);
    body_->setSleepingThresholds(0, 0);
    body_->setActivationState(DISABLE_DEACTIVATION);
    body_->setCcdMotionThreshold(0);
    const int all = BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT | BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD |
                    BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY;
    body_->setFlags((body_->getFlags() & ~all) | gyro_flag);
    btTransform t;
    t.setIdentity();
    body_->setWorldTransform(t);
    body_->setCenterOfMassTransform(t);
    world_->addRigidBody(body_.get());  // also sets the body's gravity from the world
    body_->setLinearVelocity(btVector3(c.v0_world[0], c.v0_world[1], c.v0_world[2]));
    // body = world axes at t = 0, so the body angular velocity is the world one.
    body_->setAngularVelocity(btVector3(c.w0_body[0], c.w0_body[1], c.w0_body[2]));
    tau_ = btVector3(c.torque_world[0], c.torque_world[1], c.torque_world[2]);
    has_torque_ = !tau_.isZero();
  }
  ~BulletSim() override { world_->removeRigidBody(body_.get()); }

  void run(long steps) override {
    for (long i = 0; i < steps; ++i) {
      if (has_torque_) body_->applyTorque(tau_);
      world_->stepSimulation(h_, 0);
    }
  }
  BodyState state() override {
    BodyState s;
    const btTransform& t = body_->getCenterOfMassTransform();
    const btQuaternion q = t.getRotation();
    s.q = {q.w(), q.x(), q.y(), q.z()};
    const btVector3& w = body_->getAngularVelocity();
    const btVector3& v = body_->getLinearVelocity();
    const btVector3& x = t.getOrigin();
    for (int i = 0; i < 3; ++i) {
      s.w_world[i] = w[i];
      s.x[i] = x[i];
      s.v[i] = v[i];
    }
    return s;
  }

 private:
  double h_;
  btVector3 tau_;
  bool has_torque_ = false;
  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::unique_ptr<btSphereShape> shape_;
  std::unique_ptr<btRigidBody> body_;
};

}  // namespace

int main(int argc, char** argv) {
  using bench::peers::PeerConfig;
  auto make = [](int flag) {
    return [flag](const Case& c, double h) -> std::unique_ptr<bench::peers::PeerSim> {
      return std::make_unique<BulletSim>(c, h, flag);
    };
  };
  std::vector<PeerConfig> configs = {
      {"gyro_implicit_body", make(BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY)},
      {"gyro_implicit_world", make(BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD)},
      {"gyro_explicit", make(BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT)},
      {"no_gyro", make(0)},
  };
  const std::string version = "Bullet " + std::to_string(btGetVersion()) + " (double precision)";
  return bench::peers::runSweep("bullet", version, configs, argc, argv);
}
