// The node's ~markers (include/cga_rigid_sim/ros/markers.h): reports in, MarkerArray out.
// Truth: the reports themselves and the scaling rule written out by hand (length = ℓ·x/x_ref,
// capped at kMaxRelativeLength·ℓ); the contact point against the ~contacts message of the same
// report (toContactMsg), and, end to end, a real World (a ball dropped on the ground plane).
#include "cga_rigid_sim/ros/markers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cga_rigid_sim/ros/conversions.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace node {
namespace markers_test {

using visualization_msgs::Marker;

Eigen::Vector3d toEigen3(const geometry_msgs::Point& p) { return {p.x, p.y, p.z}; }

// The marker with namespace `ns` and id `id`, or null.
const Marker* find(const visualization_msgs::MarkerArray& a, const std::string& ns, int id) {
  for (const auto& m : a.markers)
    if (m.action == Marker::ADD && m.ns == ns && m.id == id) return &m;
  return nullptr;
}

// Two moving bodies with L, ω, a tree entry and a "total" whose L are larger than either (they
// must be ignored when L_ref is chosen: they are not bodies).
MarkerInputs twoBodies() {
  MarkerInputs in;
  sim::BodyStateReport a;
  a.name = "racket";
  a.com = {0.2, -0.1, 1.5};
  a.angular_velocity = {0.5, 10.0, -0.25};
  sim::BodyStateReport b;
  b.name = "rod";
  b.com = {-1.0, 2.0, 0.5};
  b.angular_velocity = {0.0, 0.0, 4.0};
  in.bodies = {a, b};
  sim::MomentumReport ma;
  ma.body = "racket";
  ma.angular = {0.3, -0.4, 1.2};  // |L| = 1.3
  sim::MomentumReport mb;
  mb.body = "rod";
  mb.angular = {0.0, 0.6, 0.0};
  sim::MomentumReport total;
  total.kind = sim::MomentumReport::Kind::kTotal;
  total.body = sim::kTotalName;
  total.angular = {0.0, 0.0, 50.0};
  // A tree's entry sums its bodies: like the total it draws no arrow and sets no reference.
  sim::MomentumReport tree;
  tree.kind = sim::MomentumReport::Kind::kTree;
  tree.body = std::string(sim::kTreePrefix) + "racket";
  tree.angular = {0.0, 0.0, 40.0};
  in.momentum = {ma, mb, tree, total};
  in.dt = 0.001;
  return in;
}

const ::ros::Time kStamp(1.25);

// Directions and lengths are computed from the same doubles as the markers, through one
// normalisation and one scaling: 4 ulp-scale agreement, 1e-14 relative to the coordinates.
constexpr double kTol = 1e-14;

TEST(Markers, ArrowLengthFollowsTheRuleAndIsCapped) {
  EXPECT_DOUBLE_EQ(arrowLength(1.3, 2.6, 0.25), 0.125);
  EXPECT_DOUBLE_EQ(arrowLength(2.6, 2.6, 0.25), 0.25);
  EXPECT_DOUBLE_EQ(arrowLength(100.0, 2.6, 0.25), kMaxRelativeLength * 0.25);
  EXPECT_EQ(arrowLength(1.0, 0.0, 0.25), 0.0);  // no reference yet: nothing drawn
}

TEST(Markers, ReferencesAreTheLargestBodySoFarNotTheTotal) {
  MarkerInputs in = twoBodies();
  const MarkerScale scale;  // L_ref, ω_ref unset: chosen
  MarkerReferences refs = updateMarkerReferences(in, scale, MarkerReferences{});
  // The racket's |L| = sqrt(0.09 + 0.16 + 1.44) = 1.3 up to rounding; the total's 50 is ignored.
  EXPECT_DOUBLE_EQ(refs.angular_momentum, 1.3);
  EXPECT_DOUBLE_EQ(refs.angular_velocity, std::sqrt(0.25 + 100.0 + 0.0625));
  EXPECT_EQ(refs.force, 10.0);
  // Larger later: the reference grows; smaller later: it stays.
  in.momentum[1].angular = {0.0, 9.0, 0.0};
  refs = updateMarkerReferences(in, scale, refs);
  EXPECT_EQ(refs.angular_momentum, 9.0);
  in.momentum[1].angular = {0.0, 0.5, 0.0};
  refs = updateMarkerReferences(in, scale, refs);
  EXPECT_EQ(refs.angular_momentum, 9.0);

  // Given references are kept whatever the motion.
  MarkerScale given;
  given.angular_momentum_ref = 7.0;
  given.angular_velocity_ref = 3.0;
  given.force_ref = 2.0;
  refs = updateMarkerReferences(twoBodies(), given, MarkerReferences{});
  EXPECT_EQ(refs.angular_momentum, 7.0);
  EXPECT_EQ(refs.angular_velocity, 3.0);
  EXPECT_EQ(refs.force, 2.0);

  // Bodies at rest (round-off spin): the floors, so nothing visible is drawn.
  MarkerInputs rest = twoBodies();
  for (auto& b : rest.bodies) b.angular_velocity = {1e-17, 0.0, 0.0};
  for (auto& m : rest.momentum) m.angular = {0.0, 1e-18, 0.0};
  refs = updateMarkerReferences(rest, scale, MarkerReferences{});
  EXPECT_EQ(refs.angular_momentum, kMinAngularMomentumRef);
  EXPECT_EQ(refs.angular_velocity, kMinAngularVelocityRef);
  EXPECT_EQ(toMarkerArray(rest, 0.25, refs, kStamp, "world").markers.size(), 1u);  // DELETEALL
}

TEST(Markers, BodyArrowsAtTheCentreOfMassAlongLAndOmega) {
  const MarkerInputs in = twoBodies();
  MarkerReferences refs;
  refs.angular_momentum = 2.6;
  refs.angular_velocity = 2.0;
  const auto array = toMarkerArray(in, 0.25, refs, kStamp, "world");

  ASSERT_FALSE(array.markers.empty());
  EXPECT_EQ(array.markers[0].action, Marker::DELETEALL);
  for (const auto& m : array.markers) {
    EXPECT_EQ(m.header.frame_id, "world");
    EXPECT_EQ(m.header.stamp, kStamp);
  }

  // racket: L = (0.3, -0.4, 1.2), |L| = 1.3 → 0.25 · 1.3 / 2.6 = 0.125 m along L/|L|.
  const Marker* L = find(array, "body/racket", 0);
  ASSERT_NE(L, nullptr);
  EXPECT_EQ(L->type, Marker::ARROW);
  ASSERT_EQ(L->points.size(), 2u);
  const Eigen::Vector3d L_W(0.3, -0.4, 1.2);
  EXPECT_EQ(toEigen3(L->points[0]), in.bodies[0].com);
  const Eigen::Vector3d L_arrow = toEigen3(L->points[1]) - toEigen3(L->points[0]);
  EXPECT_NEAR(L_arrow.norm(), 0.125, kTol);
  EXPECT_LT((L_arrow.normalized() - L_W / 1.3).norm(), kTol);

  // racket: ω = (0.5, 10, -0.25), |ω| ≈ 10.015 > 4 ω_ref → capped at 4ℓ = 1 m.
  const Marker* w = find(array, "body/racket", 1);
  ASSERT_NE(w, nullptr);
  const Eigen::Vector3d w_W = in.bodies[0].angular_velocity;
  const Eigen::Vector3d w_arrow = toEigen3(w->points[1]) - toEigen3(w->points[0]);
  EXPECT_EQ(toEigen3(w->points[0]), in.bodies[0].com);
  EXPECT_NEAR(w_arrow.norm(), kMaxRelativeLength * 0.25, kTol);
  EXPECT_LT((w_arrow.normalized() - w_W.normalized()).norm(), kTol);

  // rod: L = (0, 0.6, 0) → 0.25 · 0.6 / 2.6 m along +y; ω = (0, 0, 4) → 0.25 · 4 / 2 = 0.5 m.
  const Marker* L_rod = find(array, "body/rod", 0);
  ASSERT_NE(L_rod, nullptr);
  const Eigen::Vector3d expected_end = in.bodies[1].com + Eigen::Vector3d(0, 0.25 * 0.6 / 2.6, 0);
  EXPECT_LT((toEigen3(L_rod->points[1]) - expected_end).norm(), kTol);
  const Marker* w_rod = find(array, "body/rod", 1);
  ASSERT_NE(w_rod, nullptr);
  EXPECT_LT((toEigen3(w_rod->points[1]) - (in.bodies[1].com + Eigen::Vector3d(0, 0, 0.5))).norm(),
            kTol);

  // Exactly: DELETEALL + 2 arrows per body, no contacts, nothing for the tree or "total".
  EXPECT_EQ(array.markers.size(), 5u);
}

TEST(Markers, IdsStableAcrossTicksAndDeletedBodiesVanish) {
  MarkerInputs in = twoBodies();
  const MarkerReferences refs = updateMarkerReferences(in, MarkerScale{}, MarkerReferences{});
  const auto first = toMarkerArray(in, 0.25, refs, kStamp, "world");
  // Next tick: other values, the rod deleted.
  in.bodies[0].angular_velocity = {1.0, 2.0, 3.0};
  in.bodies.pop_back();
  in.momentum.erase(in.momentum.begin() + 1);
  const auto second = toMarkerArray(in, 0.25, refs, ::ros::Time(1.26), "world");
  ASSERT_NE(find(first, "body/racket", 1), nullptr);
  ASSERT_NE(find(second, "body/racket", 1), nullptr);
  EXPECT_NE(find(first, "body/rod", 0), nullptr);
  // The rod is not sent again, and the DELETEALL in front removes what rviz still shows of it.
  EXPECT_EQ(find(second, "body/rod", 0), nullptr);
  EXPECT_EQ(find(second, "body/rod", 1), nullptr);
  EXPECT_EQ(second.markers.front().action, Marker::DELETEALL);
}

TEST(Markers, ContactPointNormalAndImpulseAsMeanForce) {
  MarkerInputs in = twoBodies();
  sim::ContactReport c;
  c.body_a = "racket";
  c.link_a = "racket_head";
  c.body_b = c.link_b = "ground_plane";
  c.point = {0.123456789, -0.5, 0.0};
  c.normal = Eigen::Vector3d(0.0, 0.6, 0.8);
  c.normal_impulse = 0.02;                 // N s → 20 N over dt = 1 ms
  c.friction_impulse = {0.015, 0.0, 0.0};  // N s → 15 N
  in.contacts = {c, c};
  in.contacts[1].point = {1.0, 1.0, 0.0};
  MarkerReferences refs;
  refs.angular_momentum = refs.angular_velocity = 1.0;
  refs.force = 100.0;
  const auto array = toMarkerArray(in, 0.25, refs, kStamp, "world");

  const Marker* points = find(array, "contacts", 0);
  ASSERT_NE(points, nullptr);
  EXPECT_EQ(points->type, Marker::SPHERE_LIST);
  ASSERT_EQ(points->points.size(), 2u);
  // The marker's point is the ~contacts message's point, bit for bit.
  const auto msg = toContactMsg(in.contacts[0]);
  EXPECT_EQ(points->points[0].x, msg.position.x);
  EXPECT_EQ(points->points[0].y, msg.position.y);
  EXPECT_EQ(points->points[0].z, msg.position.z);

  const Marker* normals = find(array, "contacts", 1);
  ASSERT_NE(normals, nullptr);
  EXPECT_EQ(normals->type, Marker::LINE_LIST);
  ASSERT_EQ(normals->points.size(), 4u);
  EXPECT_EQ(toEigen3(normals->points[0]), c.point);
  EXPECT_LT((toEigen3(normals->points[1]) - (c.point + 0.125 * c.normal)).norm(), kTol);

  // Impulse on a: 0.02 n + (0.015, 0, 0) = (0.015, 0.012, 0.016) N s, |J| = 0.025 N s →
  // mean force 25 N → 0.25 · 25 / 100 = 0.0625 m.
  const Marker* impulse = find(array, "contact_impulses", 0);
  ASSERT_NE(impulse, nullptr);
  ASSERT_EQ(impulse->points.size(), 2u);
  EXPECT_EQ(toEigen3(impulse->points[0]), c.point);
  const Eigen::Vector3d arrow = toEigen3(impulse->points[1]) - c.point;
  EXPECT_NEAR(arrow.norm(), 0.0625, kTol);
  EXPECT_LT((arrow.normalized() - Eigen::Vector3d(0.6, 0.48, 0.64)).norm(), kTol);
  EXPECT_NE(find(array, "contact_impulses", 1), nullptr);
}

// End to end through a World: a 1 kg ball (radius 0.1 m) dropped from 0.5 m onto the ground
// plane with e = 0, stepped 1.5 s so it rests. markersOf draws the World's own contact, at the
// World's contact point, with the arrow of its resting impulse m g dt: 9.81 N against
// F_ref = 10 N → 0.25 · 0.981 m (the contact rostest measures m g dt to 1 %; 2 % here).
TEST(Markers, RestingBallThroughWorld) {
  scene::SceneOptions options;
  auto scene =
      scene::loadUrdfFile(std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/test/ros/ball.urdf", options);
  ASSERT_TRUE(scene) << scene.error();
  sim::WorldConfig config;
  config.ground_plane = sim::GroundPlane{};
  auto world = sim::World::create(std::move(*scene), config);
  ASSERT_TRUE(world) << world.error();
  (*world)->step(1500);
  const auto contacts = (*world)->contacts();
  ASSERT_EQ(contacts.size(), 1u);

  MarkerReferences refs;  // MarkerScale's defaults: ℓ = 0.25 m, F_ref = 10 N
  const auto array = markersOf(**world, MarkerScale{}, &refs, kStamp);
  const Marker* points = find(array, "contacts", 0);
  ASSERT_NE(points, nullptr);
  ASSERT_EQ(points->points.size(), 1u);
  EXPECT_EQ(toEigen3(points->points[0]), contacts[0].point);
  const Marker* impulse = find(array, "contact_impulses", 0);
  ASSERT_NE(impulse, nullptr);
  const Eigen::Vector3d arrow = toEigen3(impulse->points[1]) - toEigen3(impulse->points[0]);
  EXPECT_NEAR(arrow.norm(), 0.25 * 0.981, 0.02 * 0.25 * 0.981);
  EXPECT_GT(arrow.normalized().z(), 0.999);  // straight up: the plane pushes the ball
  // The ball is at rest (spin from round-off only): no angular arrows.
  EXPECT_EQ(find(array, "body/ball", 0), nullptr);
  EXPECT_EQ(find(array, "body/ball", 1), nullptr);
}

}  // namespace markers_test
}  // namespace node
}  // namespace cga_rigid_sim
