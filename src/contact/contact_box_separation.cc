// The shapes' boxes (doc/contacts.md#detection): an oriented box about each shape's bounding
// sphere's centre, along the shape's axes, that holds the shape as the narrow phase sees it.
// Two shapes whose bounding spheres overlap are often still far apart: the links of a robot
// are long and thin, and a sphere about a shin holds the knee and the foot beside it. The 15
// axes of two boxes tell most such pairs apart far more cheaply than MPR can (measured in
// doc/contacts.md#detection).
#include <cmath>
#include <limits>

#include "contact/contact_detection_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {
namespace {

// The spare on every side of a box: MPR stops at a tolerance of 1e-6 (contact_convex_pairs.cc),
// so two shapes closer than that may still be reported touching; the spare keeps such pairs
// for the narrow phase. Relative to the shape's size for large shapes, so that rounding in the
// box's placement (~1e-16 of the distances) never matters.
constexpr double kSpare = 1e-5, kRelativeSpare = 1e-9;

}  // namespace

Eigen::Vector3d boxHalfSides(const CollisionCache::Shape& s) {
  using Convex = CollisionCache::Shape::Convex;
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  switch (s.convex) {
    case Convex::kBox:
      half = Eigen::Vector3d(s.extent[0], s.extent[1], s.extent[2]);
      break;
    case Convex::kSphere:
      half = Eigen::Vector3d::Constant(s.extent[0]);
      break;
    case Convex::kCylinder:  // its axis is S's z
      half = Eigen::Vector3d(s.extent[0], s.extent[0], s.extent[1]);
      break;
    case Convex::kHull: {
      if (!s.hull) break;
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
      Eigen::Vector3d hi = -lo;
      for (const Eigen::Vector3d& v : *s.hull->vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
      if (s.hull->vertices->empty()) break;
      half = (hi - s.centre_S).cwiseMax(s.centre_S - lo);
      break;
    }
  }
  // (a primitive's centre_S is its origin: its extent is about it)
  return half + Eigen::Vector3d::Constant(kSpare + kRelativeSpare * half.maxCoeff());
}

bool boxesApart(const CollisionCache& cache, int s1, int s2) {
  const Eigen::Vector3d& a = cache.shapes[s1].box_half_S;
  const Eigen::Vector3d& b = cache.shapes[s2].box_half_S;
  const Eigen::Matrix3d& A = cache.pose_W[s1].linear();
  const Eigen::Matrix3d& B = cache.pose_W[s2].linear();
  // B's axes and the centres' offset in A's frame (Gottschalk's separating axis test).
  const Eigen::Matrix3d R = A.transpose() * B;
  const Eigen::Vector3d t = A.transpose() * (cache.centre_W[s2] - cache.centre_W[s1]);
  Eigen::Matrix3d abs_R = R.cwiseAbs();
  // A's axes, then B's.
  for (int i = 0; i < 3; ++i)
    if (std::abs(t[i]) > a[i] + abs_R.row(i).dot(b)) return true;
  for (int j = 0; j < 3; ++j)
    if (std::abs(t.dot(R.col(j))) > abs_R.col(j).dot(a) + b[j]) return true;
  // The nine cross products of an axis of A and one of B. Where two axes are parallel their
  // cross product vanishes and its test must not claim a gap: the epsilon keeps |R| from
  // reading exactly zero there.
  abs_R.array() += 1e-12;
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = a[i1] * abs_R(i2, j) + a[i2] * abs_R(i1, j);
      const double rb = b[j1] * abs_R(i, j2) + b[j2] * abs_R(i, j1);
      if (std::abs(t[i2] * R(i1, j) - t[i1] * R(i2, j)) > ra + rb) return true;
    }
  }
  return false;
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
