// Contact detection: the broad phase (sort and sweep of bounding spheres), the ground plane
// against shape vertices, and FCL for every other pair. FCL is included here only.
#include "contact/contact_detection.h"

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/scene/convex_hull.h"

namespace cga_rigid_sim {
namespace sim {

/// Per shape of every body (body order, then the body's shape order): its FCL geometry, the
/// points the ground plane is tested against, and a bounding sphere about the shape's origin.
class CollisionCache {
 public:
  struct Shape {
    int body = -1;
    int shape = -1;
    std::shared_ptr<fcl::CollisionGeometryd> geometry;
    std::vector<Eigen::Vector3d> vertices_S;  ///< box corners, mesh hull vertices (plane test)
    Eigen::Vector3d centre_S = Eigen::Vector3d::Zero();  ///< the bounding sphere's centre in S
    double bound = 0.0;                                  ///< bounding radius about centre_S, m
    /// The FCL geometry is this much larger on every side (0 for meshes), so that bodies
    /// about to touch are found a step early: a pair's depth is FCL's minus both margins.
    double margin = 0.0;
  };
  /// A shape's bounding sphere in the sweep: its extent along x, and its centre's y and z and
  /// its radius, so that the sweep rejects a pair from these alone (contiguous in memory).
  struct Interval {
    double lo, hi, y, z, bound;
    int shape;
    bool awake;  ///< a moving body that does not sleep (else static or asleep: inert)
  };

  bool built = false;
  std::uint64_t topology = 0;
  std::vector<Shape> shapes;
  // Scratch, reused every step.
  std::vector<Eigen::Isometry3d> pose_W;  ///< per shape, M_WS at the step's start
  std::vector<Eigen::Vector3d> centre_W;  ///< per shape, its bounding sphere's centre then
  std::vector<Interval> sweep;
  std::vector<int> awake_at;  ///< the positions in `sweep` of the awake shapes, ascending
  std::vector<fcl::Contactd> fcl_contacts;
  std::vector<std::pair<Eigen::Vector3d, int>> plane_points;  ///< one mesh's, before reduction
};

std::shared_ptr<CollisionCache> makeCollisionCache() { return std::make_shared<CollisionCache>(); }

namespace {

using Shape = scene::CollisionShape;

// Every vertex of a (welded) triangle mesh, once.
std::vector<Eigen::Vector3d> distinctVertices(const scene::TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> v = mesh.vertices;
  const auto less = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::sort(v.begin(), v.end(), less);
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// The speculative margin of a shape whose smallest extent is `size`: 5 mm (a body at 5 m/s
// moves that far in a step of 1 ms), at most a quarter of the extent so that the inflated
// shape keeps its form.
double marginOf(double size) { return std::min(0.005, 0.25 * size); }

CollisionCache::Shape makeShape(const Shape& s, int body, int index) {
  CollisionCache::Shape out;
  out.body = body;
  out.shape = index;
  switch (s.kind) {
    case Shape::Kind::kBox: {
      out.margin = marginOf(s.size.minCoeff());
      out.geometry =
          std::make_shared<fcl::Boxd>(s.size + Eigen::Vector3d::Constant(2 * out.margin));
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
      out.bound = s.radius;
      break;
    case Shape::Kind::kCylinder:
      out.margin = marginOf(std::min(2 * s.radius, s.length));
      out.geometry =
          std::make_shared<fcl::Cylinderd>(s.radius + out.margin, s.length + 2 * out.margin);
      out.bound = std::hypot(s.radius, 0.5 * s.length);
      break;
    case Shape::Kind::kMesh: {
      // A mesh collides as its convex hull (doc/contacts.md says so): FCL's GJK asks a convex
      // shape for its extreme vertices, and the plane can touch hull vertices only. A flat mesh
      // (no volume) keeps its own triangles.
      scene::ConvexHull hull = scene::convexHull(s.mesh.vertices);
      auto vertices = std::make_shared<std::vector<Eigen::Vector3d>>(hull.vertices);
      auto faces = std::make_shared<std::vector<int>>();
      int face_count = static_cast<int>(hull.triangles.size());
      if (face_count > 0) {
        for (const auto& t : hull.triangles) faces->insert(faces->end(), {3, t[0], t[1], t[2]});
      } else {
        *vertices = distinctVertices(s.mesh);
        std::vector<int> index(s.mesh.vertices.size());
        const auto less = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
          return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
        };
        for (std::size_t k = 0; k < s.mesh.vertices.size(); ++k)
          index[k] = static_cast<int>(
              std::lower_bound(vertices->begin(), vertices->end(), s.mesh.vertices[k], less) -
              vertices->begin());
        for (const auto& t : s.mesh.triangles)
          faces->insert(faces->end(), {3, index[t[0]], index[t[1]], index[t[2]]});
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
      out.geometry = std::make_shared<fcl::Convexd>(vertices, face_count, faces);
      break;
    }
  }
  return out;
}

void build(const Model& model, CollisionCache& cache) {
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

// The pose of body j at the step's start.
const cga::Motor& bodyPose(const Model& model, const Data& data, int j) {
  const int i = model.moving_of_body[j];
  return i >= 0 ? data.bodies[i].state.M_WB : model.scene.bodies[j].M_WB0;
}

// How far any point of moving body i can travel towards the plane in one step, m: the
// speculative margin of its plane contacts.
double travel(const Model& model, const Data& data, int i, double reach) {
  const double h = model.config.dt;
  const dynamics::BodyState& s = data.bodies[i].state;
  const double v = dynamics::comVelocity_W(s, model.lambda).norm();
  const double w = s.omega_B.angular().norm();
  return h * (v + w * reach) + h * h * data.bodies[i].loads.gravity().norm() + 1e-12;
}

// The combined parameters of two surfaces (doc/contacts.md#parameters): the smaller μ, the
// larger e — Gazebo's rule, so ROS URDFs behave as they do there; equal surfaces keep theirs.
void combine(const Model& model, const scene::SurfaceParameters& a,
             const scene::SurfaceParameters& b, Contact& c) {
  const double mu0 = model.config.contact_mu, e0 = model.config.contact_restitution;
  c.mu = std::min(a.mu.value_or(mu0), b.mu.value_or(mu0));
  c.restitution = std::max(a.restitution.value_or(e0), b.restitution.value_or(e0));
}

// Reduces points of a contact patch with the plane (world, normal +z) to at most four, in a
// deterministic way: the deepest; the one farthest from it across the plane; the one that makes
// the largest triangle with those two; the one that adds the most area to that triangle. The
// four span the patch, so a body resting on them is held as on the whole patch.
void reducePatch(std::vector<std::pair<Eigen::Vector3d, int>>& points) {
  const std::size_t n = points.size();
  if (n <= 4) return;
  const auto xy = [&points](std::size_t k) { return Eigen::Vector2d(points[k].first.head<2>()); };
  const auto area = [&](std::size_t a, std::size_t b, std::size_t c) {  // twice the triangle's
    const Eigen::Vector2d u = xy(b) - xy(a), w = xy(c) - xy(a);
    return std::abs(u.x() * w.y() - u.y() * w.x());
  };
  std::size_t pick[4] = {0, 0, 0, 0};
  for (std::size_t k = 1; k < n; ++k)
    if (points[k].first.z() < points[pick[0]].first.z()) pick[0] = k;
  double best = -1.0;
  for (std::size_t k = 0; k < n; ++k)
    if (const double d = (xy(k) - xy(pick[0])).squaredNorm(); d > best) best = d, pick[1] = k;
  best = -1.0;
  for (std::size_t k = 0; k < n; ++k)
    if (const double a = area(pick[0], pick[1], k); a > best) best = a, pick[2] = k;
  best = -1.0;
  const double base = area(pick[0], pick[1], pick[2]);
  for (std::size_t k = 0; k < n; ++k)
    if (const double gain = area(pick[0], pick[1], k) + area(pick[1], pick[2], k) +
                            area(pick[2], pick[0], k) - base;
        gain > best)
      best = gain, pick[3] = k;
  std::sort(pick, pick + 4);  // in vertex order, as detection reports them
  const std::size_t count = std::unique(pick, pick + 4) - pick;
  for (std::size_t k = 0; k < count; ++k) points[k] = points[pick[k]];
  points.resize(count);
}

// Shapes [first, last) against the plane; `fixed_margin` < 0: each body's travel over the step.
void planeContacts(const Model& model, const Data& data, CollisionCache& cache, std::size_t first,
                   std::size_t last, double fixed_margin, std::vector<Contact>& out,
                   const std::vector<char>* asleep = nullptr) {
  const GroundPlane& plane = *model.config.ground_plane;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  int last_body = -1;
  double margin = fixed_margin;
  for (std::size_t s = first; s < last; ++s) {
    const CollisionCache::Shape& cs = cache.shapes[s];
    const int i = model.moving_of_body[cs.body];
    if (i < 0) continue;
    if (asleep && !asleep->empty() && (*asleep)[i]) continue;
    const scene::BodyModel& body = model.scene.bodies[cs.body];
    const Shape& shape = body.shapes[cs.shape];
    if (cs.body != last_body && fixed_margin < 0) {
      // The body's shapes are consecutive in the cache, this one at its place among them.
      double reach = 0.0;
      for (std::size_t k = 0; k < body.shapes.size(); ++k) {
        const CollisionCache::Shape& other = cache.shapes[s - cs.shape + k];
        reach = std::max(reach, body.shapes[k].M_BS.translation(model.lambda).norm() +
                                    other.centre_S.norm() + other.bound);
      }
      margin = travel(model, data, i, reach);
      last_body = cs.body;
    }
    const Eigen::Isometry3d& X = cache.pose_W[s];
    const Eigen::Vector3d c = X.translation();
    if (cache.centre_W[s].z() - cs.bound - plane.height > margin) continue;  // far above
    const auto add = [&](const Eigen::Vector3d& p, int feature) {
      const double gap = p.z() - plane.height;
      if (gap > margin) return;
      Contact k;
      k.body_a = cs.body;
      k.shape_a = cs.shape;
      k.body_b = kGroundPlane;
      k.shape_b = -1;
      k.feature = feature;
      k.point_W = p;
      k.normal_W = up;
      k.depth = -gap;
      combine(model, shape.surface, plane.surface, k);
      out.push_back(k);
    };
    switch (shape.kind) {
      case Shape::Kind::kSphere:
        add(c - shape.radius * up, 0);
        break;
      case Shape::Kind::kCylinder: {
        const Eigen::Vector3d axis = X.linear().col(2);
        const Eigen::Vector3d across = up - up.dot(axis) * axis;  // ⟂ axis, towards +z
        const double tilt = across.norm();  // sin of the axis' angle from the vertical
        for (int rim = 0; rim < 2; ++rim) {
          const Eigen::Vector3d centre = c + (rim ? 0.5 : -0.5) * shape.length * axis;
          if (tilt > 1e-9) add(centre - shape.radius * across / tilt, 8 * rim);
          // Nearly upright, the lowest point of a rim runs round it as the body rocks: four
          // fixed rim points hold it steady.
          if (tilt < 0.2)
            for (int q = 0; q < 4; ++q) {
              const Eigen::Vector3d d = X.linear() * Eigen::Vector3d(q == 0   ? 1
                                                                     : q == 2 ? -1
                                                                              : 0,
                                                                     q == 1   ? 1
                                                                     : q == 3 ? -1
                                                                              : 0,
                                                                     0);
              add(centre + shape.radius * d, 8 * rim + 1 + q);
            }
        }
        break;
      }
      case Shape::Kind::kBox:
        // Rounded edges (doc/contact_model.md#rounded-edges): the corner of the box smaller by
        // r, pushed down by r: the lowest point of the ball swept round that corner.
        if (const double r =
                std::min(model.config.contact_model.box_edge_radius, 0.5 * shape.size.minCoeff());
            r > 0) {
          for (std::size_t v = 0; v < cs.vertices_S.size(); ++v) {
            const Eigen::Vector3d& corner = cs.vertices_S[v];
            add(X * (corner - r * corner.cwiseSign()) - r * up, static_cast<int>(v));
          }
          break;
        }
        for (std::size_t v = 0; v < cs.vertices_S.size(); ++v)
          add(X * cs.vertices_S[v], static_cast<int>(v));
        break;
      case Shape::Kind::kMesh: {
        // The hull's vertices within the margin, reduced to the four that span the contact
        // patch (a mesh's flat sole has dozens of coplanar vertices; four corners hold it).
        cache.plane_points.clear();
        for (std::size_t v = 0; v < cs.vertices_S.size(); ++v) {
          const Eigen::Vector3d p = X * cs.vertices_S[v];
          if (p.z() - plane.height <= margin)
            cache.plane_points.push_back({p, static_cast<int>(v)});
        }
        reducePatch(cache.plane_points);
        for (const auto& [p, v] : cache.plane_points) add(p, v);
        break;
      }
    }
  }
}

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
    combine(model, sa.surface, sb.surface, k);
    out.push_back(k);
  }
}

}  // namespace

void detectContacts(const Model& model, const Data& data, CollisionCache& cache,
                    std::vector<Contact>& out, const std::vector<char>* asleep) {
  const bool rebuilt = !cache.built || cache.topology != model.topology_version;
  if (rebuilt) build(model, cache);
  if (cache.shapes.empty()) return;
  const double lambda = model.lambda;
  // A moving body that sleeps (it keeps the pose of its last detection, unless the cache is
  // new); static bodies count as asleep.
  const auto sleeps = [&](int body) {
    const int i = model.moving_of_body[body];
    return i < 0 || (asleep && !asleep->empty() && (*asleep)[i]);
  };
  for (std::size_t s = 0; s < cache.shapes.size(); ++s) {
    const CollisionCache::Shape& cs = cache.shapes[s];
    if (!rebuilt && model.moving_of_body[cs.body] >= 0 && sleeps(cs.body)) continue;
    const cga::Motor M_WS =
        bodyPose(model, data, cs.body) * model.scene.bodies[cs.body].shapes[cs.shape].M_BS;
    cache.pose_W[s] = M_WS.toIsometry(lambda);
    cache.centre_W[s] = cache.pose_W[s] * cs.centre_S;
  }
  if (model.config.ground_plane)
    planeContacts(model, data, cache, 0, cache.shapes.size(), -1, out, asleep);

  // Broad phase: intervals of the bounding spheres along x, sorted; a pair is tested when its
  // intervals and its y and z extents overlap. Two inert shapes (static or asleep) are never
  // tested, so an inert shape looks only at the awake shapes after it in the sweep (found by
  // bisection in their positions) rather than at every shape its interval overlaps: a
  // sleeping pile costs the sort, not its pairs. The pairs come in the same order either way.
  cache.sweep.clear();
  for (std::size_t s = 0; s < cache.shapes.size(); ++s) {
    const Eigen::Vector3d& c = cache.centre_W[s];
    const double r = cache.shapes[s].bound;
    cache.sweep.push_back({c.x() - r, c.x() + r, c.y(), c.z(), r, static_cast<int>(s),
                           !sleeps(cache.shapes[s].body)});
  }
  std::sort(cache.sweep.begin(), cache.sweep.end(),
            [](const CollisionCache::Interval& a, const CollisionCache::Interval& b) {
              return a.lo < b.lo || (a.lo == b.lo && a.shape < b.shape);
            });
  cache.awake_at.clear();
  for (std::size_t p = 0; p < cache.sweep.size(); ++p)
    if (cache.sweep[p].awake) cache.awake_at.push_back(static_cast<int>(p));
  if (cache.awake_at.empty()) return;
  // Whether the bounding spheres' boxes overlap in y and z (x: the sweep's own test).
  const auto near = [&](const CollisionCache::Interval& I, const CollisionCache::Interval& J) {
    const double reach = I.bound + J.bound;
    return std::abs(J.y - I.y) <= reach && std::abs(J.z - I.z) <= reach;
  };
  const auto test = [&](std::size_t p, std::size_t q) {
    const int s1 = cache.sweep[p].shape, s2 = cache.sweep[q].shape;
    const CollisionCache::Shape& A = cache.shapes[s1];
    const CollisionCache::Shape& B = cache.shapes[s2];
    if (A.body == B.body) return;
    const bool a_moving = model.moving_of_body[A.body] >= 0;
    const bool b_moving = model.moving_of_body[B.body] >= 0;
    // Two bodies of one robot: only the pairs its self-collision rules allow
    // (doc/contacts.md#self-collision); never a link and its parent.
    if (!model.self_collision.collides(A.body, B.body)) return;
    const Eigen::Vector3d d = cache.centre_W[s2] - cache.centre_W[s1];
    const double r = A.bound + B.bound;
    if (d.squaredNorm() > r * r) return;  // (y and z: near(), checked before each call)
    // Body a is moving; of two moving bodies, the one that comes first in the scene.
    const bool a_first = a_moving && (!b_moving || A.body < B.body);
    if (a_first)
      pairContacts(model, cache, s1, s2, out);
    else
      pairContacts(model, cache, s2, s1, out);
  };
  for (std::size_t p = 0; p < cache.sweep.size(); ++p) {
    const double hi = cache.sweep[p].hi;
    if (cache.sweep[p].awake) {
      for (std::size_t q = p + 1; q < cache.sweep.size() && cache.sweep[q].lo <= hi; ++q)
        if (near(cache.sweep[p], cache.sweep[q])) test(p, q);
      continue;
    }
    for (auto it =
             std::upper_bound(cache.awake_at.begin(), cache.awake_at.end(), static_cast<int>(p));
         it != cache.awake_at.end() && cache.sweep[*it].lo <= hi; ++it)
      if (near(cache.sweep[p], cache.sweep[*it])) test(p, static_cast<std::size_t>(*it));
  }
}

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

void detectPlaneContactsOf(const Model& model, const Data& data, CollisionCache& cache, int j,
                           double margin, std::vector<Contact>& out) {
  if (!model.config.ground_plane) return;
  std::size_t first = cache.shapes.size(), last = first;
  for (std::size_t s = 0; s < cache.shapes.size(); ++s) {
    if (cache.shapes[s].body != j) continue;
    first = std::min(first, s);
    last = s + 1;
    cache.pose_W[s] =
        (bodyPose(model, data, j) * model.scene.bodies[j].shapes[cache.shapes[s].shape].M_BS)
            .toIsometry(model.lambda);
    cache.centre_W[s] = cache.pose_W[s] * cache.shapes[s].centre_S;
  }
  planeContacts(model, data, cache, first, last, margin, out);
}

}  // namespace sim
}  // namespace cga_rigid_sim
