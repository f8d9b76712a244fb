// Simbody articulated runner (Debian libsimbody-dev 3.7): peer_articulated_simbody.
//
// Model: built in code from the case (bench/cases/articulated_cases.h). Per link a
// MobilizedBody::Pin, which turns its body about the common z axis of its two mobilizer frames:
// inboard frame F = (joint origin rotation R_o A, joint origin) in the parent body (Ground for a
// root joint), outboard frame M = (A, 0) in the link, where A is a rotation taking z to the
// case's joint axis; so at q = 0 the link frame is the joint frame and q turns it about the
// axis, as in the case. Body::Rigid(MassProperties(m, CoM, Inertia(diag) shifted from the CoM to
// the link origin)). A floating base is a MobilizedBody::Free on Ground (quaternion, Simbody's
// default) at the identity with the case's velocities. Force::UniformGravity with the case's
// gravity; no damping, no contact, no limits. q, u set to (q0, qd0) (a Pin's q is its angle, u
// its rate).
//
// Integrators (as in simbody_runner.cc): setFixedStepSize(h), setAllowInterpolation(false),
// default accuracy; one stepTo(t + n h) per run(n). SemiExplicitEuler, Verlet, RungeKutta3,
// RungeKuttaMerson in the default sweep; ExplicitEuler, SemiExplicitEuler2, RungeKutta2,
// RungeKuttaFeldberg with --all-configs. Budget: Simbody costs ~10-60 us per step, so the
// default sweep stops at h = 1e-4 (--min-h 0 lifts it) and times min(T/h, 5000) steps.
//
// Cross-check of the truth: `RKMerson_accuracy_1e-12` (not in the default sweep) integrates with
// Simbody's error control at accuracy 1e-12 (h is then only the initial step).
#include <Simbody.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "articulated_common.h"

namespace {

using bench::articulated::ArticulatedCase;
using bench::articulated::JointSpec;

enum class Method {
  ExplicitEuler,
  SemiExplicitEuler,
  SemiExplicitEuler2,
  Verlet,
  RK2,
  RK3,
  RKMerson,
  RKFeldberg
};

// A rotation taking z to the unit vector a.
SimTK::Rotation zToAxis(const SimTK::Vec3& a) {
  return SimTK::Rotation(SimTK::UnitVec3(a), SimTK::ZAxis);
}

class SimbodyArticulated : public bench::articulated::ArticulatedSim {
 public:
  SimbodyArticulated(const ArticulatedCase& c, double h, Method method, double accuracy)
      : matter_(system_), forces_(system_), h_(h) {
    SimTK::Force::UniformGravity(forces_, matter_,
                                 SimTK::Vec3(c.gravity[0], c.gravity[1], c.gravity[2]), 0);
    std::vector<SimTK::MobilizedBody> parents;
    if (c.base.floating) {
      const auto& b = c.base;
      const SimTK::Vec3 com(b.com[0], b.com[1], b.com[2]);
      const SimTK::Inertia Ic(b.inertia_diag[0], b.inertia_diag[1], b.inertia_diag[2]);
      const SimTK::Body::Rigid body(
          SimTK::MassProperties(b.mass, com, Ic.shiftFromMassCenter(com, b.mass)));
      base_ = SimTK::MobilizedBody::Free(matter_.updGround(), SimTK::Transform(), body,
                                         SimTK::Transform());
    }
    for (int i = 0; i < c.n(); ++i) {
      const JointSpec& j = c.joints[i];
      const SimTK::Vec3 axis(j.axis[0], j.axis[1], j.axis[2]);
      SimTK::Mat33 Ro;
      for (int r = 0; r < 3; ++r)
        for (int s = 0; s < 3; ++s) Ro(r, s) = j.origin_R[3 * r + s];
      const SimTK::Rotation A = zToAxis(axis);
      const SimTK::Rotation RF(SimTK::Rotation(Ro, true) * A);
      const SimTK::Vec3 com(j.com[0], j.com[1], j.com[2]);
      const SimTK::Inertia Ic(j.inertia_diag[0], j.inertia_diag[1], j.inertia_diag[2]);
      // MassProperties wants the inertia about the body origin.
      const SimTK::Body::Rigid body(
          SimTK::MassProperties(j.mass, com, Ic.shiftFromMassCenter(com, j.mass)));
      SimTK::MobilizedBody& parent =
          j.parent >= 0
              ? parents[j.parent]
              : (c.base.floating ? static_cast<SimTK::MobilizedBody&>(base_) : matter_.updGround());
      SimTK::MobilizedBody::Pin pin(
          parent,
          SimTK::Transform(RF, SimTK::Vec3(j.origin_xyz[0], j.origin_xyz[1], j.origin_xyz[2])),
          body, SimTK::Transform(A, SimTK::Vec3(0)));
      parents.push_back(pin);
      pins_.push_back(pin);
    }
    SimTK::State s = system_.realizeTopology();
    for (int i = 0; i < c.n(); ++i) {
      pins_[i].setOneQ(s, 0, c.q0[i]);
      pins_[i].setOneU(s, 0, c.qd0[i]);
    }
    if (c.base.floating) {
      floating_ = true;
      base_.setQToFitTransform(s, SimTK::Transform());
      base_.setUToFitAngularVelocity(s, SimTK::Vec3(c.base.w0[0], c.base.w0[1], c.base.w0[2]));
      base_.setUToFitLinearVelocity(s, SimTK::Vec3(c.base.v0[0], c.base.v0[1], c.base.v0[2]));
    }
    switch (method) {
      case Method::ExplicitEuler:
        integ_ = std::make_unique<SimTK::ExplicitEulerIntegrator>(system_);
        break;
      case Method::SemiExplicitEuler:
        integ_ = std::make_unique<SimTK::SemiExplicitEulerIntegrator>(system_, h);
        break;
      case Method::SemiExplicitEuler2:
        integ_ = std::make_unique<SimTK::SemiExplicitEuler2Integrator>(system_);
        break;
      case Method::Verlet:
        integ_ = std::make_unique<SimTK::VerletIntegrator>(system_);
        break;
      case Method::RK2:
        integ_ = std::make_unique<SimTK::RungeKutta2Integrator>(system_);
        break;
      case Method::RK3:
        integ_ = std::make_unique<SimTK::RungeKutta3Integrator>(system_);
        break;
      case Method::RKMerson:
        integ_ = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system_);
        break;
      case Method::RKFeldberg:
        integ_ = std::make_unique<SimTK::RungeKuttaFeldbergIntegrator>(system_);
        break;
    }
    if (accuracy > 0) {
      integ_->setAccuracy(accuracy);
      integ_->setInitialStepSize(h);
    } else {
      integ_->setFixedStepSize(h);
    }
    integ_->setAllowInterpolation(false);
    integ_->initialize(s);
  }

  void step(long n) override {
    done_ += n;
    const double target = static_cast<double>(done_) * h_;
    while (integ_->getTime() < target) {
      if (integ_->stepTo(target) == SimTK::Integrator::EndOfSimulation)
        throw std::runtime_error("Simbody: end of simulation");
    }
  }
  void joints(std::vector<double>* q, std::vector<double>* qd) override {
    const SimTK::State& s = integ_->getState();
    q->resize(pins_.size());
    qd->resize(pins_.size());
    for (size_t i = 0; i < pins_.size(); ++i) {
      (*q)[i] = pins_[i].getOneQ(s, 0);
      (*qd)[i] = pins_[i].getOneU(s, 0);
    }
  }
  bool base(bench::articulated::BaseState<double>* b) override {
    if (!floating_) return false;
    const SimTK::State& s = integ_->getState();
    system_.realize(s, SimTK::Stage::Velocity);
    const SimTK::Rotation& R = base_.getBodyRotation(s);
    const SimTK::Vec3& p = base_.getBodyOriginLocation(s);
    const SimTK::Vec3& w = base_.getBodyAngularVelocity(s);
    const SimTK::Vec3& v = base_.getBodyOriginVelocity(s);
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) b->R(r, k) = R[r][k];
      b->p(r) = p[r];
      b->w(r) = w[r];
      b->v(r) = v[r];
    }
    return true;
  }
  std::string events() override {
    return "steps taken " + std::to_string(integ_->getNumStepsTaken()) + " attempted " +
           std::to_string(integ_->getNumStepsAttempted());
  }

 private:
  SimTK::MultibodySystem system_;
  SimTK::SimbodyMatterSubsystem matter_;
  SimTK::GeneralForceSubsystem forces_;
  std::vector<SimTK::MobilizedBody::Pin> pins_;
  SimTK::MobilizedBody::Free base_;
  bool floating_ = false;
  std::unique_ptr<SimTK::Integrator> integ_;
  double h_;
  long done_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  using bench::articulated::ArticulatedConfig;
  auto make = [](Method m, double accuracy = 0) {
    return [m, accuracy](const ArticulatedCase& c,
                         double h) -> std::unique_ptr<bench::articulated::ArticulatedSim> {
      return std::make_unique<SimbodyArticulated>(c, h, m, accuracy);
    };
  };
  std::vector<ArticulatedConfig> configs = {
      {"SemiExplicitEuler", make(Method::SemiExplicitEuler), true},
      {"Verlet", make(Method::Verlet), true},
      {"RungeKutta3", make(Method::RK3), true},
      {"RungeKuttaMerson", make(Method::RKMerson), true},
      {"ExplicitEuler", make(Method::ExplicitEuler), false},
      {"SemiExplicitEuler2", make(Method::SemiExplicitEuler2), false},
      {"RungeKutta2", make(Method::RK2), false},
      {"RungeKuttaFeldberg", make(Method::RKFeldberg), false},
      {"RKMerson_accuracy_1e-12", make(Method::RKMerson, 1e-12), false},
  };
  bench::articulated::ArticulatedDefaults defaults;
  defaults.timing_steps = 5000;
  defaults.min_h = 1e-4;
  int major = 0, minor = 0, build = 0;
  SimTK_version_SimTKcommon(&major, &minor, &build);
  const std::string version = "Simbody " + std::to_string(major) + "." + std::to_string(minor) +
                              "." + std::to_string(build);
  return bench::articulated::runArticulatedSweep("simbody", version, configs, argc, argv, defaults);
}
