// The narrow phase of two shapes (doc/contacts.md#detection) through FCL: box–box gives the
// full face manifold (up to four points), meshes collide as their convex hulls, and the shapes'
// speculative margins are taken off FCL's depth again.
#include <fcl/narrowphase/collision.h>

#include <cmath>

#include "contact/contact_detection_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {

void pairContacts(const Model& model, CollisionCache& cache, int s1, int s2,
                  std::vector<Contact>& out) {
  const CollisionCache::Shape& A = cache.shapes[s1];
  const CollisionCache::Shape& B = cache.shapes[s2];
  fcl::CollisionRequestd request(4, true);
  fcl::CollisionResultd result;
  fcl::collide(A.geometry.get(), cache.pose_W[s1], B.geometry.get(), cache.pose_W[s2], request,
               result);
  if (!result.isCollision()) return;
  cache.fcl_contacts.clear();
  result.getContacts(cache.fcl_contacts);
  const auto& sa = model.scene.bodies[A.body].shapes[A.shape];
  const auto& sb = model.scene.bodies[B.body].shapes[B.shape];
  for (const fcl::Contactd& f : cache.fcl_contacts) {
    if (!f.normal.allFinite() || !f.pos.allFinite() || !std::isfinite(f.penetration_depth))
      continue;
    Contact k;
    k.body_a = A.body;
    k.shape_a = A.shape;
    k.body_b = B.body;
    k.shape_b = B.shape;
    k.point_W = f.pos;
    k.normal_W = -f.normal.normalized();  // FCL's points from o1 (a) to o2 (b)
    k.depth = f.penetration_depth - A.margin - B.margin;
    combineSurfaces(model, sa.surface, sb.surface, k);
    out.push_back(k);
  }
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
