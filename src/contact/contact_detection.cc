// Contact detection (doc/contacts.md#detection): the shapes placed at the step's start, the
// ground plane against each shape (contact_ground_plane.cc), and the broad phase — a sort and
// sweep of the shapes' bounding spheres along x, then their boxes (contact_box_separation.cc) —
// which hands the pairs that may touch to the narrow phase (contact_shape_pairs.cc).
#include <algorithm>
#include <cmath>

#include "contact/contact_detection_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// A body that does not move this step: static, or a moving body that sleeps (it keeps the pose
// of its last detection, unless the cache is new).
bool inert(const Model& model, const std::vector<char>* asleep, int body) {
  const int i = model.moving_of_body[body];
  return i < 0 || (asleep && !asleep->empty() && (*asleep)[i]);
}

// The sweep's intervals (every shape's bounding sphere along x), sorted, and the positions of
// the awake ones.
void sortIntervals(const Model& model, CollisionCache& cache, const std::vector<char>* asleep) {
  cache.sweep.clear();
  for (std::size_t s = 0; s < cache.shapes.size(); ++s) {
    const Eigen::Vector3d& c = cache.centre_W[s];
    const double r = cache.shapes[s].bound;
    cache.sweep.push_back({c.x() - r, c.x() + r, c.y(), c.z(), r, static_cast<int>(s),
                           !inert(model, asleep, cache.shapes[s].body)});
  }
  std::sort(cache.sweep.begin(), cache.sweep.end(),
            [](const CollisionCache::Interval& a, const CollisionCache::Interval& b) {
              return a.lo < b.lo || (a.lo == b.lo && a.shape < b.shape);
            });
  cache.awake_at.clear();
  for (std::size_t p = 0; p < cache.sweep.size(); ++p)
    if (cache.sweep[p].awake) cache.awake_at.push_back(static_cast<int>(p));
}

// Whether the bounding spheres' boxes overlap in y and z (x: the sweep's own test).
bool near(const CollisionCache::Interval& I, const CollisionCache::Interval& J) {
  const double reach = I.bound + J.bound;
  return std::abs(J.y - I.y) <= reach && std::abs(J.z - I.z) <= reach;
}

// The sweep's entries p and q, near in x, y and z: to the narrow phase if they are shapes of
// two bodies that may collide and their bounding spheres overlap.
__attribute__((always_inline)) inline void testPair(const Model& model, CollisionCache& cache,
                                                    std::size_t p, std::size_t q,
                                                    std::vector<Contact>& out) {
  const int s1 = cache.sweep[p].shape, s2 = cache.sweep[q].shape;
  const CollisionCache::Shape& A = cache.shapes[s1];
  const CollisionCache::Shape& B = cache.shapes[s2];
  if (A.body == B.body) return;
  const Eigen::Vector3d d = cache.centre_W[s2] - cache.centre_W[s1];
  const double r = A.bound + B.bound;
  if (d.squaredNorm() > r * r) return;  // (y and z: near(), checked before each call)
  // Two bodies of one robot: only the pairs its self-collision rules allow
  // (doc/contacts.md#self-collision); never a link and its parent. (After the spheres: a
  // lookup costs more than their test, and most pairs near in x, y and z are not near.)
  if (!model.self_collision.collides(A.body, B.body)) return;
  if (detail::boxesApart(cache, s1, s2)) return;
  const bool a_moving = model.moving_of_body[A.body] >= 0;
  const bool b_moving = model.moving_of_body[B.body] >= 0;
  // Body a is moving; of two moving bodies, the one that comes first in the scene.
  const bool a_first = a_moving && (!b_moving || A.body < B.body);
  if (a_first)
    detail::pairContacts(model, cache, s1, s2, out);
  else
    detail::pairContacts(model, cache, s2, s1, out);
}

}  // namespace

void detectContacts(const Model& model, const Data& data, CollisionCache& cache,
                    std::vector<Contact>& out, const std::vector<char>* asleep) {
  const bool rebuilt = !cache.built || cache.topology != model.topology_version;
  if (rebuilt) detail::buildCollisionCache(model, cache);
  if (cache.shapes.empty()) return;
  for (std::size_t s = 0; s < cache.shapes.size(); ++s) {
    const int body = cache.shapes[s].body;
    if (!rebuilt && model.moving_of_body[body] >= 0 && inert(model, asleep, body)) continue;
    detail::placeShape(model, data, cache, s);
  }
  if (model.config.ground_plane)
    detail::planeContacts(model, data, cache, 0, cache.shapes.size(), -1, out, asleep);

  // Broad phase: intervals of the bounding spheres along x, sorted; a pair is tested when its
  // intervals and its y and z extents overlap. Two inert shapes (static or asleep) are never
  // tested, so an inert shape looks only at the awake shapes after it in the sweep (found by
  // bisection in their positions) rather than at every shape its interval overlaps: a
  // sleeping pile costs the sort, not its pairs. The pairs come in the same order either way.
  sortIntervals(model, cache, asleep);
  if (cache.awake_at.empty()) return;
  for (std::size_t p = 0; p < cache.sweep.size(); ++p) {
    const double hi = cache.sweep[p].hi;
    if (cache.sweep[p].awake) {
      for (std::size_t q = p + 1; q < cache.sweep.size() && cache.sweep[q].lo <= hi; ++q)
        if (near(cache.sweep[p], cache.sweep[q])) testPair(model, cache, p, q, out);
      continue;
    }
    for (auto it =
             std::upper_bound(cache.awake_at.begin(), cache.awake_at.end(), static_cast<int>(p));
         it != cache.awake_at.end() && cache.sweep[*it].lo <= hi; ++it)
      if (near(cache.sweep[p], cache.sweep[*it]))
        testPair(model, cache, p, static_cast<std::size_t>(*it), out);
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
