// Gazebo's sensors and model plugins read from a URDF (scene/sensors.h, doc/sensors.md). Truth:
// gazebo_ros's documented parameter names and defaults (topic names joined to robotNamespace,
// gazebo_ros_imu_sensor's namespace defaulting to the model's name, the diff drive's 0.34 m and
// 0.15 m), and the "Bad input" rules of issue 39: an unknown sensor type or plugin is warned
// about by name; a sensor on an unknown link or joint, a negative rate or noise and a drive
// naming missing joints are refused with the line and the rule.
#include <gtest/gtest.h>

#include <string>

#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace gazebo_sensors_test {

// A two-wheeled base with an IMU link fixed to it: `extra` goes inside <robot>.
std::string rover(const std::string& extra) {
  return R"(<robot name="bot">
  <link name="base"><inertial><mass value="2"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="imu_link"/>
  <joint name="imu_joint" type="fixed"><parent link="base"/><child link="imu_link"/><origin xyz="0.1 0 0.05"/></joint>
  <link name="left_wheel"><inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="right_wheel"><inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="left_joint" type="continuous"><parent link="base"/><child link="left_wheel"/><origin xyz="0 0.2 0"/><axis xyz="0 1 0"/></joint>
  <joint name="right_joint" type="continuous"><parent link="base"/><child link="right_wheel"/><origin xyz="0 -0.2 0"/><axis xyz="0 1 0"/></joint>
)" + extra +
         "\n</robot>\n";
}

Result<Scene> load(const std::string& extra) {
  return loadUrdfString(rover(extra), "bot.urdf", SceneOptions{});
}

bool hasWarning(const Scene& scene, const std::string& part) {
  for (const auto& w : scene.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

TEST(GazeboSensors, ImuSensorWithItsPluginParameters) {
  auto scene = load(R"(
  <gazebo reference="imu_link">
    <sensor name="imu" type="imu">
      <always_on>true</always_on>
      <update_rate>200</update_rate>
      <pose>0 0 0.01 0 0 1.5707963267948966</pose>
      <imu><angular_velocity><x><noise type="gaussian"><mean>0</mean><stddev>0.01</stddev>
        <bias_mean>0.001</bias_mean><bias_stddev>0.0001</bias_stddev></noise></x></angular_velocity>
        <linear_acceleration><z><noise type="gaussian"><stddev>0.1</stddev></noise></z></linear_acceleration></imu>
      <plugin name="imu_plugin" filename="libgazebo_ros_imu_sensor.so">
        <topicName>imu/data</topicName>
        <updateRateHZ>100.0</updateRateHZ>
        <gaussianNoise>0.0</gaussianNoise>
        <frameName>imu_link</frameName>
      </plugin>
    </sensor>
  </gazebo>)");
  ASSERT_TRUE(scene) << scene.error();
  ASSERT_EQ(scene->sensors.sensors.size(), 1u);
  const SensorModel& s = scene->sensors.sensors[0];
  EXPECT_EQ(s.kind, SensorKind::kImu);
  EXPECT_EQ(s.link, "imu_link");
  EXPECT_EQ(s.topic, "/bot/imu/data");  // robotNamespace defaults to "/" + the model's name
  EXPECT_EQ(s.frame_id, "imu_link");
  EXPECT_EQ(s.update_rate, 100.0);  // the slower of <update_rate> and <updateRateHZ>
  EXPECT_EQ(s.angular_velocity_noise[0].stddev, 0.01);
  EXPECT_EQ(s.angular_velocity_noise[0].bias_mean, 0.001);
  EXPECT_EQ(s.angular_velocity_noise[0].bias_stddev, 0.0001);
  EXPECT_FALSE(s.angular_velocity_noise[1].any());
  EXPECT_EQ(s.linear_acceleration_noise[2].stddev, 0.1);
  EXPECT_EQ(s.X_LS.translation(), Eigen::Vector3d(0, 0, 0.01));
  // yaw π/2: the sensor's x axis along the link's y (to the rounding of cos(π/2) ≈ 6e-17).
  EXPECT_NEAR((s.X_LS.linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0,
              1e-15);
  EXPECT_FALSE(s.initial_orientation_as_reference);
}

TEST(GazeboSensors, ModelPluginsP3dImuFtAndDiffDrive) {
  auto scene = load(R"(
  <gazebo>
    <plugin name="truth" filename="libgazebo_ros_p3d.so">
      <bodyName>base</bodyName><topicName>ground_truth/state</topicName><updateRate>50</updateRate>
      <gaussianNoise>0.01</gaussianNoise><frameName>world</frameName><xyzOffsets>1 2 3</xyzOffsets>
    </plugin>
    <plugin name="old_imu" filename="libgazebo_ros_imu.so"><bodyName>imu_link</bodyName></plugin>
    <plugin name="ft" filename="libgazebo_ros_ft_sensor.so">
      <jointName>left_joint</jointName><topicName>ft</topicName><robotNamespace>/r</robotNamespace>
    </plugin>
    <plugin name="drive" filename="libgazebo_ros_diff_drive.so">
      <leftJoint>left_joint</leftJoint><rightJoint>right_joint</rightJoint>
      <wheelSeparation>0.4</wheelSeparation><odometrySource>encoder</odometrySource>
    </plugin>
  </gazebo>)");
  ASSERT_TRUE(scene) << scene.error();
  ASSERT_EQ(scene->sensors.sensors.size(), 3u);
  const SensorModel& p3d = scene->sensors.sensors[0];
  EXPECT_EQ(p3d.kind, SensorKind::kGroundTruth);
  EXPECT_EQ(p3d.topic, "ground_truth/state");
  EXPECT_EQ(p3d.link, "base");
  EXPECT_EQ(p3d.reference_link, "world");
  EXPECT_EQ(p3d.update_rate, 50.0);
  EXPECT_EQ(p3d.gaussian_noise, 0.01);
  EXPECT_EQ(p3d.xyz_offset, Eigen::Vector3d(1, 2, 3));
  const SensorModel& imu = scene->sensors.sensors[1];
  EXPECT_EQ(imu.kind, SensorKind::kImu);
  EXPECT_EQ(imu.topic, "/default_imu");  // gazebo_ros_imu's default
  EXPECT_EQ(imu.frame_id, "imu_link");   // frameName defaults to bodyName
  EXPECT_EQ(imu.update_rate, 0.0);       // every step
  const SensorModel& ft = scene->sensors.sensors[2];
  EXPECT_EQ(ft.kind, SensorKind::kForceTorque);
  EXPECT_EQ(ft.joint, "left_joint");
  EXPECT_EQ(ft.link, "left_wheel");
  EXPECT_EQ(ft.topic, "/r/ft");
  ASSERT_EQ(scene->sensors.drives.size(), 1u);
  const DriveModel& d = scene->sensors.drives[0];
  EXPECT_EQ(d.left_joints, std::vector<std::string>{"left_joint"});
  EXPECT_EQ(d.right_joints, std::vector<std::string>{"right_joint"});
  EXPECT_EQ(d.wheel_separation, 0.4);
  EXPECT_EQ(d.wheel_diameter, 0.15);  // gazebo_ros_diff_drive's default
  EXPECT_EQ(d.command_topic, "cmd_vel");
  EXPECT_EQ(d.odometry_topic, "odom");
  EXPECT_FALSE(d.odometry_from_world);
}

TEST(GazeboSensors, ContactAndForceTorqueSensors) {
  auto scene = load(R"(
  <gazebo reference="left_wheel">
    <sensor name="bump" type="contact"><contact><collision>left_wheel_collision</collision></contact>
      <plugin name="b" filename="libgazebo_ros_bumper.so"><bumperTopicName>bumper</bumperTopicName></plugin>
    </sensor>
  </gazebo>
  <gazebo reference="right_joint">
    <sensor name="ft" type="force_torque"><update_rate>10</update_rate>
      <force_torque><frame>parent</frame><measure_direction>parent_to_child</measure_direction></force_torque>
      <plugin name="p" filename="libgazebo_ros_ft_sensor.so"><topicName>wrench</topicName></plugin>
    </sensor>
  </gazebo>)");
  ASSERT_TRUE(scene) << scene.error();
  ASSERT_EQ(scene->sensors.sensors.size(), 2u);
  EXPECT_EQ(scene->sensors.sensors[0].kind, SensorKind::kContact);
  EXPECT_EQ(scene->sensors.sensors[0].topic, "bumper");
  EXPECT_EQ(scene->sensors.sensors[0].frame_id, "world");
  const SensorModel& ft = scene->sensors.sensors[1];
  EXPECT_EQ(ft.joint, "right_joint");
  EXPECT_EQ(ft.link, "right_wheel");
  EXPECT_EQ(ft.wrench_frame, WrenchFrame::kParent);
  EXPECT_EQ(ft.measure_direction, MeasureDirection::kParentToChild);
  EXPECT_EQ(ft.update_rate, 10.0);
}

TEST(GazeboSensors, ABumpersCollisionIsFoundByItsSdfName) {
  // sdformat's URDF → SDF names for the k-th <collision> of link "plate": the collision's name
  // (the link's if it has none) + "_collision", + "_k" for k > 0, and "plate_fixed_joint_lump__"
  // in front of a name that does not start with the link's; lumped into a parent, the parent's
  // prefix. Each resolves to its index; an unknown name is warned about and means every
  // collision; an unknown frameName is refused.
  const auto withBumper = [](const std::string& collision, const std::string& frame = "") {
    const std::string box = R"(<geometry><box size="0.1 0.1 0.1"/></geometry>)";
    return loadUrdfString(
        R"(<robot name="r"><link name="plate"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
      <collision>)" +
            box + "</collision><collision>" + box + R"(</collision><collision name="rim">)" + box +
            R"(</collision></link>
      <gazebo reference="plate"><sensor name="bump" type="contact"><contact><collision>)" +
            collision + R"(</collision></contact>
        <plugin name="b" filename="libgazebo_ros_bumper.so">)" +
            (frame.empty() ? "" : "<frameName>" + frame + "</frameName>") +
            "</plugin></sensor></gazebo></robot>",
        "bumper.urdf", SceneOptions{});
  };
  const std::pair<const char*, int> cases[] = {{"plate_collision", 0},
                                               {"plate_collision_1", 1},
                                               {"plate_fixed_joint_lump__rim_collision_2", 2},
                                               {"base_fixed_joint_lump__plate_collision_1", 1}};
  for (const auto& [name, index] : cases) {
    auto scene = withBumper(name);
    ASSERT_TRUE(scene) << scene.error();
    EXPECT_EQ(scene->sensors.sensors.at(0).collision, index) << name;
  }
  auto unknown = withBumper("plate_link_collision");
  ASSERT_TRUE(unknown) << unknown.error();
  EXPECT_EQ(unknown->sensors.sensors.at(0).collision, -1);
  EXPECT_TRUE(hasWarning(*unknown,
                         "<contact><collision> 'plate_link_collision' is not a collision of link "
                         "'plate' (its SDF names: 'plate_collision', 'plate_collision_1', "
                         "'plate_fixed_joint_lump__rim_collision_2'): the bumper reports every "
                         "contact of the link"));
  auto in_link = withBumper("plate_collision", "plate");
  ASSERT_TRUE(in_link) << in_link.error();
  EXPECT_EQ(in_link->sensors.sensors.at(0).reference_link, "plate");
  EXPECT_EQ(in_link->sensors.sensors.at(0).frame_id, "plate");
  auto bad_frame = withBumper("plate_collision", "chassis");
  ASSERT_FALSE(bad_frame);
  EXPECT_NE(
      bad_frame.error().find("<frameName> 'chassis' is neither world nor a link of this URDF"),
      std::string::npos)
      << bad_frame.error();
}

TEST(GazeboSensors, UnsupportedTypesAndPluginsAreWarnedAboutByName) {
  auto scene = load(R"(
  <gazebo reference="base"><sensor name="cam" type="camera"><plugin name="c" filename="libgazebo_ros_camera.so"/></sensor></gazebo>
  <gazebo reference="base"><sensor name="imu_bare" type="imu"/></gazebo>
  <gazebo><plugin name="laser" filename="libgazebo_ros_block_laser.so"/></gazebo>
  <gazebo><plugin name="gazebo_ros_control" filename="libgazebo_ros_control.so"/></gazebo>)");
  ASSERT_TRUE(scene) << scene.error();
  EXPECT_TRUE(scene->sensors.empty());
  EXPECT_TRUE(hasWarning(*scene, "sensor type 'camera' is not simulated"));
  EXPECT_TRUE(hasWarning(*scene, "'imu_bare' type='imu'> has no gazebo_ros plugin"));
  EXPECT_TRUE(hasWarning(*scene, "plugin 'libgazebo_ros_block_laser.so' is not simulated"));
  EXPECT_TRUE(hasWarning(*scene, "libgazebo_ros_control.so'>: ignored"));
  EXPECT_TRUE(hasWarning(*scene, "bot.urdf:"));  // each warning names the file and line
}

// Each refusal names the file, the line and the rule.
TEST(GazeboSensors, BadInputIsRefusedWithTheElementAndTheRule) {
  const std::pair<std::string, std::string> cases[] = {
      {R"(<gazebo reference="nowhere"><sensor name="s" type="imu"/></gazebo>)",
       "'nowhere' is not a link of this URDF"},
      {R"(<gazebo reference="base"><sensor name="s" type="force_torque"/></gazebo>)",
       "'base' is not a joint of this URDF"},
      {R"(<gazebo reference="base"><sensor name="s" type="imu"><update_rate>-5</update_rate></sensor></gazebo>)",
       "<update_rate> must be >= 0 (got '-5')"},
      {R"(<gazebo reference="base"><sensor name="s" type="imu"><imu><angular_velocity><x><noise type="gaussian"><stddev>-1</stddev></noise></x></angular_velocity></imu></sensor></gazebo>)",
       "<stddev> must be >= 0"},
      {R"(<gazebo><plugin name="p" filename="libgazebo_ros_p3d.so"><bodyName>ghost</bodyName><topicName>t</topicName></plugin></gazebo>)",
       "<bodyName> 'ghost' is not a link of this URDF"},
      {R"(<gazebo><plugin name="p" filename="libgazebo_ros_p3d.so"><bodyName>base</bodyName><topicName>t</topicName><gaussianNoise>-0.1</gaussianNoise></plugin></gazebo>)",
       "<gaussianNoise> must be >= 0"},
      {R"(<gazebo><plugin name="d" filename="libgazebo_ros_diff_drive.so"><leftJoint>lj</leftJoint><rightJoint>right_joint</rightJoint></plugin></gazebo>)",
       "<leftJoint> names joint 'lj', which is not a joint of this URDF"},
      {R"(<gazebo><plugin name="d" filename="libgazebo_ros_diff_drive.so"><leftJoint>imu_joint</leftJoint><rightJoint>right_joint</rightJoint></plugin></gazebo>)",
       "'imu_joint', which is not continuous or revolute"},
      {R"(<gazebo><plugin name="d" filename="libgazebo_ros_skid_steer_drive.so"/></gazebo>)",
       "<leftFrontJoint> names joint 'left_front_joint', which is not a joint"},
      {R"(<gazebo><plugin name="f" filename="libgazebo_ros_ft_sensor.so"><jointName>j</jointName><topicName>t</topicName></plugin></gazebo>)",
       "<jointName> 'j' is not a joint of this URDF"},
      {R"(<gazebo reference="base"><sensor name="s" type="imu"><pose>0 0 1</pose></sensor></gazebo>)",
       "<pose> must be six finite numbers"},
  };
  for (const auto& [extra, rule] : cases) {
    auto scene = load(extra);
    ASSERT_FALSE(scene) << extra;
    EXPECT_NE(scene.error().find(rule), std::string::npos)
        << "expected '" << rule << "' in: " << scene.error();
    EXPECT_EQ(scene.error().rfind("bot.urdf:", 0), 0u) << scene.error();
  }
}

}  // namespace gazebo_sensors_test
}  // namespace scene
}  // namespace cga_rigid_sim
