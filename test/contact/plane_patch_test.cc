// The reduction of a mesh's contact patch with the ground plane to four points
// (detail::reducePatch, contact_ground_plane.cc; doc/contacts.md#a-patch-on-the-plane): the same
// four whatever rigid motion smaller than the level tolerance moves a flat sole, and a clearly
// deeper vertex always among them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "contact/contact_detection_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace plane_patch_test {

using Patch = std::vector<std::pair<Eigen::Vector3d, int>>;

// A flat sole: the twelve corners of a regular 12-gon of radius r (every choice the reduction
// makes on it is a tie: four of its corners form squares, three of its diagonals are
// diameters), level at depth `depth` below the plane z = 0, centred on the origin.
std::vector<Eigen::Vector3d> sole(double r, double depth) {
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 12; ++k) {
    const double a = 2.0 * M_PI * k / 12;
    corners.push_back({r * std::cos(a), r * std::sin(a), -depth});
  }
  return corners;
}

// The sole moved by X, as detection hands it over: world points with their vertex, in vertex
// order.
Patch placed(const std::vector<Eigen::Vector3d>& corners, const Eigen::Isometry3d& X) {
  Patch p;
  for (std::size_t k = 0; k < corners.size(); ++k)
    p.push_back({X * corners[k], static_cast<int>(k)});
  return p;
}

std::vector<int> picked(Patch p) {
  detail::reducePatch(p);
  std::vector<int> v;
  for (const auto& q : p) v.push_back(q.second);
  return v;
}

// A resting sole rocks by round-off-sized rotations from step to step and turns about the
// vertical: which of its level corners is lowest changes each time, and the four must not.
TEST(PlanePatch, TheSameFourWhileALevelSoleRocks) {
  const double r = 0.1;
  const std::vector<Eigen::Vector3d> corners = sole(r, 5e-5);
  const std::vector<int> at_rest = picked(placed(corners, Eigen::Isometry3d::Identity()));
  ASSERT_EQ(at_rest.size(), 4u);
  // They span the patch: the largest quadrilateral in a regular 12-gon is one of its squares,
  // of area 2 r², two thirds of the 12-gon's 3 r². Exact but for the coordinates' round-off.
  Patch four = placed(corners, Eigen::Isometry3d::Identity());
  detail::reducePatch(four);
  const auto cross = [&](int a, int b, int c) {
    const Eigen::Vector2d u = (four[b].first - four[a].first).head<2>();
    const Eigen::Vector2d w = (four[c].first - four[a].first).head<2>();
    return u.x() * w.y() - u.y() * w.x();
  };
  // The four are in vertex order, which is the polygon's order: a convex quadrilateral.
  EXPECT_NEAR(0.5 * (cross(0, 1, 2) + cross(0, 2, 3)), 2 * r * r, 1e-15);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int lowest_changed = 0;
  int last_lowest = -1;
  for (int trial = 0; trial < 500; ++trial) {
    // A tilt below 1e-6 rad about a horizontal axis (depths differ by < 2e-7 m, well inside
    // the 5e-6 m level tolerance), any turn about the vertical, a shift across the plane and
    // up or down by less than the depth.
    const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), 0).normalized();
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = (Eigen::AngleAxisd(M_PI * u(rng), Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(1e-6 * u(rng), axis))
                     .toRotationMatrix();
    X.translation() = Eigen::Vector3d(u(rng), u(rng), 1e-5 * u(rng));
    const Patch p = placed(corners, X);
    EXPECT_EQ(picked(p), at_rest) << "trial " << trial;
    int lowest = 0;
    for (int k = 1; k < 12; ++k)
      if (p[k].first.z() < p[lowest].first.z()) lowest = k;
    lowest_changed += lowest != last_lowest;
    last_lowest = lowest;
  }
  // The case is the one described: the lowest corner moved about (a test of nothing otherwise).
  EXPECT_GT(lowest_changed, 100);
}

// A corner lower than the rest by more than the level tolerance is among the four (the overlap
// it carries is corrected); one lower by less leaves the level sole's four.
TEST(PlanePatch, AClearlyDeeperCornerIsAmongTheFour) {
  const std::vector<Eigen::Vector3d> level = sole(0.1, 5e-5);
  const std::vector<int> at_rest = picked(placed(level, Eigen::Isometry3d::Identity()));
  for (int k = 0; k < 12; ++k) {
    std::vector<Eigen::Vector3d> deeper = level;
    deeper[k].z() -= 1e-5;  // twice the 5e-6 m tolerance
    const std::vector<int> four = picked(placed(deeper, Eigen::Isometry3d::Identity()));
    EXPECT_NE(std::find(four.begin(), four.end(), k), four.end()) << "corner " << k;
    std::vector<Eigen::Vector3d> barely = level;
    barely[k].z() -= 1e-6;  // a fifth of it
    EXPECT_EQ(picked(placed(barely, Eigen::Isometry3d::Identity())), at_rest) << "corner " << k;
  }
  // A sole tilted by 1e-3 rad (depths spread over 2e-4 m): its lowest corner is among the four.
  for (int trial = 0; trial < 24; ++trial) {
    const double a = 2.0 * M_PI * (trial + 0.5) / 24;
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() =
        Eigen::AngleAxisd(1e-3, Eigen::Vector3d(std::cos(a), std::sin(a), 0)).toRotationMatrix();
    const Patch p = placed(level, X);
    int lowest = 0;
    for (int k = 1; k < 12; ++k)
      if (p[k].first.z() < p[lowest].first.z()) lowest = k;
    const std::vector<int> four = picked(p);
    EXPECT_NE(std::find(four.begin(), four.end(), lowest), four.end()) << "trial " << trial;
  }
}

}  // namespace plane_patch_test
}  // namespace sim
}  // namespace cga_rigid_sim
