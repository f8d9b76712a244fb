// Bullet articulated runner (Debian libbullet-dev 3.24, the double-precision libraries):
// peer_articulated_bullet.
//
// Model: a btMultiBody (Featherstone, reduced coordinates) built in code from the case
// (bench/cases/articulated_cases.h). Fixed base at the world origin (its mass 1 and inertia
// (1, 1, 1) never enter: a fixed base does not move), or a floating base with the case's mass
// and inertia (its CoM at its origin) and the initial setBaseVel/setBaseOmega (world); per link
// setupRevolute with the link's
// mass and diagonal inertia, parent index, rotParentToThis = the inverse of the joint origin
// rotation (Bullet's argument rotates parent-frame coordinates into the link frame), the axis
// in the link frame, parentComToThisPivotOffset = joint origin - parent's CoM (parent frame; the
// base's "CoM" is the world origin) and thisPivotToThisComOffset = the link's CoM. Bullet's
// link frame is then the case's link frame moved to the CoM, with the same axes, so the
// diagonal inertia is the case's. No colliders. Linear and angular damping 0 (Bullet's
// default is 0.04 for both), max coordinate velocity 1e30 (default 100 rad/s, a clamp),
// gyroscopic term on (default), no sleeping, finalizeMultiDof, then joint positions and
// velocities (q0, qd0). World: btMultiBodyDynamicsWorld with btMultiBodyConstraintSolver, the
// case's gravity; each step stepSimulation(h, 0) (exactly one internal step of h).
//
// Configs:
//   featherstone      Bullet's default: articulated-body accelerations, then qd += h qdd,
//                     q += h qd_new (semi-implicit Euler).
//   featherstone_rk4  btMultiBody::useRK4Integration(true): the classical RK4 path of
//                     btMultiBodyDynamicsWorld::solveExternalForces (four articulated-body
//                     evaluations per step). Its errors equal MuJoCo RK4's to the printed digits.
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <Eigen/Geometry>
#include <memory>
#include <stdexcept>
#include <string>

#include "articulated_common.h"

namespace {

using bench::articulated::ArticulatedCase;
using bench::articulated::JointSpec;

btVector3 bt(const std::array<double, 3>& a) { return btVector3(a[0], a[1], a[2]); }

class BulletArticulated : public bench::articulated::ArticulatedSim {
 public:
  BulletArticulated(const ArticulatedCase& c, double h, bool rk4) : h_(h) {
    config_ = std::make_unique<btDefaultCollisionConfiguration>();
    dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
    broadphase_ = std::make_unique<btDbvtBroadphase>();
    solver_ = std::make_unique<btMultiBodyConstraintSolver>();
    world_ = std::make_unique<btMultiBodyDynamicsWorld>(dispatcher_.get(), broadphase_.get(),
                                                        solver_.get(), config_.get());
    world_->setGravity(bt(c.gravity));
    const bool fl = c.base.floating;
    // Bullet's base frame is its CoM frame: a floating base must have its CoM at its origin.
    if (fl && (c.base.com[0] != 0 || c.base.com[1] != 0 || c.base.com[2] != 0))
      throw std::runtime_error("bullet runner: floating base with its CoM off its origin");
    mb_ = std::make_unique<btMultiBody>(c.n(), fl ? c.base.mass : 1.0,
                                        fl ? bt(c.base.inertia_diag) : btVector3(1, 1, 1), !fl,
                                        false);
    btTransform base_pose;
    base_pose.setIdentity();
    mb_->setBaseWorldTransform(base_pose);
    for (int i = 0; i < c.n(); ++i) {
      const JointSpec& j = c.joints[i];
      Eigen::Matrix3d R;
      for (int r = 0; r < 3; ++r)
        for (int s = 0; s < 3; ++s) R(r, s) = j.origin_R[3 * r + s];
      const Eigen::Quaterniond qinv(R.transpose());
      const btVector3 parent_com = j.parent >= 0 ? bt(c.joints[j.parent].com) : btVector3(0, 0, 0);
      mb_->setupRevolute(i, j.mass, bt(j.inertia_diag), j.parent,
                         btQuaternion(qinv.x(), qinv.y(), qinv.z(), qinv.w()), bt(j.axis),
                         bt(j.origin_xyz) - parent_com, bt(j.com), true);
    }
    mb_->setLinearDamping(0);
    mb_->setAngularDamping(0);
    mb_->setMaxCoordinateVelocity(1e30);
    mb_->setUseGyroTerm(true);
    mb_->setCanSleep(false);
    mb_->setHasSelfCollision(false);
    mb_->useRK4Integration(rk4);
    mb_->finalizeMultiDof();
    for (int i = 0; i < c.n(); ++i) {
      mb_->setJointPos(i, c.q0[i]);
      mb_->setJointVel(i, c.qd0[i]);
    }
    if (fl) {
      mb_->setBaseVel(bt(c.base.v0));
      mb_->setBaseOmega(bt(c.base.w0));
    }
    floating_ = fl;
    world_->addMultiBody(mb_.get());
  }
  ~BulletArticulated() override { world_->removeMultiBody(mb_.get()); }

  void step(long n) override {
    for (long i = 0; i < n; ++i) world_->stepSimulation(h_, 0);
  }
  void joints(std::vector<double>* q, std::vector<double>* qd) override {
    const int n = mb_->getNumLinks();
    q->resize(n);
    qd->resize(n);
    for (int i = 0; i < n; ++i) {
      (*q)[i] = mb_->getJointPos(i);
      (*qd)[i] = mb_->getJointVel(i);
    }
  }
  bool base(bench::articulated::BaseState<double>* b) override {
    if (!floating_) return false;
    const btTransform t = mb_->getBaseWorldTransform();
    const btMatrix3x3& R = t.getBasis();
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s) b->R(r, s) = R[r][s];
    for (int i = 0; i < 3; ++i) {
      b->p(i) = t.getOrigin()[i];
      b->w(i) = mb_->getBaseOmega()[i];
      b->v(i) = mb_->getBaseVel()[i];
    }
    return true;
  }

 private:
  bool floating_ = false;
  double h_;
  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btMultiBodyConstraintSolver> solver_;
  std::unique_ptr<btMultiBodyDynamicsWorld> world_;
  std::unique_ptr<btMultiBody> mb_;
};

}  // namespace

int main(int argc, char** argv) {
  auto make = [](bool rk4) {
    return [rk4](const ArticulatedCase& c,
                 double h) -> std::unique_ptr<bench::articulated::ArticulatedSim> {
      return std::make_unique<BulletArticulated>(c, h, rk4);
    };
  };
  std::vector<bench::articulated::ArticulatedConfig> configs = {
      {"featherstone", make(false)},
      {"featherstone_rk4", make(true)},
  };
  const std::string version = "Bullet " + std::to_string(btGetVersion()) + " (double precision)";
  return bench::articulated::runArticulatedSweep("bullet", version, configs, argc, argv);
}
