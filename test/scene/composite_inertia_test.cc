// Composite mass properties of bodies merged from several links by fixed joints, against values
// derived by hand (below) from the URDF numbers with the parallel-axis theorem
//   J_C = Σ_i [R_i J_i R_iᵀ + m_i (|d_i|² 1 − d_i d_iᵀ)],  d_i = c_i − C,  C = Σ m_i c_i / M.
//
// Tolerance: the inputs are decimal numbers (not exact in binary, relative error ε/2 each) and the
// loader's arithmetic is a few dozen sums and products of numbers ≤ 0.5 (and rotations by π/2 whose
// cos is 6e-17 instead of 0), so every entry (≤ 0.14 kg m²) is within ~1e-16 of the exact value.
// 1e-12 absolute (the required figure) is far above that and far below any modelling error (the
// smallest hand-derived term is 1e-5).
#include <gtest/gtest.h>

#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace composite_inertia_test {

constexpr double kTol = 1e-12;

struct Composite {
  double mass;
  Eigen::Vector3d com_R;  ///< centre of mass in the root link frame
  Eigen::Matrix3d J_R;    ///< about the centre of mass, root link axes
};

// The composite as the loader stored it: B's pose in the root link frame R is M_RB = M_BR⁻¹,
// with M_BR the root link's LinkFrame, and J_R = R_RB diag(J1, J2, J3) R_RBᵀ.
Composite compositeOf(const BodyModel& body, double lambda) {
  const cga::Motor M_RB = body.links.at(0).M_BL.reverse();
  const Eigen::Matrix3d R_RB = M_RB.rotation().toRotationMatrix();
  Composite c;
  c.mass = body.inertia->mass();
  c.com_R = M_RB.translation(lambda);
  c.J_R = R_RB * body.inertia->principalMoments().asDiagonal() * R_RB.transpose();
  return c;
}

Scene load(const std::string& name, double lambda = 1.0) {
  SceneOptions options;
  options.lambda = lambda;
  auto scene = loadUrdfFile(std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/" + name, options);
  EXPECT_TRUE(scene.ok()) << scene.error();
  return scene.ok() ? *scene : Scene();
}

void expectComposite(const Composite& got, double mass, const Eigen::Vector3d& com,
                     const Eigen::Matrix3d& J) {
  EXPECT_NEAR(got.mass, mass, kTol);
  EXPECT_LT((got.com_R - com).cwiseAbs().maxCoeff(), kTol) << got.com_R.transpose();
  EXPECT_LT((got.J_R - J).cwiseAbs().maxCoeff(), kTol) << "\n" << got.J_R;
}

// urdf/dumbbell.urdf: rod link `bar` (frame at one end of the rod, along x), mass 0.5 at
// x = 0.25 with (ixx, iyy, izz) = (0.0001, 0.0067, 0.0067); spheres `weight_a` at x = 0 and
// `weight_b` at x = 0.5 (its joint turned by an arbitrary rpy, which a sphere does not notice),
// each mass 1 with J = 0.001·1.
//   M = 0.5 + 1 + 1 = 2.5;  C = (0.5·0.25 + 1·0 + 1·0.5)/2.5 = 0.25 on x.
//   d = 0 (rod), −0.25 and +0.25 (spheres), all along x, so the parallel-axis terms add
//   m d² = 0.0625 to Iyy and Izz of each sphere and nothing to Ixx:
//   Ixx = 0.0001 + 0.001 + 0.001 = 0.0021
//   Iyy = Izz = 0.0067 + 2·(0.001 + 0.0625) = 0.1337;  no products of inertia.
TEST(CompositeInertia, DumbbellMatchesHandDerivation) {
  const Scene scene = load("dumbbell.urdf");
  ASSERT_EQ(scene.bodies.size(), 1u);
  const BodyModel& body = scene.bodies[0];
  EXPECT_EQ(body.name, "bar");
  ASSERT_EQ(body.links.size(), 3u);
  EXPECT_EQ(body.merged_joints, (std::vector<std::string>{"weight_a_weld", "weight_b_weld"}));
  Eigen::Matrix3d J = Eigen::Vector3d(0.0021, 0.1337, 0.1337).asDiagonal();
  expectComposite(compositeOf(body, scene.lambda), 2.5, Eigen::Vector3d(0.25, 0, 0), J);
  // Symmetric: the distinct axis (the rod) is B's e3 (body/inertia.h).
  EXPECT_EQ(body.inertia->inertiaClass(), dynamics::InertiaClass::kSymmetric);
  EXPECT_NEAR(body.inertia->principalMoments()[2], 0.0021, kTol);
  EXPECT_NEAR(body.inertia->principalMoments()[0], 0.1337, kTol);
}

// urdf/t_handle.urdf: shaft (root) along z, mass 0.4, (0.001, 0.001, 0.00002) at (0, 0, 0.1).
// bar_left: joint at (0, 0.05, 0.2); inertial at (0, 0.05, 0) of its link, rpy (π/2, 0, 0),
// mass 0.2, (0.0002, 0.0002, 0.00001) in the inertial frame. Rx(π/2) takes the inertial z axis
// to −y, so in the link frame J = diag(0.0002, 0.00001, 0.0002); centre (0, 0.1, 0.2) of R.
// bar_right: joint at (0, −0.05, 0.2) with yaw π (link x = −R x, link y = −R y), inertial at
// (0, 0.05, 0), rpy (−π/2, 0, 0): centre (0, −0.1, 0.2) of R, J = diag(0.0002, 0.00001, 0.0002)
// in R (a rotation by π about z keeps a diagonal tensor diagonal).
//   M = 0.8;  C = (0, (0.2·0.1 − 0.2·0.1)/0.8, (0.4·0.1 + 0.2·0.2 + 0.2·0.2)/0.8) = (0, 0, 0.15).
//   d: shaft (0, 0, −0.05); bars (0, ±0.1, 0.05).
//   Ixx = [0.001 + 0.4·0.05²] + 2·[0.0002 + 0.2·(0.1² + 0.05²)] = 0.002 + 2·0.0027 = 0.0074
//   Iyy = [0.001 + 0.4·0.05²] + 2·[0.00001 + 0.2·0.05²]         = 0.002 + 2·0.00051 = 0.00302
//   Izz = [0.00002 + 0]       + 2·[0.0002 + 0.2·0.1²]           = 0.00002 + 2·0.0022 = 0.00442
//   Iyz = −Σ m d_y d_z = −(0.2·0.1·0.05 + 0.2·(−0.1)·0.05) = 0;  Ixy = Ixz = 0 (d_x = 0).
TEST(CompositeInertia, THandleMatchesHandDerivation) {
  const Scene scene = load("t_handle.urdf");
  ASSERT_EQ(scene.bodies.size(), 1u);
  const BodyModel& body = scene.bodies[0];
  EXPECT_EQ(body.name, "shaft");
  ASSERT_EQ(body.links.size(), 3u);
  Eigen::Matrix3d J = Eigen::Vector3d(0.0074, 0.00302, 0.00442).asDiagonal();
  expectComposite(compositeOf(body, scene.lambda), 0.8, Eigen::Vector3d(0, 0, 0.15), J);
  EXPECT_EQ(body.inertia->inertiaClass(), dynamics::InertiaClass::kAsymmetric);
  EXPECT_LT((body.inertia->principalMoments() - Eigen::Vector3d(0.00302, 0.00442, 0.0074))
                .cwiseAbs()
                .maxCoeff(),
            kTol);
}

// urdf/tennis_racket.urdf: handle 0.2 kg at x = 0.1, (0.0001, 0.0005, 0.0006); head joint at
// x = 0.2, head 0.2 kg at x = 0.1 of its frame, (0.0039, 0.0035, 0.0074).
//   M = 0.4, C = 0.2 on x, d = ∓0.1 on x (m d² = 0.002 each, added to Iyy and Izz):
//   Ixx = 0.0001 + 0.0039 = 0.004, Iyy = 0.0005 + 0.0035 + 0.004 = 0.008,
//   Izz = 0.0006 + 0.0074 + 0.004 = 0.012: diag(1, 2, 3)·0.004.
TEST(CompositeInertia, TennisRacketIsDiagOneTwoThree) {
  const Scene scene = load("tennis_racket.urdf");
  ASSERT_EQ(scene.bodies.size(), 1u);
  Eigen::Matrix3d J = Eigen::Vector3d(0.004, 0.008, 0.012).asDiagonal();
  expectComposite(compositeOf(scene.bodies[0], scene.lambda), 0.4, Eigen::Vector3d(0.2, 0, 0), J);
}

// The length scale λ enters only the motors' dual parts: the composite must not move with it.
TEST(CompositeInertia, IndependentOfLambda) {
  for (const char* name : {"dumbbell.urdf", "t_handle.urdf"}) {
    const Scene a = load(name, 1.0), b = load(name, 7.3);
    const Composite ca = compositeOf(a.bodies.at(0), a.lambda);
    const Composite cb = compositeOf(b.bodies.at(0), b.lambda);
    EXPECT_LT((ca.com_R - cb.com_R).cwiseAbs().maxCoeff(), 1e-15) << name;
    EXPECT_LT((ca.J_R - cb.J_R).cwiseAbs().maxCoeff(), 1e-15) << name;
  }
}

}  // namespace composite_inertia_test
}  // namespace scene
}  // namespace cga_rigid_sim
