// Bullet contact peer runner (Debian libbullet-dev 3.24, double-precision
// `bullet-float64` libraries): peer_contacts_bullet.
//
// Scene: btDiscreteDynamicsWorld (btDbvtBroadphase, btCollisionDispatcher,
// btSequentialImpulseConstraintSolver: Bullet's standard rigid-body setup),
// ground = btStaticPlaneShape (z = 0), bin walls = static btBoxShape,
// bodies = btSphereShape / btBoxShape with the exact mass and solid-shape
// inertia (calculateLocalInertia). One internal step of h per step:
// stepSimulation(h, 0).
//
// How the case parameters map to Bullet:
//  * friction and restitution are per object; Bullet combines a contact
//    pair by the PRODUCT (btManifoldResult::calculateCombinedFriction /
//    ...Restitution). So every object, ground and walls included, gets
//    sqrt(mu) and sqrt(e): every pair then has exactly mu and e.
//    Friction is Coulomb with two independent tangent directions (each
//    clamped to mu * normal impulse), rolling/spinning friction 0 (default).
//  * restitution: Bullet applies e to the normal velocity at the contact
//    only when it is above btContactSolverInfo::m_restitutionVelocityThreshold
//    (default 0.2 m/s; kept), below that the contact is inelastic.
//  * solver defaults kept: 10 iterations, split impulse on (penetration
//    recovery without adding energy), ERP 0.2, collision margin default
//    (0.04 m; for btBoxShape it lies inside the box, the box keeps its size).
//  * deactivation ("sleeping"): Bullet's default is on (bodies slower than
//    0.8 m/s and 1 rad/s for 2 s are frozen). Config `default` keeps it,
//    config `no_sleep` switches it off (DISABLE_DEACTIVATION), which shows
//    what the solver itself does in stack10 / pile1000 at rest.
//  * speculative contacts: by default (contact processing threshold = a
//    huge value) every contact point of the manifold, also those still at a
//    positive distance within the contact breaking threshold, goes to the
//    solver, whose target normal velocity is then e v_n - distance / h; the
//    approach is braked over the steps before the touch and little of the
//    restitution survives (see bounce). Config `no_speculative` sets the
//    processing threshold to 0 on every object (only touching contacts are
//    solved; Bullet's header notes positive-distance contacts help
//    stability) to show the other side of that trade-off.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "contact_common.h"

namespace {

using bench::contacts::BodyObs;
using bench::contacts::ContactCase;
using bench::contacts::Shape;

class BulletContactSim : public bench::contacts::ContactSim {
 public:
  BulletContactSim(const ContactCase& c, double h, bool sleep, bool speculative) : h_(h) {
    dispatcher_ = std::make_unique<btCollisionDispatcher>(&config_);
    world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), &broadphase_, &solver_, &config_);
    world_->setGravity(btVector3(c.gravity[0], c.gravity[1], c.gravity[2]));
    const double fr = std::sqrt(c.mu), rs = std::sqrt(c.e);
    auto addStatic = [&](btCollisionShape* shape, const btVector3& pos) {
      shapes_.emplace_back(shape);
      btRigidBody::btRigidBodyConstructionInfo ci(0.0, nullptr, shape, btVector3(0, 0, 0));
      ci.m_startWorldTransform.setIdentity();
      ci.m_startWorldTransform.setOrigin(pos);
      ci.m_friction = fr;
      ci.m_restitution = rs;
      statics_.emplace_back(new btRigidBody(ci));
      if (!speculative) statics_.back()->setContactProcessingThreshold(0);
      world_->addRigidBody(statics_.back().get());
    };
    addStatic(new btStaticPlaneShape(btVector3(0, 0, 1), 0), btVector3(0, 0, 0));
    if (c.bin.present) {
      const double w = c.bin.half_width, t = c.bin.wall_thickness, hh = 0.5 * c.bin.wall_height;
      const double o = w + 0.5 * t, l = w + t;
      addStatic(new btBoxShape(btVector3(0.5 * t, l, hh)), btVector3(o, 0, hh));
      addStatic(new btBoxShape(btVector3(0.5 * t, l, hh)), btVector3(-o, 0, hh));
      addStatic(new btBoxShape(btVector3(l, 0.5 * t, hh)), btVector3(0, o, hh));
      addStatic(new btBoxShape(btVector3(l, 0.5 * t, hh)), btVector3(0, -o, hh));
    }
    // One shape per distinct (shape, size) is enough; bodies share it.
    btCollisionShape* sphere = nullptr;
    btCollisionShape* box = nullptr;
    for (const auto& b : c.bodies) {
      btCollisionShape*& s = b.shape == Shape::Sphere ? sphere : box;
      if (!s) {
        s = b.shape == Shape::Sphere ? static_cast<btCollisionShape*>(new btSphereShape(b.size))
                                     : new btBoxShape(btVector3(b.size, b.size, b.size));
        shapes_.emplace_back(s);
      }
      btVector3 inertia;
      s->calculateLocalInertia(b.mass, inertia);
      btRigidBody::btRigidBodyConstructionInfo ci(b.mass, nullptr, s, inertia);
      ci.m_startWorldTransform.setIdentity();
      ci.m_startWorldTransform.setOrigin(btVector3(b.x0[0], b.x0[1], b.x0[2]));
      ci.m_friction = fr;
      ci.m_restitution = rs;
      bodies_.emplace_back(new btRigidBody(ci));
      btRigidBody* rb = bodies_.back().get();
      rb->setLinearVelocity(btVector3(b.v0[0], b.v0[1], b.v0[2]));
      if (!sleep) rb->setActivationState(DISABLE_DEACTIVATION);
      if (!speculative) rb->setContactProcessingThreshold(0);
      world_->addRigidBody(rb);
    }
  }
  ~BulletContactSim() override {
    for (auto& b : bodies_) world_->removeRigidBody(b.get());
    for (auto& b : statics_) world_->removeRigidBody(b.get());
  }
  void step(long n) override {
    for (long i = 0; i < n; ++i) world_->stepSimulation(h_, 0);
  }
  void observe(std::vector<BodyObs>* out) override {
    out->resize(bodies_.size());
    for (size_t i = 0; i < bodies_.size(); ++i) {
      const btRigidBody* rb = bodies_[i].get();
      const btVector3& x = rb->getCenterOfMassPosition();
      const btVector3& v = rb->getLinearVelocity();
      const btVector3& w = rb->getAngularVelocity();
      for (int k = 0; k < 3; ++k) {
        (*out)[i].x[k] = x[k];
        (*out)[i].v[k] = v[k];
        (*out)[i].w[k] = w[k];
      }
    }
  }

 private:
  double h_;
  btDefaultCollisionConfiguration config_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> statics_, bodies_;
};

}  // namespace

int main(int argc, char** argv) {
  auto make = [](bool sleep, bool speculative) {
    return [sleep, speculative](const ContactCase& c, double h) -> std::unique_ptr<bench::contacts::ContactSim> {
      return std::make_unique<BulletContactSim>(c, h, sleep, speculative);
    };
  };
  std::vector<bench::contacts::ContactConfig> configs = {
      {"default", make(true, true), {}, ""},
      {"no_sleep", make(false, true), {"pile1000"}, "time budget (pile1000 measured with Bullet's default config)"},
      {"no_speculative", make(true, false), {"pile1000"}, "time budget (pile1000 measured with Bullet's default config)"},
  };
  return bench::contacts::runContactSweep("bullet", "Bullet " + std::to_string(btGetVersion()), configs, argc,
                                          argv);
}
