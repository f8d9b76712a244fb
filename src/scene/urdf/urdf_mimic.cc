// The URDF loader's <mimic> joints (urdf_loading.h): each resolved to the independent joint
// that leads it, and refused where the constraint cannot be simulated (doc/urdf.md).
#include <cmath>

#include "cga_rigid_sim/format.h"
#include "scene/urdf/urdf_loading.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

// Each joint's <mimic>, resolved to the independent joint at the end of its chain (multipliers
// and offsets composed: q = m1 (m2 q_l + o2) + o1), and refused where the constraint cannot be
// simulated: leader and follower in different trees (a tree on a free root and another tree,
// joints on the ground — the world or a static body — belong together), or no position of the
// leader that keeps every follower within its limits.
std::optional<Error> Loader::resolveMimics(Scene* scene) const {
  std::vector<JointModel>& joints = scene->joints;
  std::unordered_map<std::string, int> index;
  std::vector<int> moved_by(scene->bodies.size(), -1);
  for (std::size_t k = 0; k < joints.size(); ++k) {
    index.emplace(joints[k].name, static_cast<int>(k));
    moved_by[joints[k].child_body] = static_cast<int>(k);
  }
  // The free root a joint's tree hangs from, or −1 for the ground.
  const auto rootOf = [&](int k) {
    int body = joints[k].parent_body;
    while (body >= 0 && moved_by[body] >= 0) body = joints[moved_by[body]].parent_body;
    return body < 0 || scene->bodies[body].is_static ? -1 : body;
  };
  const auto rootName = [&](int root) {
    return root < 0 ? "on the ground ('" + options_.world_frame + "' or a link fixed to it)"
                    : "hanging from the free body " + inQuotes(scene->bodies[root].name);
  };
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const detail::JointXml& xml = xml_.joints.at(joints[k].name);
    if (!xml.mimic) continue;
    JointMimic m;
    m.written = xml.mimic->joint;
    m.multiplier = xml.mimic->multiplier;
    m.offset = xml.mimic->offset;
    int leader = index.at(m.written);  // the XML pass checked the chain ends at such a joint
    for (const detail::JointXml* next = &xml_.joints.at(m.written); next->mimic;
         next = &xml_.joints.at(joints[leader].name)) {
      m.offset += m.multiplier * next->mimic->offset;
      m.multiplier *= next->mimic->multiplier;
      leader = index.at(next->mimic->joint);
    }
    m.leader = leader;
    const std::string owner =
        "joint " + inQuotes(joints[k].name) + ": <mimic joint=" + inQuotes(m.written) + ">";
    const int a = rootOf(static_cast<int>(k)), b = rootOf(leader);
    if (a != b)
      return fail(xml.mimic->line, owner + ": " + inQuotes(joints[leader].name) +
                                       " is in another articulated tree (" + rootName(b) +
                                       ", this one " + rootName(a) +
                                       "); a mimic constraint couples joints of one tree");
    if (!std::isfinite(m.multiplier) || !std::isfinite(m.offset))
      return fail(xml.mimic->line, owner + ": the composed multiplier and offset overflow");
    const JointLimits& l = joints[k].limits;
    if (m.multiplier == 0.0 && l.has_position && !(l.lower <= m.offset && m.offset <= l.upper))
      return fail(xml.mimic->line, owner + ": multiplier 0 holds the joint at its offset " +
                                       formatNumber(m.offset, kDigits) + ", outside its limits [" +
                                       formatNumber(l.lower, kDigits) + ", " +
                                       formatNumber(l.upper, kDigits) + "]");
    joints[k].mimic = m;
  }
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const auto [lower, upper] = mimicRange(joints, static_cast<int>(k));
    if (lower <= upper) continue;
    std::string followers;
    for (const JointModel& j : joints)
      if (j.mimic && j.mimic->leader == static_cast<int>(k))
        followers += (followers.empty() ? "" : ", ") + inQuotes(j.name);
    return fail(xml_.joints.at(joints[k].name).line,
                "joint " + inQuotes(joints[k].name) + " and the joints that mimic it (" +
                    followers + ") cannot all be within their limits: mapped to " +
                    inQuotes(joints[k].name) + ", their limits leave no position (" +
                    formatNumber(lower, kDigits) + " > " + formatNumber(upper, kDigits) + ")");
  }
  return std::nullopt;
}

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
