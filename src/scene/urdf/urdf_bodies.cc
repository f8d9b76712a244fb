// Step (4) of the URDF loader (urdf_loading.h): bodies. The links joined by fixed joints merge
// into one body (composite mass, centre of mass and inertia; the body frame B at the centre of
// mass along the principal axes), a joint that moves no mass is welded, and the joints met start
// further bodies (doc/urdf.md).
#include <Eigen/Eigenvalues>
#include <algorithm>

#include "cga_rigid_sim/format.h"
#include "scene/urdf/urdf_loading.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {
namespace {

// A moving body with no mass of its own that carries massive links through further joints
// (the dummy link between two joints of a universal joint) gets this fraction of what it
// carries: mass and moments negligible in the dynamics, and every body of the tree physical.
constexpr double kPlaceholderFraction = 1e-6;

// Where a joint welded for want of mass stays: its default initial position (0 clamped into
// its limits).
double weldedPosition(const detail::JointXml& j) {
  const JointLimits& l = j.limits;
  return l.has_position ? std::clamp(0.0, l.lower, l.upper) : 0.0;
}

}  // namespace

std::vector<urdf::JointSharedPtr> Loader::childJoints(const urdf::Link& link) const {
  // urdfdom lists child joints by name; the document order is what the user wrote.
  std::vector<urdf::JointSharedPtr> joints = link.child_joints;
  std::sort(joints.begin(), joints.end(), [&](const auto& a, const auto& b) {
    return xml_.joints.at(a->name).order < xml_.joints.at(b->name).order;
  });
  return joints;
}

// carried_: a post-order walk over the links (no recursion: deep chains), summing each link's
// mass and keeping the largest moment below it, through fixed and moving joints.
void Loader::findCarried() {
  std::vector<std::pair<const urdf::Link*, bool>> stack{{model_->getRoot().get(), false}};
  while (!stack.empty()) {
    const auto [link, done] = stack.back();
    stack.pop_back();
    const auto joints = childJoints(*link);
    if (!done) {  // every link gets its entry, the free bodies' below floating joints too
      stack.emplace_back(link, true);
      for (const auto& j : joints)
        stack.emplace_back(model_->getLink(j->child_link_name).get(), false);
      continue;
    }
    Carried c;
    const auto own = masses_.find(link->name);
    if (own != masses_.end() && own->second.massive) {
      c.mass = own->second.in_link.mass;
      c.moment = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(own->second.in_link.J_F,
                                                                Eigen::EigenvaluesOnly)
                     .eigenvalues()
                     .maxCoeff();
    }
    for (const auto& j : joints) {
      if (j->type == urdf::Joint::FLOATING) continue;
      const Carried& below = carried_.at(j->child_link_name);
      c.mass += below.mass;
      c.moment = std::max(c.moment, below.moment);
    }
    carried_[link->name] = c;
  }
}

// A moving joint whose child carries no mass at all (the link and everything below it: a sensor
// frame on a revolute joint) has no dynamics: nothing resists its motion. By default it is
// welded at its initial position, with a warning (tf keeps publishing the frames below it), unless
// the strict option is set or a <mimic> involves it (then the body is refused for its mass).
bool Loader::weldsMassless(const urdf::Joint& j) {
  const detail::JointXml& xml = xml_.joints.at(j.name);
  if (!xml.type || strict() || carried_.at(j.child_link_name).mass > 0 || xml.mimic) return false;
  for (const auto& [name, other] : xml_.joints)
    if (other.mimic && other.mimic->joint == j.name) return false;
  warnings_.push_back(warnAt(xml.line) + toString(*xml.type) + " joint " + inQuotes(j.name) +
                      " moves link " + inQuotes(j.child_link_name) +
                      ", which carries no mass (no <inertial> there or below it): nothing resists "
                      "its motion, so it is welded at " +
                      formatNumber(weldedPosition(xml), kDigits) +
                      (*xml.type == JointType::kPrismatic ? " m" : " rad") +
                      " like a fixed joint (give the link an <inertial> to simulate the joint)" +
                      kRepairedNote);
  return true;
}

// The welded joint's motion at its default initial position (0 clamped into its limits).
Eigen::Isometry3d Loader::weldedMotion(const urdf::Joint& j) const {
  const detail::JointXml& xml = xml_.joints.at(j.name);
  const double q = weldedPosition(xml);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  if (*xml.type == JointType::kPrismatic)
    X.translation() = q * xml.axis;
  else
    X.linear() = Eigen::AngleAxisd(q, xml.axis).toRotationMatrix();
  return X;
}

// One body (roots[index]): the links reached from its root link through fixed joints.
// Floating joints met on the way start further free bodies, revolute, continuous and prismatic
// joints further moving bodies hinged to this one (appended to `more_roots`).
Result<BodyModel> Loader::buildBody(const BodyRoot& root, int index,
                                    std::vector<BodyRoot>* more_roots) {
  const double lambda = options_.lambda;
  BodyModel body;
  body.name = root.link->name;
  body.is_static = root.is_static;
  std::vector<std::pair<const urdf::Link*, Eigen::Isometry3d>> links;  // X_RL
  std::vector<BodyRoot> hinged;  // X_PJ holds X_RJ until B is known
  std::vector<std::pair<const urdf::Link*, Eigen::Isometry3d>> stack{
      {root.link, Eigen::Isometry3d::Identity()}};
  while (!stack.empty()) {
    const auto [link, X_RL] = stack.back();
    stack.pop_back();
    links.emplace_back(link, X_RL);
    const auto joints = childJoints(*link);
    // Reverse so the first child joint in the document is visited first.
    for (auto it = joints.rbegin(); it != joints.rend(); ++it) {
      const urdf::Joint& j = **it;
      const urdf::Link* child = model_->getLink(j.child_link_name).get();
      // The joint frame J, which is the child link's frame at q = 0.
      const Eigen::Isometry3d X_RC = X_RL * toIsometry(j.parent_to_joint_origin_transform);
      if (j.type == urdf::Joint::FIXED) {
        body.merged_joints.push_back(j.name);
        stack.emplace_back(child, X_RC);
      } else if (j.type == urdf::Joint::FLOATING) {
        more_roots->push_back({child, root.X_WR * X_RC, false});
      } else if (weldsMassless(j)) {  // nothing with mass moves: welded at its initial position
        body.merged_joints.push_back(j.name);
        stack.emplace_back(child, X_RC * weldedMotion(j));
      } else if (xml_.joints.at(j.name).type) {  // revolute, continuous, prismatic
        hinged.push_back({child, root.X_WR * X_RC, false, &j, index, X_RC});
      } else {  // the XML pass refuses the others first; kept so no joint is ever taken as fixed
        return fail(xml_.joints.at(j.name).line,
                    "joint " + inQuotes(j.name) + " is of a type that is not supported");
      }
    }
  }
  std::reverse(body.merged_joints.begin(), body.merged_joints.end());

  std::string link_list;
  for (const auto& l : links)
    link_list += (link_list.empty() ? "" : ", ") + inQuotes(l.first->name);

  // The body frame B. Static: the root link frame. Moving: origin at the composite centre of
  // mass, axes along the principal axes (dynamics::Inertia picks and orders them).
  Eigen::Isometry3d X_RB = Eigen::Isometry3d::Identity();
  if (!body.is_static) {
    std::vector<MassProperties> parts;
    for (const auto& [link, X_RL] : links) {
      const LinkMass& lm = masses_.at(link->name);
      if (lm.massive) parts.push_back(transformed(lm.in_link, X_RL));
    }
    MassProperties sum = combine(parts);
    const Carried& below = carried_.at(root.link->name);
    if (!(sum.mass > 0) && below.mass > 0 && !strict()) {
      // It carries massive links through further joints: a placeholder of kPlaceholderFraction
      // of what it carries, at its root link's origin.
      sum.mass = kPlaceholderFraction * below.mass;
      sum.J_F = kPlaceholderFraction * below.moment * Eigen::Matrix3d::Identity();
      sum.com_F.setZero();
      warnings_.push_back(warnAt(linkLine(body.name)) + "body " + inQuotes(body.name) +
                          " has no mass of its own (links " + link_list + ") but moves the " +
                          formatNumber(below.mass, kDigits) + " kg below it: given " +
                          formatNumber(sum.mass, kDigits) + " kg and moments " +
                          formatNumber(sum.J_F(0, 0), kDigits) + " kg m^2 (" +
                          formatNumber(kPlaceholderFraction, 1) +
                          " of what it carries; a moving body needs mass and inertia)" +
                          kRepairedNote);
    }
    if (!(sum.mass > 0)) {
      const std::string none = " has no mass: none of its links (" + link_list +
                               ") has an <inertial> with mass > 0 or a <" +
                               detail::kMassFromGeometryElement +
                               ">; a moving body needs mass and inertia (massless links are fine "
                               "only when merged by fixed joints into a body that has mass";
      if (root.joint) {
        const std::string& joint = root.joint->name;
        return fail(linkLine(body.name),
                    "body " + inQuotes(body.name) + none + "); it is a moving body of its own " +
                        "because " + toString(*xml_.joints.at(joint).type) + " joint " +
                        inQuotes(joint) + " moves it (to weld it to its parent instead, make " +
                        inQuotes(joint) + " a fixed joint)");
      }
      return fail(linkLine(body.name), "free body " + inQuotes(body.name) + none +
                                           "; to keep it still, fix it to '" +
                                           options_.world_frame + "' with a fixed joint)");
    }
    std::string warning;
    auto inertia = dynamics::Inertia::fromTensor(body.name, sum.mass, sum.J_F,
                                                 options_.triangle_policy, &warning);
    if (!inertia) {
      std::string what = inertia.error() + " [the body of links " + link_list +
                         (links.size() > 1 ? ", merged by fixed joints" : "") + "]";
      if (inertia.error().find("triangle") != std::string::npos) what += kRelaxHint;
      if (inertia.error().find("positive definite") != std::string::npos)
        what +=
            "; a moving body needs a positive moment of inertia about every axis (e.g. point "
            "masses on one line have none about that line)";
      return fail(linkLine(body.name), what);
    }
    if (!warning.empty()) warnings_.push_back(source_ + ": " + warning + kRepairedNote);
    X_RB.translation() = sum.com_F;
    X_RB.linear() = inertia->rotationFromPrincipal().toRotationMatrix();
    body.inertia = *inertia;
  }
  const Eigen::Isometry3d X_BR = X_RB.inverse();
  for (const auto& [link, X_RL] : links) {
    const Eigen::Isometry3d X_BL = X_BR * X_RL;
    // Each link's shapes move into its one body (the XML reading is not needed after this).
    for (detail::CollisionGeometry& g : xml_.links.at(link->name).collisions) {
      CollisionShape shape = std::move(g.shape);
      shape.M_BS = cga::Motor::fromIsometry(X_BL * g.X_LS, lambda);
      shape.link_index = static_cast<int>(body.links.size());
      body.shapes.push_back(std::move(shape));
    }
    body.links.push_back({link->name, cga::Motor::fromIsometry(X_BL, lambda)});
  }
  // The joints met: their frames J in this body's frame B, M_PJ = M_BL (joint <origin>).
  for (BodyRoot& h : hinged) {
    h.X_PJ = X_BR * h.X_PJ;
    more_roots->push_back(h);
  }
  // With every joint at 0 (a joint's child is placed again at its initial position later).
  body.M_WB0 = cga::Motor::fromIsometry(root.X_WR * X_RB, lambda);
  return body;
}

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
