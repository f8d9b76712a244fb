// DART articulated runner (Debian libdart-dev 6.12.1): peer_articulated_dart.
//
// Model: built in code from the case (bench/cases/articulated_cases.h): the Debian package has
// no dart-utils-urdf (no DartLoader). One Skeleton, per link a RevoluteJoint + BodyNode pair:
// joint T_ParentBodyToJoint = the case's joint origin, T_ChildBodyToJoint = identity (the
// link frame is the joint frame at q = 0), axis = the case's axis; BodyNode inertia
// Inertia(mass, CoM, diag moments about the CoM), no shape nodes (nothing can collide);
// joint damping, spring stiffness, Coulomb friction and armature 0 and position limits not
// enforced (DART's defaults). A floating base is a FreeJoint + BodyNode at the root (its
// velocity (w, v) in body coordinates, = world axes at the identity start). World gravity =
// the case's; positions and velocities (q0, qd0) set on the skeleton.
//
// Config: world_step, dart::simulation::World::step(): semi-implicit Euler on the generalised
// coordinates (articulated-body forward dynamics, then q += h qd_new), with its (here idle)
// collision detection and constraint solver. DART 6.12 has no other World stepping
// (peers/README.md, dart_runner.cc).
#include <dart/config.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/Inertia.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/simulation/World.hpp>
#include <memory>
#include <string>

#include "articulated_common.h"

namespace {

using bench::articulated::ArticulatedCase;
using bench::articulated::JointSpec;

class DartArticulated : public bench::articulated::ArticulatedSim {
 public:
  DartArticulated(const ArticulatedCase& c, double h) {
    skel_ = dart::dynamics::Skeleton::create(c.name);
    std::vector<dart::dynamics::BodyNode*> bodies;
    dart::dynamics::BodyNode* base = nullptr;
    if (c.base.floating) {
      auto pair = skel_->createJointAndBodyNodePair<dart::dynamics::FreeJoint>(
          nullptr, dart::dynamics::FreeJoint::Properties(),
          dart::dynamics::BodyNode::AspectProperties(c.base.link));
      const auto& b = c.base;
      const Eigen::Matrix3d I =
          Eigen::Vector3d(b.inertia_diag[0], b.inertia_diag[1], b.inertia_diag[2]).asDiagonal();
      pair.second->setInertia(
          dart::dynamics::Inertia(b.mass, Eigen::Vector3d(b.com[0], b.com[1], b.com[2]), I));
      base = pair.second;
      base_joint_ = pair.first;
    }
    for (int i = 0; i < c.n(); ++i) {
      const JointSpec& j = c.joints[i];
      dart::dynamics::RevoluteJoint::Properties jp;
      jp.mName = j.joint;
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      for (int r = 0; r < 3; ++r) {
        for (int s = 0; s < 3; ++s) T.linear()(r, s) = j.origin_R[3 * r + s];
        T.translation()(r) = j.origin_xyz[r];
      }
      jp.mT_ParentBodyToJoint = T;
      jp.mT_ChildBodyToJoint = Eigen::Isometry3d::Identity();
      jp.mAxis = Eigen::Vector3d(j.axis[0], j.axis[1], j.axis[2]);
      dart::dynamics::BodyNode* parent = j.parent >= 0 ? bodies[j.parent] : base;
      auto pair = skel_->createJointAndBodyNodePair<dart::dynamics::RevoluteJoint>(
          parent, jp, dart::dynamics::BodyNode::AspectProperties(j.link));
      const Eigen::Matrix3d I =
          Eigen::Vector3d(j.inertia_diag[0], j.inertia_diag[1], j.inertia_diag[2]).asDiagonal();
      pair.second->setInertia(
          dart::dynamics::Inertia(j.mass, Eigen::Vector3d(j.com[0], j.com[1], j.com[2]), I));
      bodies.push_back(pair.second);
      dofs_.push_back(pair.first->getDof(0));
    }
    for (int i = 0; i < c.n(); ++i) {
      dofs_[i]->setPosition(c.q0[i]);
      dofs_[i]->setVelocity(c.qd0[i]);
    }
    if (base_joint_) {
      // FreeJoint velocity = (w, v) of the body in body coordinates: world axes at the identity.
      Eigen::Vector6d V;
      V << c.base.w0[0], c.base.w0[1], c.base.w0[2], c.base.v0[0], c.base.v0[1], c.base.v0[2];
      base_joint_->setVelocities(V);
      base_body_ = base;
    }
    world_ = dart::simulation::World::create();
    world_->setGravity(Eigen::Vector3d(c.gravity[0], c.gravity[1], c.gravity[2]));
    world_->setTimeStep(h);
    world_->addSkeleton(skel_);
  }
  void step(long n) override {
    for (long i = 0; i < n; ++i) world_->step();
  }
  void joints(std::vector<double>* q, std::vector<double>* qd) override {
    q->resize(dofs_.size());
    qd->resize(dofs_.size());
    for (size_t i = 0; i < dofs_.size(); ++i) {
      (*q)[i] = dofs_[i]->getPosition();
      (*qd)[i] = dofs_[i]->getVelocity();
    }
  }
  bool base(bench::articulated::BaseState<double>* b) override {
    if (!base_body_) return false;
    const Eigen::Isometry3d& T = base_body_->getWorldTransform();
    b->R = T.linear();
    b->p = T.translation();
    b->w = base_body_->getAngularVelocity();
    b->v = base_body_->getLinearVelocity();
    return true;
  }

 private:
  dart::dynamics::FreeJoint* base_joint_ = nullptr;
  dart::dynamics::BodyNode* base_body_ = nullptr;
  dart::dynamics::SkeletonPtr skel_;
  dart::simulation::WorldPtr world_;
  std::vector<dart::dynamics::DegreeOfFreedom*> dofs_;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<bench::articulated::ArticulatedConfig> configs = {
      {"world_step",
       [](const ArticulatedCase& c,
          double h) -> std::unique_ptr<bench::articulated::ArticulatedSim> {
         return std::make_unique<DartArticulated>(c, h);
       }},
  };
  return bench::articulated::runArticulatedSweep("dart", std::string("DART ") + DART_VERSION,
                                                 configs, argc, argv);
}
