// Contact detection's internals (contact_detection.h), shared by its files and by nothing else:
// the collision cache (per shape its FCL geometry or hull, plane points, bounding sphere) and the
// narrow phases the broad phase hands its pairs to. FCL is included by the detection's files
// only:
//
//   contact_collision_cache.cc   the cache: its shapes, made once per topology
//   contact_detection.cc         detectContacts: the broad phase (sort and sweep)
//   contact_ground_plane.cc      the ground plane against each shape's points
//   contact_shape_pairs.cc       every other pair: a hull and a hull, box, sphere or cylinder
//                                by contact_convex_pairs.cc, the rest through FCL
//   contact_convex_pairs.cc      those pairs through libccd's MPR, allocation-free
//   contact_box_separation.cc    the shapes' boxes, which tell most pairs apart before MPR
//   contact_overlap_warnings.cc  the overlaps a World reports when it is created
#pragma once

#include <fcl/geometry/collision_geometry.h>
#include <fcl/narrowphase/contact.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "contact/contact_detection.h"

namespace cga_rigid_sim {
namespace sim {

/// Per shape of every body (body order, then the body's shape order): its FCL geometry (a
/// mesh: its hull instead), the
/// points the ground plane is tested against, and a bounding sphere about the shape's origin.
class CollisionCache {
 public:
  /// A mesh's convex hull as the narrow phase of two hulls walks it (contact_convex_pairs.cc):
  /// Walked as FCL's Convex would walk the same vertices and faces.
  struct Hull {
    std::shared_ptr<const std::vector<Eigen::Vector3d>> vertices;
    /// Per vertex v: at neighbours[v] the count of its neighbours along the faces' edges, then
    /// those neighbours in ascending order (FCL's encoding of a Convex's vertex graph).
    std::vector<int> neighbours;
    /// At each neighbour's place in `neighbours`, that neighbour's vertex (the climb reads a
    /// vertex's neighbours in a row).
    std::vector<Eigen::Vector3d> neighbour_vertices;
    Eigen::Vector3d interior = Eigen::Vector3d::Zero();  ///< the vertices' mean (MPR's start)
    /// Scratch of the support walk: a vertex is visited in this query if its mark equals
    /// `generation` (one increment per query instead of clearing the marks).
    std::vector<std::uint32_t> mark;
    std::uint32_t generation = 0;
    /// Where the support's climb starts (contact_convex_pairs.cc): per cell of a cube map of
    /// directions (kStartCells² on each of the cube's six faces), the vertex farthest along the
    /// cell's centre. Empty where the faces are not a convex hull's (a flat mesh's own
    /// triangles): there only FCL's walk from vertex 0 gives FCL's vertex.
    std::vector<int> start;
    /// A climb's end is taken only if each of its neighbours is below it by more than this
    /// times |d|₁ (the dot products' rounding, the hull's own departures from convexity, with
    /// room to spare); otherwise FCL's walk from vertex 0 decides.
    double tie_margin = 0;
  };
  struct Shape {
    int body = -1;
    int shape = -1;
    std::shared_ptr<fcl::CollisionGeometryd> geometry;
    std::vector<Eigen::Vector3d> vertices_S;  ///< box corners, mesh hull vertices (plane test)
    Eigen::Vector3d centre_S = Eigen::Vector3d::Zero();  ///< the bounding sphere's centre in S
    double bound = 0.0;                                  ///< bounding radius about centre_S, m
    /// Half the sides of a box about centre_S, along S's axes, holding the shape as the narrow
    /// phase sees it (margins included), with a little to spare (contact_box_separation.cc).
    Eigen::Vector3d box_half_S = Eigen::Vector3d::Zero();
    /// The FCL geometry is this much larger on every side (0 for meshes), so that bodies
    /// about to touch are found a step early: a pair's depth is FCL's minus both margins.
    double margin = 0.0;
    /// The shape as MPR sees it (contact_convex_pairs.cc): a mesh's hull, or the inflated box,
    /// sphere or cylinder of `geometry` (box: half sides; sphere: radius; cylinder: radius and
    /// half length), read from it so that both see the same numbers.
    enum class Convex { kHull, kBox, kSphere, kCylinder };
    Convex convex = Convex::kHull;
    double extent[3] = {0.0, 0.0, 0.0};
    std::shared_ptr<Hull> hull;  ///< meshes only
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

namespace detail {

/// The combined parameters of two surfaces (doc/contacts.md#surfaces-and-their-parameters): the
/// smaller μ, the larger e — Gazebo's rule, so ROS URDFs behave as they do there; equal
/// surfaces keep theirs.
inline void combineSurfaces(const Model& model, const scene::SurfaceParameters& a,
                            const scene::SurfaceParameters& b, Contact& c) {
  const double mu0 = model.config.contact_mu, e0 = model.config.contact_restitution;
  c.mu = std::min(a.mu.value_or(mu0), b.mu.value_or(mu0));
  c.restitution = std::max(a.restitution.value_or(e0), b.restitution.value_or(e0));
}

/// Makes the cache's shapes for `model` (contact_collision_cache.cc).
void buildCollisionCache(const Model& model, CollisionCache& cache);
/// The pose of body j at the step's start.
inline const cga::Motor& bodyPose(const Model& model, const Data& data, int j) {
  const int i = model.moving_of_body[j];
  return i >= 0 ? data.bodies[i].state.M_WB : model.scene.bodies[j].M_WB0;
}

/// Shape s's pose and bounding sphere's centre, world, at its body's pose of the step's start.
inline void placeShape(const Model& model, const Data& data, CollisionCache& cache, std::size_t s) {
  const CollisionCache::Shape& cs = cache.shapes[s];
  const cga::Motor M_WS =
      bodyPose(model, data, cs.body) * model.scene.bodies[cs.body].shapes[cs.shape].M_BS;
  cache.pose_W[s] = M_WS.toIsometry(model.lambda);
  cache.centre_W[s] = cache.pose_W[s] * cs.centre_S;
}

/// Reduces the points of a contact patch with the plane (world, normal +z; each with its
/// vertex, in vertex order) to at most four, in a deterministic way: a deepest; the one farthest
/// from it across the plane; the one that makes the largest triangle with those two; the one
/// that adds the most area to that triangle. The four span the patch, so a body resting on them
/// is held as on the whole patch. Near-ties go to the first point in vertex order, the deepest
/// among points within 5e-6 m of each other's depth included (a tenth of the solver's slop): a
/// mesh's flat sole resting on the plane has a dozen vertices level to a micrometre, and which
/// is lowest by 1e-10 m changes with every step's rocking; taking it would change the four from
/// step to step, and with them the rows whose impulses the next step starts from
/// (doc/contacts.md#a-patch-on-the-plane). contact_ground_plane.cc.
void reducePatch(std::vector<std::pair<Eigen::Vector3d, int>>& points);

/// Appends the contacts of shapes [first, last) with the ground plane, at their placed poses;
/// `fixed_margin` < 0: each body's travel over the step is its speculative margin. `asleep` as
/// for detectContacts (contact_ground_plane.cc).
void planeContacts(const Model& model, const Data& data, CollisionCache& cache, std::size_t first,
                   std::size_t last, double fixed_margin, std::vector<Contact>& out,
                   const std::vector<char>* asleep = nullptr);

/// The hull of `vertices` whose faces are given in FCL's encoding (per face its vertex count,
/// then its vertices), with its vertex graph and interior point (contact_convex_pairs.cc);
/// `convex`: the faces are the vertices' convex hull (Qhull's), so that the support may climb
/// from a start table (Hull::start).
std::shared_ptr<CollisionCache::Hull> makeHull(
    std::shared_ptr<const std::vector<Eigen::Vector3d>> vertices, const std::vector<int>& faces,
    int face_count, bool convex);

/// The vertex of hull h farthest along d (the hull's frame) as FCL's Convex::findExtremeVertex
/// picks it, as the narrow phase's support finds it; `climbed`: found by the climb from the
/// start table (else by FCL's walk from vertex 0, or search) (contact_convex_pairs.cc).
const Eigen::Vector3d& hullExtremeVertex(CollisionCache::Hull& h, const Eigen::Vector3d& d,
                                         bool& climbed);

/// Two shapes placed at M_WA and M_WB, at least one a hull: whether they overlap and, if so,
/// the deepest point, the normal from a to b and the depth of their overlap, as FCL's narrow
/// phase gives them for a Convex and a Convex, Box, Sphere or Cylinder (libccd's MPR on the same
/// support and interior points, FCL's tolerance and iteration bound), without allocating
/// (contact_convex_pairs.cc).
bool convexPairContact(CollisionCache::Shape& a, const Eigen::Isometry3d& M_WA,
                       CollisionCache::Shape& b, const Eigen::Isometry3d& M_WB,
                       Eigen::Vector3d& point_W, Eigen::Vector3d& normal_W, double& depth);

/// The box that holds shape `s` as the narrow phase sees it, for Shape::box_half_S: its hull's
/// or inflated primitive's extent along S's axes about centre_S, widened by a spare
/// (contact_box_separation.cc).
Eigen::Vector3d boxHalfSides(const CollisionCache::Shape& s);

/// Whether the boxes of shapes s1 and s2 at their placed poses are apart (a separating axis
/// among the 15 of two boxes): then the shapes are, and the narrow phase would find nothing
/// (contact_box_separation.cc).
bool boxesApart(const CollisionCache& cache, int s1, int s2);

/// Appends the contacts of shapes s1 (side a) and s2 (side b) at their placed poses
/// (contact_shape_pairs.cc).
void pairContacts(const Model& model, CollisionCache& cache, int s1, int s2,
                  std::vector<Contact>& out);

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
