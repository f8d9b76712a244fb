// The URDF loader's link names as tf frames (urdf_loading.h): a leading '/' dropped, and links
// that would become one frame, or the world frame, refused (doc/urdf.md).
#include <algorithm>

#include "cga_rigid_sim/format.h"
#include "scene/urdf/urdf_loading.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

// Links whose names begin with '/' are published on tf without it (tf2 refuses such frame ids),
// and known by that name everywhere else (bodies, initial state, messages), with a warning; two
// links that would become one frame, or a link that would become the world frame, are refused.
std::optional<Error> Loader::nameFramesForTf(Scene* scene) {
  std::unordered_map<std::string, std::string> by_frame;  // tf frame → link, for every link
  std::unordered_map<std::string, std::string> renamed;   // link → its frame, where they differ
  std::vector<std::string> names;
  for (const auto& [name, link] : xml_.links) names.push_back(name);
  std::sort(names.begin(), names.end(),
            [&](const std::string& a, const std::string& b) { return linkLine(a) < linkLine(b); });
  const std::string& world = options_.world_frame;
  const bool has_world_root =
      model_->getRoot()->name != world && tfFrame(model_->getRoot()->name) == world;
  for (const std::string& name : names) {
    const std::string frame = tfFrame(name);
    if (frame.empty())
      return fail(linkLine(name), "link " + inQuotes(name) +
                                      " has no name once its leading '/' is removed (tf2 takes "
                                      "frame ids without it)");
    const bool root = name == model_->getRoot()->name;
    if (frame == world && name != world && !(root && has_world_root))
      return fail(linkLine(name), "link " + inQuotes(name) + " would be published as the tf " +
                                      "frame " + inQuotes(frame) + ", the world frame " +
                                      "(~world_frame), which only the root link may be; rename it");
    const auto [it, added] = by_frame.emplace(frame, name);
    if (!added)
      return fail(linkLine(name), "links " + inQuotes(it->second) + " (line " +
                                      std::to_string(linkLine(it->second)) + ") and " +
                                      inQuotes(name) + " would both be published as the tf " +
                                      "frame " + inQuotes(frame) + " (tf2 takes frame ids " +
                                      "without a leading '/'); rename one");
    if (frame == name) continue;
    renamed.emplace(name, frame);
    warnings_.push_back(warnAt(linkLine(name)) + "link " + inQuotes(name) +
                        " is published on tf as " + inQuotes(frame) +
                        " and known by that name (tf2 refuses frame ids that begin with '/')");
  }
  if (renamed.empty()) return std::nullopt;
  const auto rename = [&](std::string& link) {
    const auto it = renamed.find(link);
    if (it != renamed.end()) link = it->second;
  };
  for (BodyModel& b : scene->bodies) {
    const std::string old_root = b.links.front().link;
    for (LinkFrame& l : b.links) {
      for (CollisionShape& shape : b.shapes)  // default names '<link>#<k>' follow the link
        if (&b.links[shape.link_index] == &l && shape.name.rfind(l.link + "#", 0) == 0)
          shape.name = tfFrame(l.link) + shape.name.substr(l.link.size());
      rename(l.link);
    }
    if (b.name == old_root) b.name = b.links.front().link;
  }
  for (JointModel& j : scene->joints) {
    rename(j.parent_link);
    rename(j.child_link);
  }
  return std::nullopt;
}

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
