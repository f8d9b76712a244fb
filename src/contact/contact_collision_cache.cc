// The collision cache (doc/contacts.md#detection): per shape of every body its FCL geometry,
// inflated by a speculative margin, the points the ground plane is tested against and a
// bounding sphere, made once per topology (each step places the shapes: placeShape).
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "cga_rigid_sim/scene/convex_hull.h"
#include "contact/contact_detection_internals.h"

namespace cga_rigid_sim {
namespace sim {

std::shared_ptr<CollisionCache> makeCollisionCache() { return std::make_shared<CollisionCache>(); }

namespace detail {
namespace {

using Shape = scene::CollisionShape;

// Points in lexicographic order of their coordinates.
bool lexicographicLess(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}

// Every vertex of a (welded) triangle mesh, once.
std::vector<Eigen::Vector3d> distinctVertices(const scene::TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> v = mesh.vertices;
  std::sort(v.begin(), v.end(), lexicographicLess);
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// The speculative margin of a shape whose smallest extent is `size`: 5 mm (a body at 5 m/s
// moves that far in a step of 1 ms), at most a quarter of the extent so that the inflated
// shape keeps its form.
double marginOf(double size) { return std::min(0.005, 0.25 * size); }

// A mesh collides as its convex hull (doc/contacts.md says so): MPR asks a convex shape for its
// extreme vertices (contact_convex_pairs.cc), and the plane can touch hull vertices only. A flat
// mesh (no volume) keeps its own triangles. Every pair with a mesh goes to
// contact_convex_pairs.cc, so a mesh has no FCL geometry.
void makeMeshShape(const Shape& s, CollisionCache::Shape& out) {
  scene::ConvexHull hull = scene::convexHull(s.mesh.vertices);
  auto vertices = std::make_shared<std::vector<Eigen::Vector3d>>(hull.vertices);
  std::vector<int> faces;  // FCL's encoding: per face its vertex count, then its vertices
  int face_count = static_cast<int>(hull.triangles.size());
  const bool convex = face_count > 0;
  if (convex) {
    for (const auto& t : hull.triangles) faces.insert(faces.end(), {3, t[0], t[1], t[2]});
  } else {
    *vertices = distinctVertices(s.mesh);
    std::vector<int> index(s.mesh.vertices.size());
    for (std::size_t k = 0; k < s.mesh.vertices.size(); ++k)
      index[k] = static_cast<int>(std::lower_bound(vertices->begin(), vertices->end(),
                                                   s.mesh.vertices[k], lexicographicLess) -
                                  vertices->begin());
    for (const auto& t : s.mesh.triangles)
      faces.insert(faces.end(), {3, index[t[0]], index[t[1]], index[t[2]]});
    face_count = static_cast<int>(s.mesh.triangles.size());
  }
  out.vertices_S = *vertices;
  // The bounding sphere about the centre of the vertices' box, not the mesh's origin (a
  // link's mesh often sits far from its frame's origin).
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& v : *vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  out.centre_S = vertices->empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0.5 * (lo + hi));
  for (const auto& v : *vertices) out.bound = std::max(out.bound, (v - out.centre_S).norm());
  out.hull = makeHull(vertices, faces, face_count, convex);
}

CollisionCache::Shape makeShape(const Shape& s, int body, int index) {
  CollisionCache::Shape out;
  out.body = body;
  out.shape = index;
  switch (s.kind) {
    case Shape::Kind::kBox: {
      out.margin = marginOf(s.size.minCoeff());
      auto box = std::make_shared<fcl::Boxd>(s.size + Eigen::Vector3d::Constant(2 * out.margin));
      out.convex = CollisionCache::Shape::Convex::kBox;
      for (int k = 0; k < 3; ++k) out.extent[k] = box->side[k] / 2.0;
      out.geometry = box;
      const Eigen::Vector3d h = 0.5 * s.size;
      for (int k = 0; k < 8; ++k)
        out.vertices_S.emplace_back(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(),
                                    k & 4 ? h.z() : -h.z());
      out.bound = h.norm();
      break;
    }
    case Shape::Kind::kSphere:
      out.margin = marginOf(2 * s.radius);
      out.geometry = std::make_shared<fcl::Sphered>(s.radius + out.margin);
      out.convex = CollisionCache::Shape::Convex::kSphere;
      out.extent[0] = static_cast<const fcl::Sphered&>(*out.geometry).radius;
      out.bound = s.radius;
      break;
    case Shape::Kind::kCylinder: {
      out.margin = marginOf(std::min(2 * s.radius, s.length));
      auto cylinder =
          std::make_shared<fcl::Cylinderd>(s.radius + out.margin, s.length + 2 * out.margin);
      out.convex = CollisionCache::Shape::Convex::kCylinder;
      out.extent[0] = cylinder->radius;
      out.extent[1] = cylinder->lz / 2;
      out.geometry = cylinder;
      out.bound = std::hypot(s.radius, 0.5 * s.length);
      break;
    }
    case Shape::Kind::kMesh:
      makeMeshShape(s, out);
      break;
  }
  out.box_half_S = boxHalfSides(out);
  return out;
}

}  // namespace

void buildCollisionCache(const Model& model, CollisionCache& cache) {
  cache.shapes.clear();
  const auto& bodies = model.scene.bodies;
  for (int j = 0; j < static_cast<int>(bodies.size()); ++j) {
    for (int k = 0; k < static_cast<int>(bodies[j].shapes.size()); ++k)
      cache.shapes.push_back(makeShape(bodies[j].shapes[k], j, k));
  }
  cache.pose_W.resize(cache.shapes.size());
  cache.centre_W.resize(cache.shapes.size());
  cache.sweep.reserve(cache.shapes.size());
  cache.topology = model.topology_version;
  cache.built = true;
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
