// The narrow phase of two shapes (doc/contacts.md#detection): a mesh (its convex hull) and any
// shape by contact_convex_pairs.cc, every other pair through FCL, where box–box gives the full
// face manifold (up to four points); the shapes' speculative margins are taken off the depth.
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
  const auto& sa = model.scene.bodies[A.body].shapes[A.shape];
  const auto& sb = model.scene.bodies[B.body].shapes[B.shape];
  const auto add = [&](const Eigen::Vector3d& point_W, const Eigen::Vector3d& normal_ab,
                       double depth) {
    if (!normal_ab.allFinite() || !point_W.allFinite() || !std::isfinite(depth)) return;
    Contact k;
    k.body_a = A.body;
    k.shape_a = A.shape;
    k.body_b = B.body;
    k.shape_b = B.shape;
    k.point_W = point_W;
    k.normal_W = -normal_ab.normalized();  // the contact's normal points from b to a
    k.depth = depth - A.margin - B.margin;
    combineSurfaces(model, sa.surface, sb.surface, k);
    out.push_back(k);
  };
  if (A.hull || B.hull) {
    Eigen::Vector3d point_W, normal_ab;
    double depth;
    if (convexPairContact(cache.shapes[s1], cache.pose_W[s1], cache.shapes[s2], cache.pose_W[s2],
                          point_W, normal_ab, depth))
      add(point_W, normal_ab, depth);
    return;
  }
  fcl::CollisionRequestd request(4, true);
  fcl::CollisionResultd result;
  fcl::collide(A.geometry.get(), cache.pose_W[s1], B.geometry.get(), cache.pose_W[s2], request,
               result);
  if (!result.isCollision()) return;
  cache.fcl_contacts.clear();
  result.getContacts(cache.fcl_contacts);
  for (const fcl::Contactd& f : cache.fcl_contacts)
    add(f.pos, f.normal, f.penetration_depth);  // FCL's normal points from o1 (a) to o2 (b)
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
