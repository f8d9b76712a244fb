// The ground plane's narrow phase (doc/contacts.md#detection): each shape's points against the
// plane — the lowest point of a sphere, a box's corners (rounded: doc/contact_model.md), a mesh
// hull's vertices reduced to four that span its patch, the rims of a cylinder — with a
// speculative margin of the body's travel over the step, so that a body about to land is caught
// in the step it lands.
#include <algorithm>
#include <cmath>

#include "cga_rigid_sim/body/derived.h"
#include "contact/contact_detection_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {

// Points of a patch whose depths differ by less than this (m) are equally deep for the choice
// below: a tenth of the overlap the solver leaves uncorrected (SolverSettings::slop, 5e-5 m), so
// the four chosen may miss the deepest point by no more than that.
constexpr double kLevelTolerance = 5e-6;
// A maximum within this fraction of the best so far is a tie, kept by the first point.
constexpr double kTieFraction = 1e-6;

void reducePatch(std::vector<std::pair<Eigen::Vector3d, int>>& points) {
  const std::size_t n = points.size();
  if (n <= 4) return;
  const auto xy = [&points](std::size_t k) { return Eigen::Vector2d(points[k].first.head<2>()); };
  const auto area = [&](std::size_t a, std::size_t b, std::size_t c) {  // twice the triangle's
    const Eigen::Vector2d u = xy(b) - xy(a), w = xy(c) - xy(a);
    return std::abs(u.x() * w.y() - u.y() * w.x());
  };
  // The first of the points, in vertex order, that beats `best` by more than a tie.
  const auto argmax = [n](const auto& value) {
    double best = -1.0;
    std::size_t pick = 0;
    for (std::size_t k = 0; k < n; ++k)
      if (const double v = value(k); v > best + kTieFraction * std::abs(best)) best = v, pick = k;
    return pick;
  };
  std::size_t pick[4] = {0, 0, 0, 0};
  double lowest = points[0].first.z();
  for (std::size_t k = 1; k < n; ++k) lowest = std::min(lowest, points[k].first.z());
  while (points[pick[0]].first.z() > lowest + kLevelTolerance) ++pick[0];
  pick[1] = argmax([&](std::size_t k) { return (xy(k) - xy(pick[0])).squaredNorm(); });
  pick[2] = argmax([&](std::size_t k) { return area(pick[0], pick[1], k); });
  const double base = area(pick[0], pick[1], pick[2]);
  pick[3] = argmax([&](std::size_t k) {
    return area(pick[0], pick[1], k) + area(pick[1], pick[2], k) + area(pick[2], pick[0], k) - base;
  });
  std::sort(pick, pick + 4);  // in vertex order, as detection reports them
  const std::size_t count = std::unique(pick, pick + 4) - pick;
  for (std::size_t k = 0; k < count; ++k) points[k] = points[pick[k]];
  points.resize(count);
}

namespace {

using Shape = scene::CollisionShape;

// How far any point of moving body i can travel towards the plane in one step, m: the
// speculative margin of its plane contacts.
double travel(const Model& model, const Data& data, int i, double reach) {
  const double h = model.config.dt;
  const dynamics::BodyState& s = data.bodies[i].state;
  const double v = dynamics::comVelocity_W(s, model.lambda).norm();
  const double w = s.omega_B.angular().norm();
  return h * (v + w * reach) + h * h * data.bodies[i].loads.gravity().norm() + 1e-12;
}

// The speculative margin of moving body i's plane contacts, whose shapes start at shape s of
// the cache (the body's shapes are consecutive in the cache, s at its place among them).
double bodyMargin(const Model& model, const Data& data, const CollisionCache& cache, int i,
                  std::size_t s) {
  const CollisionCache::Shape& cs = cache.shapes[s];
  const scene::BodyModel& body = model.scene.bodies[cs.body];
  double reach = 0.0;
  for (std::size_t k = 0; k < body.shapes.size(); ++k) {
    const CollisionCache::Shape& other = cache.shapes[s - cs.shape + k];
    reach = std::max(reach, body.shapes[k].M_BS.translation(model.lambda).norm() +
                                other.centre_S.norm() + other.bound);
  }
  return travel(model, data, i, reach);
}

// The rims of a cylinder at pose X: the lowest point of each, and four fixed points of each
// when it stands nearly upright; add(point, feature) for each.
template <class Add>
void cylinderRims(const Eigen::Isometry3d& X, const Shape& shape, Add&& add) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d c = X.translation();
  const Eigen::Vector3d axis = X.linear().col(2);
  const Eigen::Vector3d across = up - up.dot(axis) * axis;  // ⟂ axis, towards +z
  const double tilt = across.norm();  // sin of the axis' angle from the vertical
  for (int rim = 0; rim < 2; ++rim) {
    const Eigen::Vector3d centre = c + (rim ? 0.5 : -0.5) * shape.length * axis;
    if (tilt > 1e-9) add(centre - shape.radius * across / tilt, 8 * rim);
    // Nearly upright, the lowest point of a rim runs round it as the body rocks: four fixed rim
    // points hold it steady.
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
}

// Appends the contacts of shape s with the plane whose gap is within `margin`.
void shapeOnPlane(const Model& model, CollisionCache& cache, std::size_t s, double margin,
                  std::vector<Contact>& out) {
  const GroundPlane& plane = *model.config.ground_plane;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const CollisionCache::Shape& cs = cache.shapes[s];
  const Shape& shape = model.scene.bodies[cs.body].shapes[cs.shape];
  const Eigen::Isometry3d& X = cache.pose_W[s];
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
    combineSurfaces(model, shape.surface, plane.surface, k);
    out.push_back(k);
  };
  switch (shape.kind) {
    case Shape::Kind::kSphere:
      add(X.translation() - shape.radius * up, 0);
      break;
    case Shape::Kind::kCylinder:
      cylinderRims(X, shape, add);
      break;
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
      // A vertex is placed (X * v, the test's own arithmetic) only where its height, from X's
      // last row alone, is not clearly above the margin: most of a hull's vertices are far
      // above. The two heights differ by a few roundings of the terms (≤ 1e-15 of their size);
      // `slack`, 1e-9 of a bound on every term, keeps each vertex the exact test could take.
      cache.plane_points.clear();
      const Eigen::Vector3d row = X.linear().row(2).transpose();
      const double z0 = X.translation().z();
      const double slack = 1e-9 * (cs.centre_S.norm() + cs.bound + std::abs(z0) +
                                   std::abs(plane.height) + std::abs(margin));
      const double skip_above = plane.height + margin + slack;
      for (std::size_t v = 0; v < cs.vertices_S.size(); ++v) {
        if (row.dot(cs.vertices_S[v]) + z0 > skip_above) continue;
        const Eigen::Vector3d p = X * cs.vertices_S[v];
        if (p.z() - plane.height <= margin) cache.plane_points.push_back({p, static_cast<int>(v)});
      }
      reducePatch(cache.plane_points);
      for (const auto& [p, v] : cache.plane_points) add(p, v);
      break;
    }
  }
}

}  // namespace

void planeContacts(const Model& model, const Data& data, CollisionCache& cache, std::size_t first,
                   std::size_t last, double fixed_margin, std::vector<Contact>& out,
                   const std::vector<char>* asleep) {
  const GroundPlane& plane = *model.config.ground_plane;
  int last_body = -1;
  double margin = fixed_margin;
  for (std::size_t s = first; s < last; ++s) {
    const CollisionCache::Shape& cs = cache.shapes[s];
    const int i = model.moving_of_body[cs.body];
    if (i < 0) continue;
    if (asleep && !asleep->empty() && (*asleep)[i]) continue;
    if (cs.body != last_body && fixed_margin < 0) {
      margin = bodyMargin(model, data, cache, i, s);
      last_body = cs.body;
    }
    if (cache.centre_W[s].z() - cs.bound - plane.height > margin) continue;  // far above
    shapeOnPlane(model, cache, s, margin, out);
  }
}

}  // namespace detail

void detectPlaneContactsOf(const Model& model, const Data& data, CollisionCache& cache, int j,
                           double margin, std::vector<Contact>& out) {
  if (!model.config.ground_plane) return;
  std::size_t first = cache.shapes.size(), last = first;
  for (std::size_t s = 0; s < cache.shapes.size(); ++s) {
    if (cache.shapes[s].body != j) continue;
    first = std::min(first, s);
    last = s + 1;
    detail::placeShape(model, data, cache, s);
  }
  detail::planeContacts(model, data, cache, first, last, margin, out);
}

}  // namespace sim
}  // namespace cga_rigid_sim
