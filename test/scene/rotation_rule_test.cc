// The rotation rule (scene/rotation_rule.h). Truths: its documented bounds — every unit
// quaternion or rotation matrix rounded to 4 significant digits passes, norms off by more than
// kRotationTolerance (2 kRotationTolerance on RᵀR for a matrix), reflections and non-finite
// numbers are refused with the documented text.
#include "cga_rigid_sim/scene/rotation_rule.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>

namespace cga_rigid_sim {
namespace scene {
namespace rotation_rule_test {

// Rounds x to 4 significant digits, as a person copying it would.
double fourDigits(double x) {
  if (x == 0) return 0;
  const double unit = std::pow(10.0, std::floor(std::log10(std::abs(x))) - 3);
  return std::round(x / unit) * unit;
}

TEST(RotationRule, QuaternionsTypedWithFourDigitsPass) {
  EXPECT_FALSE(quaternionRule(0.7071, 0, 0, 0.7071));  // norm 0.99999
  std::mt19937_64 rng(21);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 10000; ++i) {
    Eigen::Vector4d q(n(rng), n(rng), n(rng), n(rng));
    q.normalize();
    const auto refused =
        quaternionRule(fourDigits(q[0]), fourDigits(q[1]), fourDigits(q[2]), fourDigits(q[3]));
    ASSERT_FALSE(refused) << *refused;
  }
}

TEST(RotationRule, QuaternionsOffByMoreThanTheToleranceAreRefused) {
  EXPECT_FALSE(quaternionRule(1.0 + 0.9 * kRotationTolerance, 0, 0, 0));
  EXPECT_FALSE(quaternionRule(0, 0, 1.0 - 0.9 * kRotationTolerance, 0));
  EXPECT_TRUE(quaternionRule(1.0 + 1.1 * kRotationTolerance, 0, 0, 0));
  EXPECT_TRUE(quaternionRule(0, 1.0 - 1.1 * kRotationTolerance, 0, 0));
  EXPECT_EQ(quaternionRule(1.1, 0, 0, 0).value_or(""),
            "must be a unit quaternion (norm 1.1; a norm within 0.001 of 1 is normalised, others "
            "are refused)");
  EXPECT_EQ(quaternionRule(0, 0, 0, 0).value_or("").rfind("must be a unit quaternion (norm 0;", 0),
            0u);
  EXPECT_EQ(quaternionRule(1, std::numeric_limits<double>::quiet_NaN(), 0, 0).value_or(""),
            "not finite");
  EXPECT_EQ(quaternionRule(std::numeric_limits<double>::infinity(), 0, 0, 0).value_or(""),
            "not finite");
}

TEST(RotationRule, MatricesTypedWithFourDigitsPass) {
  std::mt19937_64 rng(22);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 10000; ++i) {
    Eigen::Matrix3d R =
        Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
    EXPECT_FALSE(rotationMatrixRule(R));
    R = R.unaryExpr(&fourDigits);
    const auto refused = rotationMatrixRule(R);
    ASSERT_FALSE(refused) << *refused;
  }
}

TEST(RotationRule, ScaledReflectedAndNonFiniteMatricesAreRefused) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  // (1 + s)² − 1 ≈ 2s against the bound 2 kRotationTolerance.
  EXPECT_FALSE(rotationMatrixRule((1.0 + 0.9 * kRotationTolerance) * I));
  EXPECT_TRUE(rotationMatrixRule((1.0 + 1.1 * kRotationTolerance) * I));
  Eigen::Matrix3d reflection = I;
  reflection(2, 2) = -1;
  EXPECT_EQ(rotationMatrixRule(reflection).value_or(""),
            "not a proper rotation (max |R^T R - I| = 0, det R = -1; allowed 0.002, det > 0)");
  Eigen::Matrix3d nan = I;
  nan(0, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(rotationMatrixRule(nan).value_or(""), "not finite");
}

}  // namespace rotation_rule_test
}  // namespace scene
}  // namespace cga_rigid_sim
