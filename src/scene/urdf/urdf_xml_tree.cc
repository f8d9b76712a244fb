// The URDF reader's tree check (urdf_reader.h): the joints join defined links into one tree
// rooted at one link, without cycles, at most kMaxUrdfDepth joints deep, with the world frame at
// the root (doc/urdf.md).
#include <unordered_map>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "scene/urdf/urdf_reader.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

std::optional<Error> Reader::checkTree() const {
  std::unordered_map<std::string, const JointEdge*> parent_joint;
  std::unordered_map<std::string, std::vector<std::string>> children;
  for (const JointEdge& j : edges_) {
    const std::string owner = "joint " + inQuotes(j.name);
    for (const std::string* l : {&j.parent, &j.child})
      if (!out_.links.count(*l))
        return fail(j.line, owner + ": " + (l == &j.parent ? "parent" : "child") + " link " +
                                inQuotes(*l) + " is not defined (no <link name=\"" + *l + "\">)");
    if (j.parent == j.child)
      return fail(j.line, owner + " joins link " + inQuotes(j.child) + " to itself");
    const auto [it, added] = parent_joint.emplace(j.child, &j);
    if (!added)
      return fail(j.line, "link " + inQuotes(j.child) + " is the child of two joints, " +
                              inQuotes(it->second->name) + " (line " +
                              std::to_string(it->second->line) + ") and " + inQuotes(j.name) +
                              "; a URDF must be a tree (each link has at most one parent joint)");
    children[j.parent].push_back(j.child);
  }
  if (link_names_.empty()) return fail(1, "the <robot> has no <link>");
  std::vector<std::string> roots;
  for (const std::string& l : link_names_)
    if (!parent_joint.count(l)) roots.push_back(l);
  if (roots.size() > 1)
    return fail(out_.links.at(roots[1]).line,
                "more than one root link: " + inQuotes(roots[0]) + " and " + inQuotes(roots[1]) +
                    " both have no parent joint; a URDF is one tree (to simulate several bodies, "
                    "give each a floating joint from a common '" +
                    world_frame_ + "' link)");
  // Links not reachable from the root hang in a cycle of joints. The depth of each link (joints
  // from the root) is bounded: urdfdom builds the tree recursively.
  std::unordered_map<std::string, bool> reached;
  if (!roots.empty()) {
    std::vector<std::pair<std::string, int>> stack{{roots[0], 0}};
    reached[roots[0]] = true;
    while (!stack.empty()) {
      const auto [l, depth] = stack.back();
      stack.pop_back();
      const auto c = children.find(l);
      if (c == children.end()) continue;
      for (const std::string& child : c->second) {
        if (reached[child]) continue;
        reached[child] = true;
        if (depth + 1 > kMaxUrdfDepth)
          return fail(parent_joint.at(child)->line,
                      "link " + inQuotes(child) + " is more than " + std::to_string(kMaxUrdfDepth) +
                          " joints below the root link " + inQuotes(roots[0]) +
                          "; the loader takes chains of at most " + std::to_string(kMaxUrdfDepth) +
                          " joints (kMaxUrdfDepth: urdfdom builds the tree recursively, and a "
                          "tree integrator factors a mass matrix as large every step; "
                          "doc/urdf.md#bounds)");
        stack.emplace_back(child, depth + 1);
      }
    }
  }
  for (const std::string& l : link_names_) {
    if (reached.count(l)) continue;
    // Walk up the parents until a link repeats: that loop is the cycle.
    std::unordered_map<std::string, int> seen;
    std::vector<const JointEdge*> path;
    std::string at = l;
    while (!seen.count(at)) {
      seen[at] = static_cast<int>(path.size());
      path.push_back(parent_joint.at(at));
      at = path.back()->parent;
    }
    std::string joints;
    for (std::size_t k = seen[at]; k < path.size(); ++k)
      joints += (joints.empty() ? "" : ", ") + inQuotes(path[k]->name);
    return fail(
        path[seen[at]]->line,
        "the joints " + joints + " form a cycle (link " + inQuotes(l) + " is not connected to " +
            (roots.empty() ? std::string("any root link") : "the root link " + inQuotes(roots[0])) +
            "); a URDF must be a tree");
  }
  const auto world = parent_joint.find(world_frame_);
  if (world != parent_joint.end())
    return fail(world->second->line, "link " + inQuotes(world_frame_) +
                                         " is the world frame and must be the root of the tree, "
                                         "but joint " +
                                         inQuotes(world->second->name) + " makes it a child of " +
                                         inQuotes(world->second->parent));
  return std::nullopt;
}

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
