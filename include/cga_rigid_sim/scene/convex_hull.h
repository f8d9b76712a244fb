// ConvexHull: the convex hull of a point set (a mesh's vertices), through Qhull (Debian
// libqhull-dev). Contacts treat a mesh as its convex hull (doc/contacts.md#detection): the hull's
// vertices are the only ones that can touch a plane or be a support point, and a robot's link
// mesh of thousands of vertices has a hull of a few hundred.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace cga_rigid_sim {
namespace scene {

struct ConvexHull {
  std::vector<Eigen::Vector3d> vertices;      ///< the hull's vertices (a subset of the points)
  std::vector<std::array<int, 3>> triangles;  ///< its faces as triangles, outward (counter-
                                              ///< clockwise seen from outside), into vertices
};

/// The convex hull of `points`. Points that span no volume (fewer than four, or all on a plane
/// or a line) have no hull of their own: then the distinct points are returned as vertices and
/// no triangles.
ConvexHull convexHull(const std::vector<Eigen::Vector3d>& points);

}  // namespace scene
}  // namespace cga_rigid_sim
