#include "cga_rigid_sim/sim/reports.h"

#include <map>
#include <sstream>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/format.h"

namespace cga_rigid_sim {
namespace sim {

namespace {

// Adds body r (of mass m, centre of mass x) to the sums of a group; `mass_x` is Σ m x.
void addTo(MomentumReport& group, double& mass, Eigen::Vector3d& mass_x, const MomentumReport& r,
           double m, const Eigen::Vector3d& x) {
  group.linear += r.linear;
  group.angular_origin += r.angular_origin;
  group.kinetic_energy += r.kinetic_energy;
  group.potential_energy += r.potential_energy;
  mass += m;
  mass_x += m * x;
}

// About the group's centre of mass x_cm = Σ m x_c / Σ m: L_cm = L_origin − x_cm × P.
void finish(MomentumReport& group, double mass, const Eigen::Vector3d& mass_x) {
  if (mass > 0) group.angular = group.angular_origin - (mass_x / mass).cross(group.linear);
}

}  // namespace

std::vector<MomentumReport> momentumReports(const Model& model, const Data& data) {
  const double lambda = model.lambda;
  const Eigen::Vector3d& g_W = model.scene.gravity_W;
  std::vector<MomentumReport> out;
  out.reserve(data.bodies.size() + model.trees.size() + 1);
  MomentumReport total;
  total.kind = MomentumReport::Kind::kTotal;
  total.body = kTotalName;
  double mass = 0.0;
  Eigen::Vector3d mass_x = Eigen::Vector3d::Zero();  // Σ m x_c
  for (std::size_t i = 0; i < data.bodies.size(); ++i) {
    const dynamics::Inertia& I = model.moving[i].inertia;
    const dynamics::BodyState& s = data.bodies[i].state;
    MomentumReport r;
    r.body = model.bodyOf(static_cast<int>(i)).name;
    r.linear = dynamics::linearMomentum_W(I, s, lambda);
    r.angular = dynamics::angularMomentumCom_W(I, s);
    r.angular_origin = dynamics::angularMomentumOrigin_W(I, s, lambda);
    r.kinetic_energy = dynamics::kineticEnergy(I, s, lambda);
    r.potential_energy = dynamics::potentialEnergy(I, s, g_W, lambda);
    addTo(total, mass, mass_x, r, I.mass(), dynamics::comPosition_W(s, lambda));
    out.push_back(std::move(r));
  }
  // Each tree: the sums over its bodies (their entries are out[i] by moving index).
  for (const TreeModel& tm : model.trees) {
    MomentumReport tree;
    tree.kind = MomentumReport::Kind::kTree;
    tree.body = kTreePrefix + model.bodyOf(tm.movingOf(tm.body.floating() ? 0 : 1)).name;
    double tree_mass = 0.0;
    Eigen::Vector3d tree_mass_x = Eigen::Vector3d::Zero();
    for (int b = tm.body.floating() ? 0 : 1; b < tm.body.bodyCount(); ++b) {
      const int i = tm.movingOf(b);
      addTo(tree, tree_mass, tree_mass_x, out[i], model.moving[i].inertia.mass(),
            dynamics::comPosition_W(data.bodies[i].state, lambda));
    }
    finish(tree, tree_mass, tree_mass_x);
    out.push_back(std::move(tree));
  }
  finish(total, mass, mass_x);
  total.dissipated_energy = data.dissipated_energy;
  out.push_back(std::move(total));
  return out;
}

ContactReport contactReport(const Model& model, const Contact& c) {
  const auto names = [&model](int j, int shape, std::string& body, std::string& link) {
    if (j == kGroundPlane) {
      body = link = kGroundPlaneName;
      return;
    }
    const scene::BodyModel& b = model.scene.bodies[j];
    body = b.name;
    link = b.links[b.shapes[shape].link_index].link;
  };
  ContactReport r;
  names(c.body_a, c.shape_a, r.body_a, r.link_a);
  names(c.body_b, c.shape_b, r.body_b, r.link_b);
  r.point = c.point_W;
  r.normal = c.normal_W;
  r.depth = c.depth;
  r.normal_impulse = c.normal_impulse;
  r.friction_impulse = c.friction_impulse_W;
  return r;
}

std::vector<ContactReport> contactReports(const Model& model, const Data& data) {
  std::vector<ContactReport> out;
  out.reserve(data.contacts.size());
  for (const Contact& c : data.contacts) out.push_back(contactReport(model, c));
  return out;
}

BodyStateReport bodyStateReport(const Model& model, const Data& data, int j) {
  const scene::BodyModel& b = model.scene.bodies[j];
  const int i = model.moving_of_body[j];
  const double lambda = model.lambda;
  BodyStateReport r;
  r.name = b.name;
  if (i >= 0) {
    r.state = data.bodies[i].state;
  } else {
    r.state.M_WB = b.M_WB0;  // static: fixed pose, no velocity
  }
  r.pose_root = (r.state.M_WB * b.links.front().M_BL).toIsometry(lambda);
  r.com = dynamics::comPosition_W(r.state, lambda);
  r.linear_velocity = dynamics::comVelocity_W(r.state, lambda);
  r.angular_velocity = dynamics::angularVelocity_W(r.state);
  return r;
}

std::vector<BodyStateReport> bodyStateReports(const Model& model, const Data& data) {
  std::vector<BodyStateReport> out;
  out.reserve(model.moving.size());
  for (const MovingBody& m : model.moving) out.push_back(bodyStateReport(model, data, m.body));
  return out;
}

std::vector<FramePose> movingFrames(const Model& model, const Data& data) {
  std::vector<FramePose> out;
  out.reserve(data.bodies.size());
  for (std::size_t i = 0; i < data.bodies.size(); ++i) {
    const scene::LinkFrame& root = model.bodyOf(static_cast<int>(i)).links.front();
    out.push_back({model.config.world_frame, root.link,
                   (data.bodies[i].state.M_WB * root.M_BL).toIsometry(model.lambda)});
  }
  return out;
}

std::vector<FramePose> staticFrames(const Model& model) {
  std::vector<FramePose> out;
  const double lambda = model.lambda;
  for (const auto& b : model.scene.bodies) {
    const scene::LinkFrame& root = b.links.front();
    if (b.is_static)
      out.push_back(
          {model.config.world_frame, root.link, (b.M_WB0 * root.M_BL).toIsometry(lambda)});
    // Link L relative to the root link R: M_RL = M_BR⁻¹ M_BL.
    const cga::Motor M_RB = root.M_BL.reverse();
    for (std::size_t li = 1; li < b.links.size(); ++li)
      out.push_back({root.link, b.links[li].link, (M_RB * b.links[li].M_BL).toIsometry(lambda)});
  }
  return out;
}

std::string worldSummary(const Model& model, const Data& data) {
  constexpr std::size_t kMaxListed = 20;  // one screen, as the scene summary
  const auto& bodies = model.scene.bodies;
  // The path of each body: the one its integrator took in the last step, "at-rest" if it was
  // skipped, or before its first step the planned one (scene.h).
  auto pathOf = [&](std::size_t j) -> std::string {
    const int i = model.moving_of_body[j];
    if (i < 0) return "static";
    switch (data.bodies[i].last_path) {
      case StepPath::kAtRest:
        return "at-rest";
      case StepPath::kStepped:
        return data.bodies[i].integrator->path();
      default:
        return scene::plannedIntegratorPath(model.scene, bodies[j], model.config.integrator);
    }
  };
  std::ostringstream os;
  os.precision(6);
  const auto& g = model.scene.gravity_W;
  const double t = static_cast<double>(data.step_count) * model.config.dt;
  os << "world: " << model.moving.size() << " moving, " << bodies.size() - model.moving.size()
     << " static bodies; dt " << model.config.dt << " s, integrator '" << model.config.integrator
     << "', lambda " << model.lambda << " m, gravity (" << g.x() << ", " << g.y() << ", " << g.z()
     << ") m/s^2; step " << data.step_count << ", t " << t << " s\n";
  std::map<std::string, std::size_t> count;  // ordered: deterministic output
  for (std::size_t j = 0; j < bodies.size(); ++j) {
    const std::string path = pathOf(j);
    ++count[path];
    if (j >= kMaxListed) continue;
    const scene::BodyModel& b = bodies[j];
    const int i = model.moving_of_body[j];
    os << "  " << b.name << ": ";
    if (i >= 0) {
      const dynamics::Inertia& I = model.moving[i].inertia;
      const Eigen::Vector3d& J = I.principalMoments();
      os << dynamics::toString(I.inertiaClass()) << ", mass " << I.mass() << " kg, J (" << J.x()
         << ", " << J.y() << ", " << J.z() << ") kg m^2, ";
    }
    os << "path " << path << ", links";
    for (const auto& l : b.links) os << " " << l.link;
    os << "\n";
  }
  if (bodies.size() > kMaxListed) os << "  ... and " << bodies.size() - kMaxListed << " more\n";
  os << "paths:";
  for (const auto& kv : count) os << " " << kv.first << " x" << kv.second;
  os << "\n";
  return os.str();
}

Error treeFaultError(const Model& m, const TreeFaults& f) {
  const std::vector<TreeModel>& trees = m.trees;
  const bool known = f.tree >= 0 && f.tree < static_cast<int>(trees.size());
  const std::string who = known ? "tree '" + trees[f.tree].name + "'"
                                : "a tree";  // (trees are not removed; a guard all the same)
  const auto bodyName = [&m](int j) {
    return j < 0                                         ? std::string("the ground plane")
           : j < static_cast<int>(m.scene.bodies.size()) ? "'" + m.scene.bodies[j].name + "'"
                                                         : std::string("a body");
  };
  const std::string pair = f.body_a >= 0 ? " (its deepest contact: " + bodyName(f.body_a) +
                                               " against " + bodyName(f.body_b) + ")"
                                         : "";
  std::string what;
  switch (f.rule) {
    case TreeFaults::Rule::kNotFinite:
      what =
          "left a non-finite state (its mass matrix cannot be resolved in double precision: "
          "links implausibly far from their joints or too light for their offsets)";
      break;
    case TreeFaults::Rule::kNotSolved:
      what = "could not be solved: the implicit step did not converge within its attempts";
      break;
    case TreeFaults::Rule::kLimit: {
      const std::string joint =
          known && f.joint >= 0 && f.joint < static_cast<int>(trees[f.tree].scene_joint.size())
              ? "joint '" + m.scene.joints[trees[f.tree].scene_joint[f.joint]].name + "'"
              : "a joint";
      what = "left " + joint + " at " + formatNumber(f.value, 10) + ", past its limit " +
             formatNumber(f.bound, 10) + " (rule: no joint passes its limits)";
      break;
    }
    case TreeFaults::Rule::kEnergy:
      what = "raised the tree's energy by " + formatNumber(f.value, 6) +
             " J beyond the work of gravity and its inputs (tolerance " + formatNumber(f.bound, 6) +
             " J; rule: contacts never create energy)" + pair;
      break;
    case TreeFaults::Rule::kMomentum:
      what = "changed the floating tree's momentum by " + formatNumber(f.value, 6) +
             " beyond gravity, its inputs and its contacts with other bodies (tolerance " +
             formatNumber(f.bound, 6) + "; rule: its contacts with itself cancel)" + pair;
      break;
  }
  return Error("step", "tree",
               who + ": step " + std::to_string(f.step) + " " + what +
                   "; it was undone and the tree is at rest at its pose before the step "
                   "(doc/articulated.md#faults)");
}

}  // namespace sim
}  // namespace cga_rigid_sim
