#include "sim/curved_bodies.h"

#include <cmath>
#include <sstream>

#include "cga_rigid_sim/curved/curved_derived.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// The curved integrator a body gets: auto → the exact flow for an isotropic body, else curved2.
std::string curvedIntegratorName(const std::string& configured,
                                 const dynamics::CurvedInertia& inertia) {
  if (configured == "auto") return inertia.isotropic() ? "curved_exact" : "curved2";
  return configured;
}

// The moment of a force f_B at the body-axes offset x_B plus a couple τ_B (curved_bodies.h).
cga::Bivector4 bodyMoment(const dynamics::CurvedSpace& S, const Eigen::Vector3d& f_B,
                          const Eigen::Vector3d& x_B, const Eigen::Vector3d& couple_B) {
  cga::Bivector4 M(couple_B, Eigen::Vector3d::Zero());
  if (!f_B.isZero(0.0))
    M += cga::wedge(dynamics::curvedBodyPoint(S, x_B), dynamics::curvedBodyVector(S, x_B, f_B));
  return M;
}

// The body moment of the body's active wrenches (b.loads) at its current pose: world-axes
// forces and couples turned into the body's axes through the chart attitude there.
cga::Bivector4 wrenchMoment_B(const dynamics::CurvedSpace& S, const MovingBodyData& b) {
  Eigen::Vector3d x;
  Eigen::Quaterniond q;
  S.chartPose(b.curved_state.psi, x, q);
  const Eigen::Quaterniond q_BW = q.conjugate();
  cga::Bivector4 M;
  for (const dynamics::AppliedLoad& l : b.loads.applied()) {
    const bool world = l.axes == dynamics::Axes::kWorld;
    M += bodyMoment(S, world ? Eigen::Vector3d(q_BW * l.F.f) : l.F.f, l.point_B,
                    world ? Eigen::Vector3d(q_BW * l.couple) : l.couple);
  }
  return M;
}

// K(τ): L_B += τ M_B(ψ) (the wrenches' moment at the current pose).
void kick(const Model& model, int i, double tau, MovingBodyData& b) {
  const dynamics::CurvedInertia& I = *model.moving[i].curved_inertia;
  dynamics::CurvedBodyState& s = b.curved_state;
  s.omega_B = I.velocity(I.momentum(s.omega_B) + tau * wrenchMoment_B(*model.curved_space, b));
}

// b.state from the curved state: the chart pose and the true velocities (w, v = |R| u).
void writeChartState(const Model& model, MovingBodyData& b) {
  const dynamics::CurvedSpace& S = *model.curved_space;
  const dynamics::CurvedBodyState& s = b.curved_state;
  Eigen::Vector3d x;
  Eigen::Quaterniond q;
  S.chartPose(s.psi, x, q);
  b.state.M_WB = cga::Motor::fromPose(q, x, model.lambda);
  b.state.omega_B = cga::Bivelocity(s.omega_B.rot, (S.rho() / model.lambda) * s.omega_B.trans);
}

}  // namespace

std::optional<Error> checkCurvedConfig(const WorldConfig& config) {
  const auto space = dynamics::CurvedSpace::fromRadius(*config.curvature);
  if (!space) return Error("config", "curvature", space.failure().rule);
  const std::string& name = config.integrator;
  if (name != "auto" && name != "curved2" && name != "curved_exact")
    return Error(
        "config", "integrator",
        "'" + name + "' is not an integrator of curved space (auto, curved2, curved_exact)");
  return std::nullopt;
}

std::optional<Error> compileCurvedBodies(Model& model) {
  model.curved_space = dynamics::CurvedSpace::fromRadius(*model.config.curvature).value();
  const Eigen::Vector3d& g = model.scene.gravity_W;
  if (!g.isZero(0.0)) {
    std::ostringstream os;
    os << "needs gravity off (a uniform field has no meaning in curved space); gravity is ("
       << g.x() << ", " << g.y() << ", " << g.z() << ")";
    return Error("config", "curvature", os.str());
  }
  if (!model.trees.empty())
    return Error("config", "curvature",
                 "articulated trees are not simulated in curved space (tree '" +
                     model.trees.front().name + "')");
  if (model.config.ground_plane)
    return Error("config", "curvature", "a ground plane has no meaning in curved space");
  for (MovingBody& mb : model.moving) {
    const std::string& name = model.scene.bodies[mb.body].name;
    auto I = dynamics::CurvedInertia::fromEuclidean(name, mb.inertia, *model.curved_space);
    if (!I) return Error("scene", "body '" + name + "'", I.failure().rule);
    auto it = dynamics::makeCurvedIntegrator(curvedIntegratorName(model.config.integrator, *I), *I);
    if (!it) return Error("config", "integrator", "body '" + name + "': " + it.failure().rule);
    mb.curved_inertia = std::move(I.value());
  }
  return std::nullopt;
}

std::optional<Error> makeCurvedBodyData(const Model& model, int moving_index,
                                        const dynamics::BodyState& initial, MovingBodyData& b) {
  const dynamics::CurvedSpace& S = *model.curved_space;
  const MovingBody& mb = model.moving[moving_index];
  const std::string& name = model.scene.bodies[mb.body].name;
  auto psi = S.poseFromChart(initial.M_WB.translation(model.lambda), initial.M_WB.rotation());
  if (!psi)
    return Error("scene", "body '" + name + "'",
                 "initial " + psi.failure().field + " " + psi.failure().rule);
  b.curved_state.psi = *psi;
  b.curved_state.omega_B = cga::Bivector4(
      initial.omega_B.rot, (model.lambda / S.rho()) * initial.omega_B.trans);  // u = v/|R|
  auto it = dynamics::makeCurvedIntegrator(
      curvedIntegratorName(model.config.integrator, *mb.curved_inertia), *mb.curved_inertia);
  if (!it) return Error("config", "integrator", it.failure().rule);
  b.curved_integrator = std::move(it.value());
  return std::nullopt;
}

void stepCurvedBody(const Model& model, int i, MovingBodyData& b) {
  dynamics::CurvedBodyState& s = b.curved_state;
  const bool loaded = b.loads.hasApplied();
  // No wrench and Ω_B = 0: at rest under both integrators; left exactly as it is.
  if (!loaded && s.omega_B.rot.isZero(0.0) && s.omega_B.trans.isZero(0.0)) {
    b.last_path = StepPath::kAtRest;
    return;
  }
  b.last_path = StepPath::kStepped;
  // Wrenches: the Strang splitting K(h/2) F(h) K(h/2), each kick at its own pose (so a world-axes
  // load is turned into the body's axes at that pose).
  const double h = model.config.dt;
  if (loaded) kick(model, i, 0.5 * h, b);
  b.curved_integrator->step(*model.moving[i].curved_inertia, dynamics::CurvedLoads(), h, s);
  if (loaded) kick(model, i, 0.5 * h, b);
  writeChartState(model, b);
}

void applyCurvedImpulse(const Model& model, int i, const Eigen::Vector3d& j_B,
                        const Eigen::Vector3d& x_B, const Eigen::Vector3d& a_B, MovingBodyData& b) {
  const dynamics::CurvedInertia& I = *model.moving[i].curved_inertia;
  dynamics::CurvedBodyState& s = b.curved_state;
  s.omega_B = I.velocity(I.momentum(s.omega_B) + bodyMoment(*model.curved_space, j_B, x_B, a_B));
  writeChartState(model, b);
}

std::optional<Error> refuseInCurvedSpace(const Model& model, const std::string& input) {
  if (!model.curved_space) return std::nullopt;
  return Error(input, "",
               "not available in curved space yet (curvature R = " +
                   std::to_string(model.curved_space->radius()) + " m)");
}

std::vector<CurvedMomentumReport> curvedMomentumReports(const Model& model, const Data& data) {
  std::vector<CurvedMomentumReport> out;
  if (!model.curved_space) return out;
  CurvedMomentumReport total;
  total.body = kTotalName;
  for (std::size_t i = 0; i < model.moving.size(); ++i) {
    const dynamics::CurvedInertia& I = *model.moving[i].curved_inertia;
    CurvedMomentumReport r;
    r.body = model.scene.bodies[model.moving[i].body].name;
    r.L_W = dynamics::curvedWorldMomentum(I, data.bodies[i].curved_state);
    r.kinetic_energy = dynamics::curvedKineticEnergy(I, data.bodies[i].curved_state);
    total.L_W += r.L_W;
    total.kinetic_energy += r.kinetic_energy;
    out.push_back(std::move(r));
  }
  out.push_back(std::move(total));
  return out;
}

}  // namespace sim
}  // namespace cga_rigid_sim
