// The IMU (sensor/imu.h, doc/sensors.md#imu) against analytic values, noise off: at rest it
// reads +g up, in free fall 0, on a body spinning steadily about a principal axis the
// centripetal acceleration ω × (ω × r); on free bodies, on a body resting on the ground and on a
// link of a tree. Then the noise: its statistics over 10⁵ samples within their confidence
// bounds, and bit-identical replays with noise on.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "cga_rigid_sim/sensor/sensors.h"
#include "cga_rigid_sim/sim/world.h"
#include "common/urdf_world.h"

namespace cga_rigid_sim {
namespace sensor {
namespace imu_test {

constexpr double kEps = 2.220446049250313e-16;
constexpr double kG = 9.81;

using Map = scene::ParamValue::Map;
using List = scene::ParamValue::List;

// {name: {key: [x, y, z]}} of the initial-state dictionary.
scene::ParamValue initial(const std::string& name, const std::string& key,
                          const Eigen::Vector3d& v) {
  return Map{{name, Map{{key, List{v.x(), v.y(), v.z()}}}}};
}

std::unique_ptr<sim::World> makeWorld(const std::string& urdf, sim::WorldConfig config = {},
                                      scene::ParamValue initial_state = {},
                                      Eigen::Vector3d g = Eigen::Vector3d(0, 0, -kG)) {
  scene::SceneOptions options;
  options.gravity_W = g;
  return test::worldFromUrdf(urdf, config, std::move(initial_state), options);
}

// An IMU plugin on `link` at <pose>, with `noise` inside <imu>.
std::string imuOn(const std::string& link, const std::string& pose, const std::string& noise = "") {
  return "<gazebo reference=\"" + link + "\"><sensor name=\"imu\" type=\"imu\"><pose>" + pose +
         "</pose><imu>" + noise +
         "</imu><plugin name=\"p\" filename=\"libgazebo_ros_imu_sensor.so\">"
         "<updateRateHZ>0</updateRateHZ></plugin></sensor></gazebo>";
}

// One free body, a box 0.4 × 0.2 × 0.1 m of 2 kg (distinct principal moments), optionally with
// its collision box.
std::string box(const std::string& extra, bool collision) {
  const std::string geometry = "<geometry><box size=\"0.4 0.2 0.1\"/></geometry>";
  return R"(<robot name="r"><link name="box"><inertial><mass value="2"/>
    <inertia ixx="0.008333333333333333" iyy="0.02833333333333333" izz="0.03333333333333333" ixy="0" ixz="0" iyz="0"/></inertial>)" +
         (collision ? "<collision>" + geometry + "</collision>" : std::string()) + "</link>" +
         extra + "</robot>";
}

// Steps once after remembering, and returns the IMU's sample.
ImuSample sampleAfterStep(Sensors& sensors, sim::World& world, std::uint64_t n = 0) {
  sensors.remember(0, world);
  world.step();
  EXPECT_TRUE(sensors.ready(0, world));
  return sensors.imu(0, world, n);
}

// A sensor turned by yaw π/2 about z and pitched by π/2 about y (URDF rpy) reads a world vector
// v as R_WSᵀ v: the truth the tests below compare with, computed from the pose alone.
Eigen::Matrix3d rotationFromRpy(double r, double p, double y) {
  return (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

TEST(Imu, FreeFallReadsZeroAndTheOrientationOfItsFrame) {
  // Truth: in free fall the specific force is 0. The body coasts on the exact flow (v = v0 + g t
  // to rounding); the mean acceleration over a step, (v(t) − v(t − h))/h, carries the rounding
  // of two velocities of size |v| ≤ 10 m/s divided by h = 1 ms: 4 ε |v| / h ≈ 1e-11.
  auto world = makeWorld(box(imuOn("box", "0.1 0.05 0 0.3 0.2 0.1"), false));
  Sensors sensors(*world, 1);
  world->step(999);
  const ImuSample s = sampleAfterStep(sensors, *world);
  EXPECT_LT(s.linear_acceleration_S.norm(), 4 * kEps * 10 / 1e-3);
  EXPECT_LT(s.angular_velocity_S.norm(), 1e-15);
  // The body does not turn: the sensor's attitude is its <pose>'s rotation.
  const Eigen::Quaterniond q(rotationFromRpy(0.3, 0.2, 0.1));
  EXPECT_NEAR(std::abs(s.orientation_WS.dot(q)), 1.0, 4 * kEps);
}

TEST(Imu, SpinningBodyReadsTheCentripetalTerm) {
  // Truth: a body spinning at constant ω about its principal axis z; a point at r (body axes)
  // accelerates by ω × (ω × r) = −ω² r_⊥; the sensor, pitched by π/2, reads it in its axes.
  // In free fall as well (gravity on): the fall cancels, the centripetal term stays. ω_B stays
  // constant on the exact flow up to rounding, so the bound is a few ε of ω² |r| ≈ 7.5 m/s².
  const double w = 5.0;
  const Eigen::Vector3d r(0.3, 0.1, 0.05);
  for (const Eigen::Vector3d& g : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, -kG)}) {
    auto world = makeWorld(box(imuOn("box", "0.3 0.1 0.05 0 1.5707963267948966 0"), false), {},
                           initial("box", "angular_velocity_body", {0, 0, 5}), g);
    Sensors sensors(*world, 1);
    world->step(1234);
    const ImuSample s = sampleAfterStep(sensors, *world);
    const Eigen::Vector3d a_B(-w * w * r.x(), -w * w * r.y(), 0.0);
    const Eigen::Matrix3d R_BS = rotationFromRpy(0, M_PI / 2, 0);
    const Eigen::Vector3d expected = R_BS.transpose() * a_B;
    EXPECT_LT((s.linear_acceleration_S - expected).norm(), 1e-11 * (1 + g.norm()))
        << s.linear_acceleration_S.transpose() << " vs " << expected.transpose();
    EXPECT_LT((s.angular_velocity_S - R_BS.transpose() * Eigen::Vector3d(0, 0, w)).norm(),
              8 * kEps * w);
  }
}

TEST(Imu, RestingOnTheGroundReadsPlusGUp) {
  // Truth: at rest the specific force is −g: +9.81 m/s² along the world's up, in the sensor's
  // axes (here yawed by π/2 and rolled by π: up is the sensor's −z). The box settles on the
  // ground plane and rests (its velocity exactly zero once asleep or resting).
  sim::WorldConfig config;
  config.ground_plane = sim::GroundPlane{};
  auto world = makeWorld(box(imuOn("box", "0 0 0.05 3.141592653589793 0 1.5707963267948966"), true),
                         config, initial("box", "position", {0, 0, 0.06}));
  Sensors sensors(*world, 1);
  world->step(3000);
  const ImuSample s = sampleAfterStep(sensors, *world);
  const Eigen::Matrix3d R_WS =
      world->getBodyState("box")->pose_root.linear() * rotationFromRpy(M_PI, 0, M_PI / 2);
  const Eigen::Vector3d expected = R_WS.transpose() * Eigen::Vector3d(0, 0, kG);
  // The resting contact holds the box to its solver's tolerance; a settled box's velocities
  // change by less than 1e-9 m/s per step here.
  EXPECT_LT((s.linear_acceleration_S - expected).norm(), 1e-5)
      << s.linear_acceleration_S.transpose();
  EXPECT_NEAR(s.linear_acceleration_S.z(), -kG, 1e-5);
}

TEST(Imu, OnALinkOfATreeHangingAtRest) {
  // Truth: a pendulum hanging straight down is in equilibrium: its link stays at rest and the
  // IMU on it reads +g up. The link's IMU is below the joint (r = −0.5 z).
  const std::string urdf = R"(<robot name="p"><link name="world"/>
    <link name="arm"><inertial><origin xyz="0 0 -0.5"/><mass value="1"/><inertia ixx="0.02" iyy="0.02" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="hinge" type="continuous"><parent link="world"/><child link="arm"/><origin xyz="0 0 2"/><axis xyz="1 0 0"/></joint>)" +
                           imuOn("arm", "0 0 -0.5 0 0 0") + "</robot>";
  auto world = makeWorld(urdf);
  Sensors sensors(*world, 1);
  world->step(500);
  const ImuSample s = sampleAfterStep(sensors, *world);
  // Gravity acts along the arm: no torque, q̈ = 0 up to the rounding of the link's pose.
  EXPECT_LT((s.linear_acceleration_S - Eigen::Vector3d(0, 0, kG)).norm(), 1e-9);
  EXPECT_LT(s.angular_velocity_S.norm(), 1e-12);
}

TEST(Imu, SwingingLinkMatchesTheTreesOwnAcceleration) {
  // Truth: a rigid pendulum of length-to-centre l released at angle θ0 from rest: at release
  // θ̈ = −(m g l / I_pivot) sin θ0, and a point at distance d along the arm has tangential
  // acceleration d θ̈ and no centripetal part (θ̇ = 0). The IMU at the centre, one step after
  // release, reads (a − g) in its axes; the step's mean acceleration differs from the instant's
  // by O(h) of the change of θ̈ — with θ̇ ≈ θ̈ h, the centripetal part d θ̇² ≈ 1e-5 and the drift
  // of sin θ over a step ≈ 1e-5 relative: 1e-3 m/s² bounds both.
  const double l = 0.5, m = 1.0, I_c = 0.02, theta0 = 0.4;
  const std::string urdf = R"(<robot name="p"><link name="world"/>
    <link name="arm"><inertial><origin xyz="0 0 -0.5"/><mass value="1"/><inertia ixx="0.02" iyy="0.02" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="hinge" type="continuous"><parent link="world"/><child link="arm"/><origin xyz="0 0 2"/><axis xyz="1 0 0"/></joint>)" +
                           imuOn("arm", "0 0 -0.5 0 0 0") + "</robot>";
  auto world = makeWorld(urdf, {}, Map{{"hinge", Map{{"position", 0.4}}}});
  Sensors sensors(*world, 1);
  const ImuSample s = sampleAfterStep(sensors, *world);
  const double theta_dd = -m * kG * l / (I_c + m * l * l) * std::sin(theta0);
  // Link axes: the arm along −z; a positive θ about x moves the centre towards +y·cos… the
  // tangential direction at the centre is −y in link axes times −1 (right-handed about x):
  // a point at (0, 0, −l) moving with θ̇ about x has velocity θ̇ x × (0, 0, −l) = (0, θ̇ l, 0).
  const Eigen::Vector3d a_L(0, theta_dd * l, 0);
  const Eigen::Matrix3d R_WL =
      Eigen::AngleAxisd(theta0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d expected = a_L - R_WL.transpose() * Eigen::Vector3d(0, 0, -kG);
  EXPECT_LT((s.linear_acceleration_S - expected).norm(), 1e-3)
      << s.linear_acceleration_S.transpose() << " vs " << expected.transpose();
}

TEST(Imu, ASensorGoesWithTheBodyItIsOn) {
  // ~delete_body removes the link the IMU is on, and the sensor with it (the node then drops
  // its topic): nothing is left to read a state that is gone.
  auto world = makeWorld(box(imuOn("box", "0 0 0 0 0 0"), false));
  ASSERT_EQ(Sensors(*world, 1).size(), 1u);
  ASSERT_TRUE(world->deleteBody("box"));
  EXPECT_TRUE(world->scene().sensors.sensors.empty());
  EXPECT_EQ(Sensors(*world, 1).size(), 0u);
}

// ---- noise ----

std::string noisyImu() {
  const std::string n =
      R"(<noise type="gaussian"><mean>0.0</mean><stddev>0.2</stddev><bias_mean>0.05</bias_mean><bias_stddev>0</bias_stddev></noise>)";
  return imuOn("box", "0 0 0 0 0 0",
               "<linear_acceleration><x>" + n +
                   "</x></linear_acceleration><angular_velocity><z>"
                   "<noise type=\"gaussian\"><stddev>0.01</stddev></noise></z></angular_velocity>");
}

TEST(ImuNoise, StatisticsOverATenthOfAMillionSamplesMatchTheDeclaredNoise) {
  // Truth: sample = value + bias + N(0, σ²) with |bias| = bias_mean (bias_stddev 0, random
  // sign). Over N = 10⁵ samples the sample mean is within 5 σ/√N of value + bias (5σ bounds:
  // a false failure once in ~1.7 million runs) and the sample variance within
  // 5 σ² √(2/(N−1)) of σ². The body is weightless and at rest: the value is exactly 0.
  auto world = makeWorld(box(noisyImu(), false), {}, {}, Eigen::Vector3d::Zero());
  Sensors sensors(*world, 42);
  sensors.remember(0, *world);
  world->step();
  const int N = 100000;
  double sum = 0, sum2 = 0, sum_w = 0, sum_w2 = 0;
  for (int n = 0; n < N; ++n) {
    const ImuSample s = sensors.imu(0, *world, n);
    sum += s.linear_acceleration_S.x();
    sum2 += s.linear_acceleration_S.x() * s.linear_acceleration_S.x();
    sum_w += s.angular_velocity_S.z();
    sum_w2 += s.angular_velocity_S.z() * s.angular_velocity_S.z();
    ASSERT_EQ(s.linear_acceleration_S.y(), 0.0);  // the other channels are noiseless
  }
  const double mean = sum / N, var = (sum2 - N * mean * mean) / (N - 1);
  const double sigma = 0.2;
  EXPECT_NEAR(std::abs(mean), 0.05, 5 * sigma / std::sqrt(N));
  EXPECT_NEAR(var, sigma * sigma, 5 * sigma * sigma * std::sqrt(2.0 / (N - 1)));
  const double mean_w = sum_w / N, var_w = (sum_w2 - N * mean_w * mean_w) / (N - 1);
  EXPECT_NEAR(mean_w, 0.0, 5 * 0.01 / std::sqrt(N));
  EXPECT_NEAR(var_w, 1e-4, 5 * 1e-4 * std::sqrt(2.0 / (N - 1)));
}

TEST(ImuNoise, ReplaysAreBitIdenticalWhateverWasSampledBefore) {
  // Truth: a sample is a function of (seed, sensor, n, state). Run A samples every step, run B
  // only every 7th; at the steps both sample they agree bit for bit. Another seed differs.
  auto a =
      makeWorld(box(noisyImu(), false), {}, initial("box", "angular_velocity_body", {1, 2, 3}));
  auto b =
      makeWorld(box(noisyImu(), false), {}, initial("box", "angular_velocity_body", {1, 2, 3}));
  auto c =
      makeWorld(box(noisyImu(), false), {}, initial("box", "angular_velocity_body", {1, 2, 3}));
  Sensors sa(*a, 7), sb(*b, 7), sc(*c, 8);
  int compared = 0;
  for (std::uint64_t k = 1; k <= 70; ++k) {
    sa.remember(0, *a);
    if (k % 7 == 0) sb.remember(0, *b), sc.remember(0, *c);
    a->step(), b->step(), c->step();
    const ImuSample ra = sa.imu(0, *a, k);
    if (k % 7 != 0) continue;
    const ImuSample rb = sb.imu(0, *b, k), rc = sc.imu(0, *c, k);
    EXPECT_EQ(ra.linear_acceleration_S, rb.linear_acceleration_S);
    EXPECT_EQ(ra.angular_velocity_S, rb.angular_velocity_S);
    EXPECT_EQ(ra.orientation_WS.coeffs(), rb.orientation_WS.coeffs());
    EXPECT_NE(ra.linear_acceleration_S.x(), rc.linear_acceleration_S.x());
    ++compared;
  }
  EXPECT_EQ(compared, 10);
}

}  // namespace imu_test
}  // namespace sensor
}  // namespace cga_rigid_sim
