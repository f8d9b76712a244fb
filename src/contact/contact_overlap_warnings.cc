// The overlaps at a World's start (contact_detection.h): the pairs of bodies that overlap by
// more than a depth, named one by one or, for a heap of them, counted with the deepest.
#include <algorithm>
#include <string>

#include "contact/contact_detection.h"

namespace cga_rigid_sim {
namespace sim {

std::vector<std::string> overlapWarnings(const Model& model, const Data& data,
                                         CollisionCache& cache, double depth) {
  std::vector<Contact> found;
  detectContacts(model, data, cache, found);
  // The deepest contact of each pair of bodies deeper than `depth`, in detection order of the
  // pairs' first contact (sorting keeps a pile of thousands of overlaps cheap).
  std::vector<std::size_t> order;
  for (std::size_t k = 0; k < found.size(); ++k)
    if (found[k].depth > depth) order.push_back(k);
  const auto pairOf = [&found](std::size_t k) {
    return std::make_pair(found[k].body_a, found[k].body_b);
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return pairOf(x) < pairOf(y); });
  std::vector<std::size_t> deepest;  // per pair: its deepest contact (first of equals)
  for (std::size_t q = 0; q < order.size();) {
    std::size_t best = order[q], e = q;
    for (; e < order.size() && pairOf(order[e]) == pairOf(order[q]); ++e)
      if (found[order[e]].depth > found[best].depth) best = order[e];
    deepest.push_back(best);
    q = e;
  }
  const auto name = [&model](int j, int shape) {
    if (j == kGroundPlane) return std::string("the ground plane");
    const scene::BodyModel& b = model.scene.bodies[j];
    return "body '" + b.name + "' (link '" + b.links[b.shapes[shape].link_index].link + "')";
  };
  const auto line = [&](const Contact& c) {
    return name(c.body_a, c.shape_a) + " and " + name(c.body_b, c.shape_b) + " overlap by " +
           std::to_string(c.depth) +
           " m at the start: they are pushed apart without adding energy (against gravity only "
           "as far as their kinetic energy pays for it)";
  };
  // A few pairs are named one by one; past that a count and the deepest, so that a heap of
  // overlapping bodies does not flood the log.
  constexpr std::size_t kNamed = 5;
  std::vector<std::string> out;
  if (deepest.size() > kNamed) {
    std::stable_sort(deepest.begin(), deepest.end(), [&found](std::size_t x, std::size_t y) {
      return found[x].depth > found[y].depth;
    });
    out.push_back(std::to_string(deepest.size()) + " pairs of bodies overlap by more than " +
                  std::to_string(depth) +
                  " m at the start; they are pushed apart without adding energy. The " +
                  std::to_string(kNamed) + " deepest:");
    deepest.resize(kNamed);
  } else {
    std::sort(deepest.begin(), deepest.end());
  }
  for (std::size_t k : deepest) out.push_back(line(found[k]));
  return out;
}

}  // namespace sim
}  // namespace cga_rigid_sim
