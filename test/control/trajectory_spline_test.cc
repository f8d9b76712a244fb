// Spline segments against hand-derived polynomials: linear, cubic and quintic interpolants are
// unique, so a segment built from the ends of a known polynomial of that degree must return that
// polynomial everywhere. Tolerance 1e-12: Horner over ≤ 6 terms of magnitude ≤ 50 on [0, 2]
// rounds to a few ulps of 50 (≈ 1e-14); the coefficients come from divisions by T⁵ ≈ 8, so a
// margin of 100 over that.
#include "cga_rigid_sim/control/trajectory_spline.h"

#include <gtest/gtest.h>

namespace cga_rigid_sim {
namespace control {
namespace trajectory_spline_test {

constexpr double kTol = 1e-12;

SplineKnot knot(double t, double q, const double* v = nullptr, const double* a = nullptr) {
  SplineKnot k;
  k.time = t;
  k.position = q;
  if (v) k.velocity = *v, k.has_velocity = true;
  if (a) k.acceleration = *a, k.has_acceleration = true;
  return k;
}

TEST(SplineSegment, LinearWhenAnEndGivesOnlyPositions) {
  // q(t) = 2 + 2 (t − 1) from (1, 2) to (3, 6); the start's velocity is ignored because the end
  // gives none (joint_trajectory_controller picks by both ends).
  const double v0 = 7;
  const SplineSegment s = SplineSegment::between(knot(1, 2, &v0), knot(3, 6));
  EXPECT_EQ(s.kind, SegmentKind::kLinear);
  for (double t : {1.0, 1.5, 2.0, 3.0}) {
    const JointSample x = s.at(t);
    EXPECT_NEAR(x.position, 2 + 2 * (t - 1), kTol);
    EXPECT_NEAR(x.velocity, 2, kTol);
    EXPECT_NEAR(x.acceleration, 0, kTol);
  }
}

TEST(SplineSegment, CubicRecoversTheHermitePolynomial) {
  // q(s) = 1 + 2s − s² + 0.5 s³, q̇ = 2 − 2s + 1.5 s², q̈ = −2 + 3s, s = t − 0.5, T = 2:
  // ends q(0) = 1, q̇(0) = 2; q(2) = 5, q̇(2) = 4.
  auto q = [](double s) { return 1 + 2 * s - s * s + 0.5 * s * s * s; };
  auto qd = [](double s) { return 2 - 2 * s + 1.5 * s * s; };
  const double v0 = 2, v1 = 4;
  const SplineSegment seg = SplineSegment::between(knot(0.5, 1, &v0), knot(2.5, 5, &v1));
  EXPECT_EQ(seg.kind, SegmentKind::kCubic);
  for (double s : {0.0, 0.3, 0.7, 1.4, 2.0}) {
    const JointSample x = seg.at(0.5 + s);
    EXPECT_NEAR(x.position, q(s), kTol) << s;
    EXPECT_NEAR(x.velocity, qd(s), kTol) << s;
    EXPECT_NEAR(x.acceleration, -2 + 3 * s, kTol) << s;
  }
}

TEST(SplineSegment, QuinticRecoversTheQuinticPolynomial) {
  // q(s) = 0.5 − s + 0.25 s² + 0.3 s³ − 0.1 s⁴ + 0.02 s⁵ on T = 1.5, ends from its derivatives.
  const double c[6] = {0.5, -1, 0.25, 0.3, -0.1, 0.02};
  auto q = [&](double s) {
    return c[0] + s * (c[1] + s * (c[2] + s * (c[3] + s * (c[4] + s * c[5]))));
  };
  auto qd = [&](double s) {
    return c[1] + s * (2 * c[2] + s * (3 * c[3] + s * (4 * c[4] + s * 5 * c[5])));
  };
  auto qdd = [&](double s) { return 2 * c[2] + s * (6 * c[3] + s * (12 * c[4] + s * 20 * c[5])); };
  const double T = 1.5;
  const double v0 = qd(0), a0 = qdd(0), v1 = qd(T), a1 = qdd(T);
  const SplineSegment seg =
      SplineSegment::between(knot(2, q(0), &v0, &a0), knot(2 + T, q(T), &v1, &a1));
  EXPECT_EQ(seg.kind, SegmentKind::kQuintic);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(seg.c[k], c[k], kTol) << k;
  for (double s : {0.0, 0.2, 0.75, 1.1, 1.5}) {
    const JointSample x = seg.at(2 + s);
    EXPECT_NEAR(x.position, q(s), kTol);
    EXPECT_NEAR(x.velocity, qd(s), kTol);
    EXPECT_NEAR(x.acceleration, qdd(s), kTol);
  }
}

TEST(SplineSegment, AccelerationsWithoutVelocitiesGiveALinearSegment) {
  // joint_trajectory_controller: no velocities at an end → linear, whatever the accelerations.
  const double a = 3;
  EXPECT_EQ(SplineSegment::between(knot(0, 0, nullptr, &a), knot(1, 1, nullptr, &a)).kind,
            SegmentKind::kLinear);
}

TEST(TrajectorySpline, HitsEveryKnotAndIsContinuousWhereTheEndsAllowIt) {
  // Two joints, four points with positions, velocities and accelerations (quintic everywhere),
  // from a start state at t0 = 1, the points at start_time 1 + time_from_start.
  std::vector<TrajectoryPoint> points(4);
  const double times[4] = {0.5, 1.0, 1.7, 2.0};
  for (int k = 0; k < 4; ++k) {
    points[k].positions = {0.1 * k * k, -0.3 * k};
    points[k].velocities = {0.2 * k, k % 2 ? 0.5 : -0.25};
    points[k].accelerations = {-0.1 * k, 0.05 * k};
    points[k].time_from_start = times[k];
  }
  const std::vector<JointSample> start = {{0.3, -0.2, 0.4}, {1.0, 0.0, 0.0}};
  const TrajectorySpline spline = TrajectorySpline::build(1.0, start, points, 1.0);
  ASSERT_EQ(spline.joints.size(), 2u);
  std::vector<JointSample> x;
  spline.sample(1.0, x);
  for (int j = 0; j < 2; ++j) {
    EXPECT_NEAR(x[j].position, start[j].position, kTol);
    EXPECT_NEAR(x[j].velocity, start[j].velocity, kTol);
    EXPECT_NEAR(x[j].acceleration, start[j].acceleration, kTol);
  }
  for (int k = 0; k < 4; ++k) {
    spline.sample(1.0 + times[k], x);
    for (int j = 0; j < 2; ++j) {
      EXPECT_NEAR(x[j].position, points[k].positions[j], kTol) << k;
      EXPECT_NEAR(x[j].velocity, points[k].velocities[j], kTol) << k;
      EXPECT_NEAR(x[j].acceleration, points[k].accelerations[j], kTol) << k;
    }
  }
  // Continuity: each segment's end equals the next one's start in q, q̇ and q̈.
  for (const JointSpline& js : spline.joints) {
    const auto& segs = js.segments();
    for (std::size_t i = 0; i + 1 < segs.size(); ++i) {
      const JointSample l = segs[i].at(segs[i].end()), r = segs[i + 1].at(segs[i + 1].begin);
      EXPECT_NEAR(l.position, r.position, kTol);
      EXPECT_NEAR(l.velocity, r.velocity, kTol);
      EXPECT_NEAR(l.acceleration, r.acceleration, kTol);
    }
  }
  // Before the start: the start position at rest; after the end: the last position at rest,
  // although the last point gives a velocity (joint_trajectory_controller's sampling).
  spline.sample(0.5, x);
  EXPECT_EQ(x[0].position, 0.3);
  EXPECT_EQ(x[0].velocity, 0.0);
  spline.sample(3.5, x);
  EXPECT_NEAR(x[1].position, points[3].positions[1], kTol);
  EXPECT_EQ(x[1].velocity, 0.0);
  EXPECT_EQ(x[1].acceleration, 0.0);
  EXPECT_DOUBLE_EQ(spline.endTime(), 3.0);
}

TEST(JointSpline, SpliceKeepsTheCurrentUntilTheNewStartThenBridgesFromItsState) {
  // Current: linear 0 → 2 over [0, 2]. New knots from t_b = 1.5 (now = 1): cubic to (3, q = 1,
  // q̇ = 0) from the current state at 1.5: q = 1.5, q̇ = 1 (the current linear's slope).
  const JointSpline current = JointSpline::through(knot(0, 0), {knot(2, 2)});
  const double v = 0;
  const JointSpline s = JointSpline::splice(current, 1.0, 1.5, {knot(3, 1, &v)});
  for (double t : {1.0, 1.2, 1.5}) EXPECT_NEAR(s.sample(t).position, t, kTol);
  // The bridge starts from the current state at t_b (q = 1.5, q̇ = 1: the bridge start always
  // carries q̇ and q̈) and, the knot giving q̇, is the cubic that meets both ends — unique, so its
  // ends are the check.
  const JointSample end = s.segments().back().at(3);
  EXPECT_NEAR(end.position, 1, kTol);
  EXPECT_NEAR(end.velocity, 0, kTol);
  EXPECT_EQ(s.segments().back().kind, SegmentKind::kCubic);
  // q̇ continuous across t_b: 1e-9 covers the 1e-12 step times |q̈| ≤ 10 and round-off.
  EXPECT_NEAR(s.sample(1.5 + 1e-12).velocity, 1.0, 1e-9);
}

}  // namespace trajectory_spline_test
}  // namespace control
}  // namespace cga_rigid_sim
