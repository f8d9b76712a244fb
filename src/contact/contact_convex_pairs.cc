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
#include <limits>
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
// The support first climbs from a start table: a cube of directions, kStartCells² cells on each
// face (a cell spans at most 90°/kStartCells). Its end is taken if each neighbour is below it
// by more than kTieShare of |d|₁ times the hull's largest coordinate (Hull::tie_margin).
constexpr int kStartCells = 16;
constexpr double kTieShare = 1e-10;

// A shape placed in the world, in libccd's terms, and the last hull vertex its support gave,
// placed (MPR asks for the same vertex again and again).
struct Placed {
  CollisionCache::Shape* shape;
  ccd_vec3_t position;
  ccd_quat_t rotation, inverse;
  mutable const Eigen::Vector3d* last_vertex = nullptr;
  mutable ccd_vec3_t last_vertex_W;
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

// FCL's choice of the vertex farthest along d (Convex::findExtremeVertex): a walk from vertex 0
// to a neighbour at least as far until none is, each vertex looked at once (>=: a start coplanar
// with all its neighbours and perpendicular to d still walks on); small hulls are searched
// whole, the first of equals kept. Where several vertices are (or round to) equally far, which
// one it gives depends on this order.
int fclExtremeVertex(CollisionCache::Hull& h, const Eigen::Vector3d& d) {
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
  return best;
}

// The start table's cell of direction d, not zero and finite (d_abs: its components'
// magnitudes): the axis and sign of its largest component pick the cube's face, the other two
// components over it the cell.
int startCell(const Eigen::Vector3d& d, const double (&d_abs)[3]) {
  int face;
  double major, u, w;
  if (d_abs[0] >= d_abs[1] && d_abs[0] >= d_abs[2]) {
    face = d[0] < 0 ? 1 : 0, major = d_abs[0], u = d[1], w = d[2];
  } else if (d_abs[1] >= d_abs[2]) {
    face = d[1] < 0 ? 3 : 2, major = d_abs[1], u = d[2], w = d[0];
  } else {
    face = d[2] < 0 ? 5 : 4, major = d_abs[2], u = d[0], w = d[1];
  }
  const double to_cell = 0.5 * kStartCells / major;
  // u, w over the largest component lie in [−1, 1]: cells 0 … kStartCells − 1 (a rounding
  // below 0 truncates to 0)
  const int i = std::min(static_cast<int>(u * to_cell + 0.5 * kStartCells), kStartCells - 1);
  const int j = std::min(static_cast<int>(w * to_cell + 0.5 * kStartCells), kStartCells - 1);
  return (face * kStartCells + i) * kStartCells + j;
}

// The direction at the centre of the start table's cell `c` (startCell's inverse).
Eigen::Vector3d cellCentre(int c) {
  const int j = c % kStartCells, i = (c / kStartCells) % kStartCells,
            face = c / (kStartCells * kStartCells);
  const int axis = face / 2;
  Eigen::Vector3d d;
  d[axis] = face % 2 ? -1.0 : 1.0;
  d[(axis + 1) % 3] = (2.0 * i + 1.0) / kStartCells - 1.0;
  d[(axis + 2) % 3] = (2.0 * j + 1.0) / kStartCells - 1.0;
  return d;
}

// The vertex farthest along d by a climb from the start table's vertex for d's cell to the
// farthest neighbour while one is farther, where that end is FCL's: where each of its
// neighbours is below it by more than the tie margin. Then on a convex hull it is the farthest
// vertex in exact arithmetic too (the next farthest vertex of a convex hull is a neighbour of
// the farthest), no other vertex rounds to its value, so FCL's search picks it; and FCL's walk,
// which stops only where no neighbour is as far, stops there (a stop elsewhere would need a
// vertex whose neighbours all lie within rounding of it, yet far below: a vertex cone 10⁵
// times narrower than the hull; none was met in convex_pairs_test nor in any support query of
// Atlas's and the humanoid's first 4000 steps, each checked against the walk). −1 where a
// neighbour is within the margin (ties), d is not finite or the hull has no table.
int climbedExtremeVertex(const CollisionCache::Hull& h, const Eigen::Vector3d& d) {
  if (h.start.empty()) return -1;
  const double d_abs[3] = {std::abs(d[0]), std::abs(d[1]), std::abs(d[2])};
  const double d_l1 = d_abs[0] + d_abs[1] + d_abs[2];
  if (!(d_l1 > 0) || !(d_l1 <= std::numeric_limits<double>::max())) return -1;
  const std::vector<Eigen::Vector3d>& v = *h.vertices;
  int best = h.start[startCell(d, d_abs)];
  double best_value = d.dot(v[best]);
  for (;;) {
    const int first = h.neighbours[best] + 1;
    const int end = first + h.neighbours[first - 1];
    int next = first;
    double next_value = -std::numeric_limits<double>::infinity();
    for (int k = first; k < end; ++k) {
      const double value = d.dot(h.neighbour_vertices[k]);
      if (value > next_value) {
        next = k;
        next_value = value;
      }
    }
    if (next_value > best_value) {
      best = h.neighbours[next];
      best_value = next_value;
      continue;
    }
    return best_value - next_value > h.tie_margin * d_l1 ? best : -1;
  }
}

// The hull's vertex farthest along d (shape frame), as FCL picks it.
const Eigen::Vector3d& extremeVertex(CollisionCache::Hull& h, const Eigen::Vector3d& d) {
  const int climbed = climbedExtremeVertex(h, d);
  return (*h.vertices)[climbed >= 0 ? climbed : fclExtremeVertex(h, d)];
}

// A primitive's point farthest along d (shape frame) into `out`: a box's corner on the side of
// each component (a zero one counts as positive, so the point is always a corner), a sphere's
// point along d, a cylinder's rim point (the axis' end when d is along the axis).
void primitiveSupport(const CollisionCache::Shape& s, const ccd_vec3_t& d, ccd_vec3_t* out) {
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
    case Convex::kHull:  // support() places a hull's vertex itself
      return;
  }
}

// The shape's point farthest along world direction d, placed: d into the shape's frame and the
// point out of it by libccd's rotations, as FCL's support functions do.
void support(const void* object, const ccd_vec3_t* direction_W, ccd_vec3_t* out) {
  const auto* p = static_cast<const Placed*>(object);
  // libccd has just stored the direction as x, y in one 16-byte store and z in another
  // (__ccdSupport's copy). Read as three numbers: the rotation below, vectorised, would read
  // y, z as one 16-byte load across the two stores, which the store buffer cannot forward, and
  // every query would wait for them to reach the cache. (The empty asm keeps the three loads.)
  double x = direction_W->v[0], y = direction_W->v[1], z = direction_W->v[2];
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  asm("" : "+x"(x), "+x"(y), "+x"(z));  // ("x": an SSE register, x86-64 only)
#endif
  ccd_vec3_t d;
  ccdVec3Set(&d, x, y, z);
  ccdQuatRotVec(&d, &p->inverse);
  if (p->shape->convex == CollisionCache::Shape::Convex::kHull) {
    const Eigen::Vector3d& v =
        extremeVertex(*p->shape->hull, Eigen::Vector3d(d.v[0], d.v[1], d.v[2]));
    if (&v != p->last_vertex) {  // the same vertex placed again would give the same bits
      p->last_vertex = &v;
      ccdVec3Set(&p->last_vertex_W, v.x(), v.y(), v.z());
      ccdQuatRotVec(&p->last_vertex_W, &p->rotation);
      ccdVec3Add(&p->last_vertex_W, &p->position);
    }
    ccdVec3Copy(out, &p->last_vertex_W);
    return;
  }
  primitiveSupport(*p->shape, d, out);
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

// The hull's start table and tie margin (Hull::start, Hull::tie_margin). kTieShare of the
// largest coordinate, times |d|₁, is 3·10⁵ times the most rounding moves a dot product (3
// roundings of at most |d|₁ · the largest coordinate each): an end that beats its neighbours by
// it beats them in exact arithmetic too, by a gap no rounding closes. Added: four times the
// farthest a vertex stands out of a face's plane (Qhull's hull is convex only to its rounding).
void makeStartTable(CollisionCache::Hull& h, const std::vector<int>& faces, int face_count) {
  const std::vector<Eigen::Vector3d>& v = *h.vertices;
  double largest = 0;
  for (const Eigen::Vector3d& p : v) largest = std::max(largest, p.cwiseAbs().maxCoeff());
  double outside = 0;
  std::size_t at = 0;
  for (int f = 0; f < face_count; at += faces[at] + 1, ++f) {
    const Eigen::Vector3d& a = v[faces[at + 1]];
    Eigen::Vector3d normal = (v[faces[at + 2]] - a).cross(v[faces[at + 3]] - a);
    if (!(normal.norm() > 1e-9 * largest * largest)) continue;  // a sliver: no plane to speak of
    normal.normalize();
    if (normal.dot(h.interior - a) > 0) normal = -normal;
    for (const Eigen::Vector3d& p : v) outside = std::max(outside, normal.dot(p - a));
  }
  h.tie_margin = kTieShare * largest + 4.0 * outside;
  h.start.resize(6 * kStartCells * kStartCells);
  for (int c = 0; c < static_cast<int>(h.start.size()); ++c) {
    const Eigen::Vector3d d = cellCentre(c);
    int best = 0;
    for (int k = 1; k < static_cast<int>(v.size()); ++k)
      if (d.dot(v[k]) > d.dot(v[best])) best = k;
    h.start[c] = best;
  }
}

}  // namespace

std::shared_ptr<CollisionCache::Hull> makeHull(
    std::shared_ptr<const std::vector<Eigen::Vector3d>> vertices, const std::vector<int>& faces,
    int face_count, bool convex) {
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
  h->neighbour_vertices.resize(h->neighbours.size(), Eigen::Vector3d::Zero());
  for (int v = 0; v < n; ++v)
    for (int k = h->neighbours[v] + 1; k <= h->neighbours[v] + h->neighbours[h->neighbours[v]]; ++k)
      h->neighbour_vertices[k] = (*vertices)[h->neighbours[k]];
  h->vertices = std::move(vertices);
  if (convex && n > 0) makeStartTable(*h, faces, face_count);
  return h;
}

const Eigen::Vector3d& hullExtremeVertex(CollisionCache::Hull& h, const Eigen::Vector3d& d,
                                         bool& climbed) {
  const int end = climbedExtremeVertex(h, d);
  climbed = end >= 0;
  return (*h.vertices)[climbed ? end : fclExtremeVertex(h, d)];
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
