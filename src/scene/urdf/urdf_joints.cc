// The URDF loader's joints (urdf_loading.h): each articulated joint's model, the bodies and
// joints put parent first, and the joints' default initial positions (doc/urdf.md).
#include <algorithm>

#include "cga_rigid_sim/format.h"
#include "scene/urdf/urdf_loading.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

// The joint that starts the body roots[index] (`child`, built): its frames and what the XML pass
// read. J is the child link's frame at q = 0, and the child link is the body's root link, so
// M_JC = M_BL⁻¹ of the root link.
JointModel Loader::jointModel(const BodyRoot& root, int index, const BodyModel& child) const {
  const detail::JointXml& xml = xml_.joints.at(root.joint->name);
  JointModel j;
  j.name = root.joint->name;
  j.type = *xml.type;
  j.parent_body = root.parent;
  j.child_body = index;
  j.parent_link = root.joint->parent_link_name;
  j.child_link = root.joint->child_link_name;
  j.M_PJ = cga::Motor::fromIsometry(root.X_PJ, options_.lambda);
  j.M_JC = child.links.front().M_BL.reverse();
  j.axis = xml.axis;
  j.limits = xml.limits;
  j.damping = xml.damping;
  j.friction = xml.friction;
  return j;
}

// Bodies in the document order of their root links, except that a joint's parent body comes
// before its child body (a child link may be written before its parent's links): each body is
// preceded by those of its ancestors not yet placed. `document_order` lists the body indices
// sorted by the document order of their root links; the joints' body indices are renumbered and
// the joints sorted by child body, which puts them parent first too.
void Loader::orderParentFirst(Scene* scene, const std::vector<int>& document_order) {
  const std::size_t n = scene->bodies.size();
  std::vector<int> parent(n, -1);
  for (const JointModel& j : scene->joints) parent[j.child_body] = j.parent_body;
  std::vector<int> order, chain;  // order[new index] = old index
  std::vector<bool> placed(n, false);
  for (const int k : document_order) {
    chain.clear();  // k and its ancestors not yet placed, child first (no recursion: deep chains)
    for (int a = k; a >= 0 && !placed[a]; a = parent[a]) chain.push_back(a);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      placed[*it] = true;
      order.push_back(*it);
    }
  }
  std::vector<int> new_index(n);
  std::vector<BodyModel> bodies;
  bodies.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    new_index[order[i]] = static_cast<int>(i);
    bodies.push_back(std::move(scene->bodies[order[i]]));
  }
  scene->bodies = std::move(bodies);
  for (JointModel& j : scene->joints) {
    if (j.parent_body >= 0) j.parent_body = new_index[j.parent_body];
    j.child_body = new_index[j.child_body];
  }
  std::sort(scene->joints.begin(), scene->joints.end(),
            [](const JointModel& a, const JointModel& b) { return a.child_body < b.child_body; });
}

// Each joint starts at q = 0 unless its limits exclude 0: then at the nearest limit, with a
// warning (the initial-state dictionary can choose another position). A joint that mimics
// another starts where its leader puts it; a leader's limits include those of its followers.
void Loader::setDefaultInitialPositions(Scene* scene) {
  for (std::size_t k = 0; k < scene->joints.size(); ++k) {
    JointModel& j = scene->joints[k];
    if (j.mimic) continue;
    const auto [lower, upper] = mimicRange(scene->joints, static_cast<int>(k));
    if (lower <= 0.0 && 0.0 <= upper) continue;
    const bool own = j.limits.has_position && (j.limits.lower > 0.0 || j.limits.upper < 0.0);
    j.initial_position = 0.0 < lower ? lower : upper;
    const char* unit = j.type == JointType::kPrismatic ? " m" : " rad";
    warnings_.push_back(
        source_ + ":" + std::to_string(xml_.joints.at(j.name).line) + ": joint " +
        inQuotes(j.name) + ": the default initial position 0" + unit + " is outside its limits [" +
        formatNumber(lower, kDigits) + ", " + formatNumber(upper, kDigits) + "]" + unit +
        (own ? "" : " (those of the joints that mimic it, mapped to it)") + ": clamped to the " +
        (0.0 < lower ? "lower" : "upper") + " limit " + formatNumber(j.initial_position, kDigits) +
        unit + " (~initial_state." + j.name + ".position chooses another)");
  }
}

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
