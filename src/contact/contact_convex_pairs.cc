// The narrow phase of a mesh's hull and a hull, box, sphere or cylinder
// (doc/contacts.md#detection): libccd's Minkowski Portal Refinement, as FCL runs it for a Convex
// and those shapes (its GJKSolver_libccd: the same support and interior points, tolerance and
// iteration bound), called here directly so that a step does not allocate. FCL's Convex
// allocates its visit marks on every support query and FCL a libccd object per shape on every
// pair; here the marks live in the hull and the objects on the stack.
#include <ccd/ccd.h>
#include <ccd/quat.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "contact/contact_detection_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {
namespace {

// FCL walks a hull's vertex graph for the support point from this many vertices on (fewer:
// it looks at every vertex), and stops MPR at this tolerance and iteration count.
constexpr std::size_t kWalkFromVertices = 32;
constexpr double kMprTolerance = 1e-6;
constexpr unsigned long kMprIterations = 500;

// A shape placed in the world, in libccd's terms.
struct Placed {
  CollisionCache::Shape* shape;
  ccd_vec3_t position;
  ccd_quat_t rotation, inverse;
};

Placed place(CollisionCache::Shape& shape, const Eigen::Isometry3d& M_WS) {
  Placed p;
  p.shape = &shape;
  const Eigen::Quaterniond q(M_WS.linear());
  const Eigen::Vector3d& t = M_WS.translation();
  ccdVec3Set(&p.position, t.x(), t.y(), t.z());
  ccdQuatSet(&p.rotation, q.x(), q.y(), q.z(), q.w());
  ccdQuatInvert2(&p.inverse, &p.rotation);
  return p;
}

// The hull's vertex farthest along d (shape frame): a walk from vertex 0 to a neighbour at
// least as far until none is, each vertex looked at once (>=: a start coplanar with all its
// neighbours and perpendicular to d still walks on); small hulls are searched whole.
const Eigen::Vector3d& extremeVertex(CollisionCache::Hull& h, const Eigen::Vector3d& d) {
  const std::vector<Eigen::Vector3d>& v = *h.vertices;
  int best = 0;
  double best_value = d.dot(v[0]);
  if (v.size() > kWalkFromVertices) {
    if (++h.generation == 0) {  // wrapped: no stale mark may equal the new generation
      std::fill(h.mark.begin(), h.mark.end(), 0u);
      h.generation = 1;
    }
    bool moved = true;
    while (moved) {
      moved = false;
      const int start = h.neighbours[best];
      const int count = h.neighbours[start];
      for (int k = start + 1; k <= start + count; ++k) {
        const int n = h.neighbours[k];
        if (h.mark[n] == h.generation) continue;
        h.mark[n] = h.generation;
        const double value = d.dot(v[n]);
        if (value >= best_value) {
          moved = true;
          best = n;
          best_value = value;
        }
      }
    }
  } else {
    for (int k = 1; k < static_cast<int>(v.size()); ++k) {
      const double value = d.dot(v[k]);
      if (value > best_value) {
        best = k;
        best_value = value;
      }
    }
  }
  return v[best];
}

// The shape's point farthest along d (shape frame) into `out`: a box's corner on the side of
// each component (a zero one counts as positive, so the point is always a corner), a sphere's
// point along d, a cylinder's rim point (the axis' end when d is along the axis), a hull's vertex.
void supportInShape(CollisionCache::Shape& s, const ccd_vec3_t& d, ccd_vec3_t* out) {
  using Convex = CollisionCache::Shape::Convex;
  const double* e = s.extent;
  switch (s.convex) {
    case Convex::kBox: {
      const auto side = [](double x) { return x >= 0 ? 1.0 : -1.0; };
      ccdVec3Set(out, side(d.v[0]) * e[0], side(d.v[1]) * e[1], side(d.v[2]) * e[2]);
      return;
    }
    case Convex::kSphere:
      ccdVec3Copy(out, &d);
      ccdVec3Scale(out, e[0]);
      ccdVec3Scale(out, CCD_ONE / CCD_SQRT(ccdVec3Len2(&d)));
      return;
    case Convex::kCylinder: {
      const double across = std::sqrt(d.v[0] * d.v[0] + d.v[1] * d.v[1]);
      if (ccdIsZero(across)) {
        ccdVec3Set(out, 0.0, 0.0, ccdSign(d.v[2]) * e[1]);
      } else {
        const double r = e[0] / across;
        ccdVec3Set(out, r * d.v[0], r * d.v[1], ccdSign(d.v[2]) * e[1]);
      }
      return;
    }
    case Convex::kHull: {
      const Eigen::Vector3d& v = extremeVertex(*s.hull, Eigen::Vector3d(d.v[0], d.v[1], d.v[2]));
      ccdVec3Set(out, v.x(), v.y(), v.z());
      return;
    }
  }
}

void support(const void* object, const ccd_vec3_t* direction_W, ccd_vec3_t* out) {
  const auto* p = static_cast<const Placed*>(object);
  ccd_vec3_t d;
  ccdVec3Copy(&d, direction_W);
  ccdQuatRotVec(&d, &p->inverse);
  supportInShape(*p->shape, d, out);
  ccdQuatRotVec(out, &p->rotation);
  ccdVec3Add(out, &p->position);
}

// MPR's interior point: a hull's vertices' mean, placed; a primitive's centre.
void interior(const void* object, ccd_vec3_t* out) {
  const auto* p = static_cast<const Placed*>(object);
  if (p->shape->convex != CollisionCache::Shape::Convex::kHull) {
    ccdVec3Copy(out, &p->position);
    return;
  }
  const Eigen::Vector3d& c = p->shape->hull->interior;
  ccdVec3Set(out, c.x(), c.y(), c.z());
  ccdQuatRotVec(out, &p->rotation);
  ccdVec3Add(out, &p->position);
}

}  // namespace

std::shared_ptr<CollisionCache::Hull> makeHull(
    std::shared_ptr<const std::vector<Eigen::Vector3d>> vertices, const std::vector<int>& faces,
    int face_count) {
  auto h = std::make_shared<CollisionCache::Hull>();
  const int n = static_cast<int>(vertices->size());
  std::vector<std::set<int>> next(n);
  std::size_t at = 0;
  for (int f = 0; f < face_count; ++f) {
    const int corners = faces[at];
    int previous = faces[at + corners];
    for (std::size_t k = at + 1; k <= at + corners; ++k) {
      next[faces[k]].insert(previous);
      next[previous].insert(faces[k]);
      previous = faces[k];
    }
    at += corners + 1;
  }
  h->neighbours.resize(n);
  for (int v = 0; v < n; ++v) {
    h->neighbours[v] = static_cast<int>(h->neighbours.size());
    h->neighbours.push_back(static_cast<int>(next[v].size()));
    h->neighbours.insert(h->neighbours.end(), next[v].begin(), next[v].end());
  }
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& v : *vertices) sum += v;
  h->interior = sum * (1.0 / n);
  h->mark.assign(n, 0u);
  h->vertices = std::move(vertices);
  return h;
}

bool convexPairContact(CollisionCache::Shape& a, const Eigen::Isometry3d& M_WA,
                       CollisionCache::Shape& b, const Eigen::Isometry3d& M_WB,
                       Eigen::Vector3d& point_W, Eigen::Vector3d& normal_W, double& depth) {
  const Placed pa = place(a, M_WA), pb = place(b, M_WB);
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = &support;
  ccd.support2 = &support;
  ccd.center1 = &interior;
  ccd.center2 = &interior;
  ccd.max_iterations = kMprIterations;
  ccd.mpr_tolerance = kMprTolerance;
  ccd_real_t d;
  ccd_vec3_t direction, position;
  if (ccdMPRPenetration(&pa, &pb, &ccd, &d, &direction, &position) != 0) return false;
  point_W = Eigen::Vector3d(position.v[0], position.v[1], position.v[2]);
  normal_W = Eigen::Vector3d(direction.v[0], direction.v[1], direction.v[2]);
  depth = d;
  return true;
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
