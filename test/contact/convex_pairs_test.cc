// Two convex hulls' narrow phase (src/contact/contact_convex_pairs.cc) against FCL's for the same
// two Convex shapes, which it replaces: the same algorithm (libccd's MPR) on the same support and
// interior points, so the same answer to the last bit; and it allocates nothing.
#include <fcl/geometry/shape/convex.h>
#include <fcl/narrowphase/collision.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cga_rigid_sim/scene/convex_hull.h"
#include "contact/contact_detection_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace convex_pairs_test {

struct TestHull {
  std::shared_ptr<fcl::Convexd> fcl;
  std::shared_ptr<CollisionCache::Hull> ours;
  double bound = 0;
};

// The convex hull of n points on an ellipsoid of semi-axes r (a mesh's hull: many vertices, so
// the support is found by walking the vertex graph), or of a few (searched whole).
TestHull makeTestHull(int n, const Eigen::Vector3d& r, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < n; ++k)
    points.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized().cwiseProduct(r));
  const scene::ConvexHull hull = scene::convexHull(points);
  auto vertices = std::make_shared<std::vector<Eigen::Vector3d>>(hull.vertices);
  auto faces = std::make_shared<std::vector<int>>();
  for (const auto& t : hull.triangles) faces->insert(faces->end(), {3, t[0], t[1], t[2]});
  const int count = static_cast<int>(hull.triangles.size());
  TestHull h;
  h.fcl = std::make_shared<fcl::Convexd>(vertices, count, faces);
  h.ours = detail::makeHull(vertices, *faces, count);
  h.bound = r.maxCoeff();
  return h;
}

Eigen::Isometry3d randomPose(std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  M.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
  M.translation() = spread * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return M;
}

// Truth: FCL's own narrow phase (fcl::collide, libccd's MPR through GJKSolver_libccd) on the same
// hulls and poses. Hulls of 200 and 12 points (walked and searched whole), 3000 poses of each pair
// with the centres within reach: the same verdict in every one, and point, normal and depth equal
// to the last bit (one algorithm, one arithmetic: any difference would be a different support
// point).
TEST(ConvexPairs, SameContactsAsFclToTheLastBit) {
  const TestHull big = makeTestHull(200, {0.12, 0.07, 0.05}, 1);
  const TestHull small = makeTestHull(12, {0.04, 0.04, 0.03}, 2);
  ASSERT_GT(big.ours->vertices->size(), 32u);
  ASSERT_LE(small.ours->vertices->size(), 32u);
  std::mt19937 rng(3);
  int hits = 0, pairs = 0;
  for (const TestHull* a : {&big, &small}) {
    for (const TestHull* b : {&big, &small}) {
      for (int k = 0; k < 3000; ++k, ++pairs) {
        const Eigen::Isometry3d Ma = randomPose(rng, 0.7 * (a->bound + b->bound));
        const Eigen::Isometry3d Mb = randomPose(rng, 0.0);
        fcl::CollisionRequestd request(4, true);
        fcl::CollisionResultd result;
        fcl::collide(a->fcl.get(), Ma, b->fcl.get(), Mb, request, result);
        Eigen::Vector3d point, normal;
        double depth = 0;
        const bool ours = detail::hullPairContact(*a->ours, Ma, *b->ours, Mb, point, normal, depth);
        ASSERT_EQ(ours, result.isCollision()) << k;
        if (!ours) continue;
        ++hits;
        ASSERT_EQ(result.numContacts(), 1u);
        const fcl::Contactd& f = result.getContact(0);
        EXPECT_EQ(point, f.pos) << k;
        EXPECT_EQ(normal, f.normal) << k;
        EXPECT_EQ(depth, f.penetration_depth) << k;
      }
    }
  }
  // Both verdicts are exercised (measured: 5595 of the 12 000 poses overlap).
  EXPECT_GT(hits, pairs / 5);
  EXPECT_LT(hits, pairs - pairs / 5);
}

}  // namespace convex_pairs_test
}  // namespace sim
}  // namespace cga_rigid_sim
