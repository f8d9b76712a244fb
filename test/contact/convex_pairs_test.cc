// The narrow phase of a hull and a hull, box, sphere or cylinder
// (src/contact/contact_convex_pairs.cc) against FCL's for the same shapes, which it replaces: the
// same algorithm (libccd's MPR) on the same support and interior points, so the same answer to the
// last bit.
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cga_rigid_sim/scene/convex_hull.h"
#include "contact/contact_detection_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace convex_pairs_test {

using Convex = CollisionCache::Shape::Convex;

struct TestShape {
  std::shared_ptr<fcl::CollisionGeometryd> fcl;
  CollisionCache::Shape ours;
  double bound = 0;
  std::vector<int> faces;  // a hull's, in FCL's encoding (all triangles)
};

// The convex hull of n points on an ellipsoid of semi-axes r (a mesh's hull: many vertices, so
// the support is found by walking the vertex graph), or of a few (searched whole).
TestShape hullOf(const std::vector<Eigen::Vector3d>& points, double bound);

TestShape makeTestHull(int n, const Eigen::Vector3d& r, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < n; ++k)
    points.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized().cwiseProduct(r));
  return hullOf(points, r.maxCoeff());
}

// A prism on a regular n-gon of radius r, half height z: flat ends of n vertices and flat
// sides, so that a direction along the axis or across a side ties several vertices.
TestShape makeTestPrism(int n, double r, double z) {
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * k / n;
    points.push_back({r * std::cos(a), r * std::sin(a), z});
    points.push_back({r * std::cos(a), r * std::sin(a), -z});
  }
  return hullOf(points, std::hypot(r, z));
}

TestShape hullOf(const std::vector<Eigen::Vector3d>& points, double bound) {
  const scene::ConvexHull hull = scene::convexHull(points);
  auto vertices = std::make_shared<std::vector<Eigen::Vector3d>>(hull.vertices);
  auto faces = std::make_shared<std::vector<int>>();
  for (const auto& t : hull.triangles) faces->insert(faces->end(), {3, t[0], t[1], t[2]});
  const int count = static_cast<int>(hull.triangles.size());
  TestShape h;
  h.fcl = std::make_shared<fcl::Convexd>(vertices, count, faces);
  h.ours.hull = detail::makeHull(vertices, *faces, count, true);
  h.bound = bound;
  h.faces = *faces;
  return h;
}

TestShape makeTestBox(const Eigen::Vector3d& side) {
  TestShape b;
  b.fcl = std::make_shared<fcl::Boxd>(side);
  b.ours.convex = Convex::kBox;
  for (int k = 0; k < 3; ++k) b.ours.extent[k] = side[k] / 2.0;
  b.bound = 0.5 * side.norm();
  return b;
}

TestShape makeTestSphere(double radius) {
  TestShape s;
  s.fcl = std::make_shared<fcl::Sphered>(radius);
  s.ours.convex = Convex::kSphere;
  s.ours.extent[0] = radius;
  s.bound = radius;
  return s;
}

TestShape makeTestCylinder(double radius, double length) {
  TestShape c;
  c.fcl = std::make_shared<fcl::Cylinderd>(radius, length);
  c.ours.convex = Convex::kCylinder;
  c.ours.extent[0] = radius;
  c.ours.extent[1] = length / 2;
  c.bound = std::hypot(radius, 0.5 * length);
  return c;
}

Eigen::Isometry3d randomPose(std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  M.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
  M.translation() = spread * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return M;
}

// A hull of 200 points on an ellipsoid of semi-axes `big` (walked), one of 12 (searched whole),
// a box, a sphere and a cylinder.
struct TestShapes {
  TestShape big, small, box, sphere, cylinder;
  std::vector<TestShape*> all() { return {&big, &small, &box, &sphere, &cylinder}; }
};

TestShapes makeTestShapes(const Eigen::Vector3d& big, unsigned seed) {
  return {makeTestHull(200, big, seed), makeTestHull(12, {0.04, 0.04, 0.03}, 2),
          makeTestBox({0.1, 0.06, 0.2}), makeTestSphere(0.05), makeTestCylinder(0.03, 0.15)};
}

// FCL's contact and ours for one pose; true if they overlap. The same verdict, and point,
// normal and depth equal to the last bit.
bool compareWithFcl(TestShape& a, const Eigen::Isometry3d& Ma, TestShape& b,
                    const Eigen::Isometry3d& Mb, int pose) {
  fcl::CollisionRequestd request(4, true);
  fcl::CollisionResultd result;
  fcl::collide(a.fcl.get(), Ma, b.fcl.get(), Mb, request, result);
  Eigen::Vector3d point, normal;
  double depth = 0;
  const bool ours = detail::convexPairContact(a.ours, Ma, b.ours, Mb, point, normal, depth);
  EXPECT_EQ(ours, result.isCollision()) << pose;
  if (!ours || !result.isCollision()) return false;
  EXPECT_EQ(result.numContacts(), 1u);
  const fcl::Contactd& f = result.getContact(0);
  EXPECT_EQ(point, f.pos) << pose;
  EXPECT_EQ(normal, f.normal) << pose;
  EXPECT_EQ(depth, f.penetration_depth) << pose;
  return true;
}

// Truth: FCL's own narrow phase (fcl::collide, libccd's MPR through GJKSolver_libccd) on the same
// shapes and poses. Hulls of 200 and 12 points (walked and searched whole) against each other and
// against a box, a sphere and a cylinder, 3000 poses of each pair with the centres within reach
// (a hull's pairs both ways round): the same verdict in every one, and point, normal and depth
// equal to the last bit (one algorithm, one arithmetic: any difference would be a different
// support point).
TEST(ConvexPairs, SameContactsAsFclToTheLastBit) {
  TestShapes shapes = makeTestShapes({0.12, 0.07, 0.05}, 1);
  ASSERT_GT(shapes.big.ours.hull->vertices->size(), 32u);
  ASSERT_LE(shapes.small.ours.hull->vertices->size(), 32u);
  std::mt19937 rng(3);
  int hits = 0, pairs = 0;
  for (TestShape* a : shapes.all()) {
    for (TestShape* b : shapes.all()) {
      if (!a->ours.hull && !b->ours.hull) continue;  // two primitives stay with FCL
      for (int k = 0; k < 3000; ++k, ++pairs) {
        const Eigen::Isometry3d Ma = randomPose(rng, 0.7 * (a->bound + b->bound));
        const Eigen::Isometry3d Mb = randomPose(rng, 0.0);
        if (compareWithFcl(*a, Ma, *b, Mb, pairs)) ++hits;
        if (HasFatalFailure()) return;
      }
    }
  }
  // Both verdicts are exercised (measured: 24 482 of the 48 000 poses overlap).
  EXPECT_GT(hits, pairs / 5);
  EXPECT_LT(hits, pairs - pairs / 5);
}

// Ties: prisms with flat ends (24 and 20 vertices each) and flat sides, square to each other and
// to a box and a cylinder and moved along the axes, so that MPR's directions are square to whole
// faces and several vertices are equally far. Which of them a walk ends at depends on where it
// starts and in which order it looks; ours must end where FCL's walk from vertex 0 does (a walk
// started from the last query's vertex, tried, differed in 2330 values over both tests), so the
// same contacts to the last bit, as above. Random poses in between vary the hulls' history.
TEST(ConvexPairs, TiedVerticesAsFclPicksThem) {
  TestShape a = makeTestPrism(24, 0.05, 0.04);
  TestShape b = makeTestPrism(20, 0.04, 0.06);
  TestShape box = makeTestBox({0.1, 0.06, 0.2});
  TestShape cylinder = makeTestCylinder(0.03, 0.15);
  ASSERT_GT(a.ours.hull->vertices->size(), 32u);
  ASSERT_GT(b.ours.hull->vertices->size(), 32u);
  const Eigen::Matrix3d square[] = {
      Eigen::Matrix3d::Identity(),
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix(),
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix(),
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix()};
  const Eigen::Vector3d shifts[] = {{0.06, 0, 0},    {0, 0.07, 0},    {0, 0, 0.08},
                                    {0.05, 0.05, 0}, {0, 0, -0.09},   {0.03, 0, 0.07},
                                    {-0.08, 0, 0},   {0, -0.05, 0.05}};
  std::mt19937 rng(5);
  int hits = 0, poses = 0;
  for (TestShape* first : {&a, &b}) {
    for (TestShape* second : {&a, &b, &box, &cylinder}) {
      for (const Eigen::Matrix3d& R : square) {
        for (const Eigen::Vector3d& t : shifts) {
          for (double scale : {0.5, 0.8, 1.0, 1.3}) {
            compareWithFcl(*first, randomPose(rng, 0.1), *second, randomPose(rng, 0.0), poses);
            Eigen::Isometry3d Ma = Eigen::Isometry3d::Identity(), Mb = Ma;
            Ma.linear() = R;
            Ma.translation() = scale * t;
            if (compareWithFcl(*first, Ma, *second, Mb, ++poses)) ++hits;
            if (compareWithFcl(*second, Mb, *first, Ma, ++poses)) ++hits;
            if (HasFatalFailure()) return;
          }
        }
      }
    }
  }
  EXPECT_GT(hits, poses / 5);  // both verdicts exercised
}

// Truth: FCL's own choice of a hull's support vertex (fcl::Convex::findExtremeVertex, its walk
// from vertex 0 or its search of a small hull) on the same vertices, which FCL and ours share:
// the same vertex, by address. Hulls of 200 and 12 points on an ellipsoid and the two prisms;
// directions at random, and the ones that tie or nearly tie vertices: along the axes, every
// face's normal (its three corners tie, a prism's end face ties all its vertices) and its sum
// with the next face's in Qhull's list (where the two share an edge, its ends tie), each also
// turned by 1e-15, 1e-12 and 1e-9 rad (rounding decides, then barely, then not). Both ways of
// finding it are exercised: the climb from the start table (most directions; measured: 81 113
// of 84 768) and FCL's walk or search where the climb's end has a neighbour within the tie
// margin (ties; measured: 3 655). A climb that took ends merely as far as their neighbours
// fails 768 of these queries (tried).
TEST(ConvexPairs, SupportVertexAsFclPicksIt) {
  std::vector<TestShape> hulls;
  hulls.push_back(makeTestHull(200, {0.12, 0.07, 0.05}, 1));
  hulls.push_back(makeTestHull(12, {0.04, 0.04, 0.03}, 2));
  hulls.push_back(makeTestPrism(24, 0.05, 0.04));
  hulls.push_back(makeTestPrism(20, 0.04, 0.06));
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  const auto turned = [&](const Eigen::Vector3d& d, double angle) {
    const Eigen::Vector3d axis = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    return Eigen::AngleAxisd(angle, axis) * d;
  };
  long climbed_count = 0, walked_count = 0, queries = 0;
  for (TestShape& h : hulls) {
    const auto& fcl_convex = static_cast<const fcl::Convexd&>(*h.fcl);
    const std::vector<Eigen::Vector3d>& v = *h.ours.hull->vertices;
    std::vector<Eigen::Vector3d> directions;
    for (int k = 0; k < 20000; ++k) directions.push_back({g(rng), g(rng), g(rng)});
    for (int k = 0; k < 3; ++k) {
      directions.push_back(Eigen::Vector3d::Unit(k));
      directions.push_back(-Eigen::Vector3d::Unit(k));
    }
    std::vector<Eigen::Vector3d> normals;
    for (std::size_t at = 0; at < h.faces.size(); at += 4) {
      const Eigen::Vector3d& a = v[h.faces[at + 1]];
      Eigen::Vector3d n = (v[h.faces[at + 2]] - a).cross(v[h.faces[at + 3]] - a).normalized();
      if (n.dot(a - h.ours.hull->interior) < 0) n = -n;
      normals.push_back(n);
    }
    for (std::size_t f = 0; f < normals.size(); ++f) {
      directions.push_back(normals[f]);
      directions.push_back(normals[f] + normals[(f + 1) % normals.size()]);
    }
    const std::size_t exact = directions.size() - 20000;
    for (std::size_t k = 20000; k < 20000 + exact; ++k)
      for (double angle : {1e-15, 1e-12, 1e-9}) directions.push_back(turned(directions[k], angle));
    for (const Eigen::Vector3d& d : directions) {
      bool climbed = false;
      const Eigen::Vector3d& ours = detail::hullExtremeVertex(*h.ours.hull, d, climbed);
      EXPECT_EQ(&ours, &fcl_convex.findExtremeVertex(d)) << queries << " " << d.transpose();
      (climbed ? climbed_count : walked_count)++;
      ++queries;
    }
  }
  EXPECT_GT(climbed_count, queries / 2);
  EXPECT_GT(walked_count, 100);
}

// The boxes that let a pair skip MPR (contact_box_separation.cc). Truth: MPR itself on the same
// shapes and poses. Long and round hulls (a shin's 0.25 × 0.05 × 0.05 m, 200 and 12 points), a
// box, a sphere and a cylinder, 3000 poses of each pair whose bounding spheres overlap: the
// boxes are never apart where MPR finds a contact (a box that did not hold its shape would drop
// contacts), and they tell a fair part of MPR's "no contact" poses (a test that always said
// "not apart" would save nothing: measured 17 775 of 24 427, 73 %; asserted > 50 %).
TEST(ConvexPairs, BoxesApartOnlyWhereMprFindsNothing) {
  TestShapes shapes = makeTestShapes({0.25, 0.05, 0.05}, 7);  // the big hull a shin
  std::mt19937 rng(11);
  int apart = 0, missed = 0, empty = 0;
  for (TestShape* a : shapes.all()) {
    for (TestShape* b : shapes.all()) {
      if (!a->ours.hull && !b->ours.hull) continue;
      CollisionCache cache;
      cache.shapes = {a->ours, b->ours};
      for (CollisionCache::Shape& s : cache.shapes) s.box_half_S = detail::boxHalfSides(s);
      cache.pose_W.resize(2);
      cache.centre_W.resize(2);
      for (int k = 0; k < 3000; ++k) {
        cache.pose_W[0] = randomPose(rng, 0.9 * (a->bound + b->bound));
        cache.pose_W[1] = randomPose(rng, 0.0);
        for (int s = 0; s < 2; ++s) cache.centre_W[s] = cache.pose_W[s] * cache.shapes[s].centre_S;
        if ((cache.centre_W[1] - cache.centre_W[0]).norm() > a->bound + b->bound) continue;
        Eigen::Vector3d point, normal;
        double depth = 0;
        const bool touching =
            detail::convexPairContact(cache.shapes[0], cache.pose_W[0], cache.shapes[1],
                                      cache.pose_W[1], point, normal, depth);
        const bool boxes_apart = detail::boxesApart(cache, 0, 1);
        if (touching && boxes_apart) ++missed;
        if (!touching) ++empty;
        if (!touching && boxes_apart) ++apart;
      }
    }
  }
  EXPECT_EQ(missed, 0);
  EXPECT_GT(apart, empty / 2) << apart << " of " << empty;
}

// Two boxes face to face: a gap of 1e-7 m, below MPR's tolerance, is left to MPR (the boxes'
// spare); a gap of 1 mm is told apart.
TEST(ConvexPairs, BoxesApartLeaveTheNarrowPhaseItsTolerance) {
  TestShape box = makeTestBox({0.1, 0.06, 0.2});
  CollisionCache cache;
  cache.shapes = {box.ours, box.ours};
  for (CollisionCache::Shape& s : cache.shapes) s.box_half_S = detail::boxHalfSides(s);
  cache.pose_W.assign(2, Eigen::Isometry3d::Identity());
  cache.centre_W.resize(2);
  for (const double gap : {1e-7, 1e-3}) {
    cache.pose_W[1].translation() = Eigen::Vector3d(0.1 + gap, 0, 0);
    for (int s = 0; s < 2; ++s) cache.centre_W[s] = cache.pose_W[s].translation();
    EXPECT_EQ(detail::boxesApart(cache, 0, 1), gap > 1e-5) << gap;
  }
}

}  // namespace convex_pairs_test
}  // namespace sim
}  // namespace cga_rigid_sim
