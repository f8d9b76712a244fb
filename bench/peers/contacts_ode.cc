// ODE contact peer runner (Debian libode-dev 0.16.2, double precision):
// peer_contacts_ode.
//
// Scene: dHashSpace, ground = dCreatePlane(0, 0, 1, 0), bin walls = static
// dBox geoms (no body), bodies = dBody with dMassSetSphereTotal /
// dMassSetBoxTotal (exact mass, solid-shape inertia) and a sphere / box geom.
// Each step: dSpaceCollide -> one contact joint per contact point (at most 8
// per geom pair) -> dWorldStep or dWorldQuickStep (config) -> empty the
// contact group. Auto-disable off (ODE's default).
//
// How the case parameters map to ODE:
//  * friction: surface.mu = mu with dContactApprox1 (the friction limit is
//    mu times the normal force of that contact; without Approx1 ODE's mu is a
//    fixed force limit in newtons, not a coefficient). ODE's friction is a
//    pyramid (two tangent directions, each limited separately), not a cone;
//    the sliding cases here move along a pyramid axis (world x).
//  * restitution: dContactBounce with surface.bounce = e and
//    surface.bounce_vel = 0.1 m/s (the minimum incoming normal velocity for a
//    bounce; 0.1 as in ODE's own demos; below it contacts are inelastic).
//    e = 0: no dContactBounce.
//  * softness: world ERP 0.2 (default), world CFM 1e-5, contact surface layer
//    1 mm, contact max correcting velocity 0.1 m/s: the values ODE's box
//    stacking demos use (ODE's double-precision default CFM 1e-10 makes
//    stacks jittery).
// Configs: `step` (dWorldStep: big-matrix LCP, "accurate") and `quickstep`
// (dWorldQuickStep: iterative SOR-LCP, 20 iterations, the default). `step`
// does not run pile1000 (a dense LCP over thousands of contact rows does not
// fit the time budget; ODE's docs recommend quickstep for large systems).
#include <cmath>
#include <cstdarg>
#include <memory>
#include <string>
#include <vector>

#include <ode/ode.h>

#include "contact_common.h"

namespace {

using bench::contacts::BodyObs;
using bench::contacts::ContactCase;
using bench::contacts::Shape;

constexpr int kMaxContacts = 8;

// ODE prints solver trouble ("LCP internal error") through its message
// handler; count it per run and report it in the notes instead.
long g_ode_messages = 0;
void countMessage(int, const char*, va_list) { ++g_ode_messages; }

class OdeContactSim : public bench::contacts::ContactSim {
 public:
  OdeContactSim(const ContactCase& c, double h, bool quick) : h_(h), quick_(quick), mu_(c.mu), e_(c.e) {
    world_ = dWorldCreate();
    space_ = dHashSpaceCreate(nullptr);
    group_ = dJointGroupCreate(0);
    dWorldSetGravity(world_, c.gravity[0], c.gravity[1], c.gravity[2]);
    dWorldSetERP(world_, 0.2);
    dWorldSetCFM(world_, 1e-5);
    dWorldSetContactSurfaceLayer(world_, 0.001);
    dWorldSetContactMaxCorrectingVel(world_, 0.1);
    dCreatePlane(space_, 0, 0, 1, 0);
    if (c.bin.present) {
      const double w = c.bin.half_width, t = c.bin.wall_thickness, hh = 0.5 * c.bin.wall_height;
      const double o = w + 0.5 * t, l = 2 * (w + t);
      auto wall = [&](double lx, double ly, double x, double y) {
        dGeomID g = dCreateBox(space_, lx, ly, 2 * hh);
        dGeomSetPosition(g, x, y, hh);
      };
      wall(t, l, o, 0);
      wall(t, l, -o, 0);
      wall(l, t, 0, o);
      wall(l, t, 0, -o);
    }
    for (const auto& b : c.bodies) {
      dBodyID body = dBodyCreate(world_);
      dMass m;
      dGeomID g;
      if (b.shape == Shape::Sphere) {
        dMassSetSphereTotal(&m, b.mass, b.size);
        g = dCreateSphere(space_, b.size);
      } else {
        const double a = 2 * b.size;
        dMassSetBoxTotal(&m, b.mass, a, a, a);
        g = dCreateBox(space_, a, a, a);
      }
      dBodySetMass(body, &m);
      dGeomSetBody(g, body);
      dBodySetPosition(body, b.x0[0], b.x0[1], b.x0[2]);
      dBodySetLinearVel(body, b.v0[0], b.v0[1], b.v0[2]);
      bodies_.push_back(body);
    }
  }
  ~OdeContactSim() override {
    dJointGroupDestroy(group_);
    dSpaceDestroy(space_);  // destroys the geoms (cleanup mode on)
    dWorldDestroy(world_);
  }
  void step(long n) override {
    for (long i = 0; i < n; ++i) {
      dSpaceCollide(space_, this, &nearCallback);
      if (quick_) dWorldQuickStep(world_, h_);
      else dWorldStep(world_, h_);
      dJointGroupEmpty(group_);
    }
  }
  std::string events() override {
    return g_ode_messages ? "ODE messages (LCP internal error etc.) " + std::to_string(g_ode_messages) : "";
  }
  void observe(std::vector<BodyObs>* out) override {
    out->resize(bodies_.size());
    for (size_t i = 0; i < bodies_.size(); ++i) {
      const dReal* x = dBodyGetPosition(bodies_[i]);
      const dReal* v = dBodyGetLinearVel(bodies_[i]);
      const dReal* w = dBodyGetAngularVel(bodies_[i]);  // world frame
      for (int k = 0; k < 3; ++k) {
        (*out)[i].x[k] = x[k];
        (*out)[i].v[k] = v[k];
        (*out)[i].w[k] = w[k];
      }
    }
  }

 private:
  static void nearCallback(void* data, dGeomID o1, dGeomID o2) {
    auto* self = static_cast<OdeContactSim*>(data);
    dBodyID b1 = dGeomGetBody(o1), b2 = dGeomGetBody(o2);
    if (!b1 && !b2) return;  // static vs static
    dContact contact[kMaxContacts];
    const int n = dCollide(o1, o2, kMaxContacts, &contact[0].geom, sizeof(dContact));
    for (int i = 0; i < n; ++i) {
      dSurfaceParameters& s = contact[i].surface;
      s.mode = dContactApprox1 | (self->e_ > 0 ? dContactBounce : 0);
      s.mu = self->mu_;
      s.bounce = self->e_;
      s.bounce_vel = 0.1;
      dJointID j = dJointCreateContact(self->world_, self->group_, &contact[i]);
      dJointAttach(j, b1, b2);
    }
  }

  double h_;
  bool quick_;
  double mu_, e_;
  dWorldID world_;
  dSpaceID space_;
  dJointGroupID group_;
  std::vector<dBodyID> bodies_;
};

}  // namespace

int main(int argc, char** argv) {
  dInitODE2(0);
  dSetMessageHandler(countMessage);
  auto make = [](bool quick) {
    return [quick](const ContactCase& c, double h) -> std::unique_ptr<bench::contacts::ContactSim> {
      return std::make_unique<OdeContactSim>(c, h, quick);
    };
  };
  std::vector<bench::contacts::ContactConfig> configs = {
      {"step", make(false), {"pile1000"}, "dense LCP (dWorldStep) over thousands of contact rows: outside the budget"},
      {"quickstep", make(true), {}, ""},
  };
  const int rc = bench::contacts::runContactSweep("ode", std::string("ODE ") + (dCheckConfiguration("ODE_double_precision") ? "double" : "single"), configs, argc, argv);
  dCloseODE();
  return rc;
}
