// Collision shapes and contact parameters out of the loader (collision_shape.h, doc/urdf.md):
// - poses: a shape's world pose at the initial state, M_WB0 M_BS, against the URDF origins
//   composed by hand with Eigen (joint origin, then collision origin, rpy as Rz Ry Rx) — a truth
//   that never passes through the body frame B, the principal axes or motors;
// - contact parameters against the numbers written in the URDF, with the precedence of
//   doc/urdf.md (extension over Gazebo, the smaller of Gazebo's mu1/mu2, unset = nullopt);
// - mesh vertices against the mesh files read here with a few lines of text parsing, scaled.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cga_rigid_sim/scene/scene_summary.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace collision_shapes_test {

namespace fs = std::filesystem;
using Kind = CollisionShape::Kind;

const fs::path kMeshes = fs::path(CGA_RIGID_SIM_SOURCE_DIR) / "test/scene/bad_urdf/meshes";

// URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Isometry3d origin(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  X.translation() = xyz;
  return X;
}

// The shape's world pose at the initial state, as the loader gives it.
Eigen::Isometry3d shapeInWorld(const Scene& scene, const BodyModel& body,
                               const CollisionShape& shape) {
  return (body.M_WB0 * shape.M_BS).toIsometry(scene.lambda);
}

// Tolerance of the pose checks: both sides compose three or four rotations and translations of
// numbers ≤ 1 m, each rounding to a few ε; the loader also passes through B (an eigen-
// decomposition) and motors, which returns to the same pose to ~1e-15. 1e-12 leaves a margin of
// hundreds while a frame error (wrong order, transposed rotation, lost offset) is ≥ 1e-2.
constexpr double kPoseTol = 1e-12;

void expectPose(const Eigen::Isometry3d& got, const Eigen::Isometry3d& truth) {
  EXPECT_LT((got.linear() - truth.linear()).cwiseAbs().maxCoeff(), kPoseTol) << got.matrix();
  EXPECT_LT((got.translation() - truth.translation()).cwiseAbs().maxCoeff(), kPoseTol)
      << got.translation().transpose() << " vs " << truth.translation().transpose();
}

// A free body of two links merged by a fixed joint, each with collisions at turned origins.
// The base's inertia is off-centre and not diagonal, so B differs from every link frame.
const char* const kTwoLinks =
    R"(<robot name="two" xmlns:cga_rigid_sim="urn:cga_rigid_sim:urdf_extension">
  <link name="world"/>
  <joint name="float" type="floating"><parent link="world"/><child link="base"/>
    <origin xyz="0.5 -0.25 1" rpy="0.3 -0.2 0.7"/></joint>
  <link name="base">
    <inertial><origin xyz="0.02 0.01 -0.03" rpy="0.1 0.2 0.3"/><mass value="2"/>
      <inertia ixx="0.03" ixy="0.001" ixz="0" iyy="0.04" iyz="0.002" izz="0.05"/></inertial>
    <collision name="base_box">
      <origin xyz="0.1 0 0.05" rpy="0.4 0.5 -0.6"/>
      <geometry><box size="0.3 0.2 0.1"/></geometry>
    </collision>
    <collision>
      <geometry><sphere radius="0.05"/></geometry>
    </collision>
  </link>
  <joint name="weld" type="fixed"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0.2 0.1" rpy="-0.8 0.1 1.2"/></joint>
  <link name="arm">
    <inertial><mass value="0.5"/>
      <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.001"/></inertial>
    <collision>
      <origin xyz="0 0 0.15" rpy="1.5707963267948966 0 0.25"/>
      <geometry><cylinder radius="0.02" length="0.3"/></geometry>
    </collision>
  </link>
</robot>)";

TEST(CollisionShapes, PosesOfAMergedTwoLinkBodyAgainstTheUrdfOriginsComposedByHand) {
  const auto scene = loadUrdfString(kTwoLinks, "two", SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_EQ(scene->bodies.size(), 1u);
  const BodyModel& b = scene->bodies[0];
  ASSERT_EQ(b.shapes.size(), 3u);
  const Eigen::Isometry3d X_W_base =
      origin(Eigen::Vector3d(0.5, -0.25, 1), Eigen::Vector3d(0.3, -0.2, 0.7));
  const Eigen::Isometry3d X_W_arm =
      X_W_base * origin(Eigen::Vector3d(0, 0.2, 0.1), Eigen::Vector3d(-0.8, 0.1, 1.2));

  const CollisionShape& box = b.shapes[0];
  EXPECT_EQ(box.kind, Kind::kBox);
  EXPECT_EQ(box.name, "base_box");
  EXPECT_EQ(box.link_index, 0);
  EXPECT_EQ(box.size, Eigen::Vector3d(0.3, 0.2, 0.1));  // as written: parsing is exact
  expectPose(shapeInWorld(*scene, b, box),
             X_W_base * origin(Eigen::Vector3d(0.1, 0, 0.05), Eigen::Vector3d(0.4, 0.5, -0.6)));

  const CollisionShape& sphere = b.shapes[1];
  EXPECT_EQ(sphere.kind, Kind::kSphere);
  EXPECT_EQ(sphere.name, "base#1");  // unnamed: the link's second collision
  EXPECT_EQ(sphere.radius, 0.05);
  expectPose(shapeInWorld(*scene, b, sphere), X_W_base);  // no <origin>: the link frame

  const CollisionShape& cylinder = b.shapes[2];
  EXPECT_EQ(cylinder.kind, Kind::kCylinder);
  EXPECT_EQ(cylinder.name, "arm#0");
  ASSERT_EQ(cylinder.link_index, 1);
  EXPECT_EQ(b.links[cylinder.link_index].link, "arm");
  EXPECT_EQ(cylinder.radius, 0.02);
  EXPECT_EQ(cylinder.length, 0.3);
  expectPose(
      shapeInWorld(*scene, b, cylinder),
      X_W_arm * origin(Eigen::Vector3d(0, 0, 0.15), Eigen::Vector3d(1.5707963267948966, 0, 0.25)));

  // The same in B: M_BS = M_BL M_LS, the link's own frame in B composed with the <origin>.
  const Eigen::Isometry3d X_B_arm = b.links[1].M_BL.toIsometry(scene->lambda);
  expectPose(
      cylinder.M_BS.toIsometry(scene->lambda),
      X_B_arm * origin(Eigen::Vector3d(0, 0, 0.15), Eigen::Vector3d(1.5707963267948966, 0, 0.25)));
  EXPECT_EQ(cylinder.line, 21);  // the <collision> element's line in kTwoLinks
  for (const auto& s : b.shapes) {
    EXPECT_FALSE(s.surface.mu) << s.name;  // nothing set: the node's default
    EXPECT_FALSE(s.surface.restitution) << s.name;
  }
}

TEST(CollisionShapes, PosesDoNotDependOnLambda) {
  // λ only scales the motors' translation parts: the world poses agree to round-off.
  SceneOptions o;
  o.lambda = 0.01;
  const auto a = loadUrdfString(kTwoLinks, "two", SceneOptions());
  const auto c = loadUrdfString(kTwoLinks, "two", o);
  ASSERT_TRUE(a.ok() && c.ok());
  for (std::size_t k = 0; k < 3; ++k)
    expectPose(shapeInWorld(*c, c->bodies[0], c->bodies[0].shapes[k]),
               shapeInWorld(*a, a->bodies[0], a->bodies[0].shapes[k]));
}

// A static table (fixed to the world) with a leg merged by a fixed joint, and the world link's
// own collision (ignored, with a warning).
const char* const kTable = R"(<robot name="room">
  <link name="world"><collision><geometry><box size="10 10 0.1"/></geometry></collision></link>
  <joint name="table_fix" type="fixed"><parent link="world"/><child link="table"/>
    <origin xyz="1 2 0.75" rpy="0 0 0.5"/></joint>
  <link name="table">
    <collision><geometry><box size="1.2 0.8 0.04"/></geometry></collision>
  </link>
  <joint name="leg_fix" type="fixed"><parent link="table"/><child link="leg"/>
    <origin xyz="0.55 0.35 -0.37"/></joint>
  <link name="leg">
    <collision><origin rpy="0 0.1 0"/><geometry><cylinder radius="0.03" length="0.7"/></geometry></collision>
  </link>
</robot>)";

TEST(CollisionShapes, StaticBodiesKeepTheirShapesAsObstacles) {
  const auto scene = loadUrdfString(kTable, "room", SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_EQ(scene->bodies.size(), 1u);
  const BodyModel& table = scene->bodies[0];
  EXPECT_TRUE(table.is_static);
  ASSERT_EQ(table.shapes.size(), 2u);
  const Eigen::Isometry3d X_W_table =
      origin(Eigen::Vector3d(1, 2, 0.75), Eigen::Vector3d(0, 0, 0.5));
  expectPose(shapeInWorld(*scene, table, table.shapes[0]), X_W_table);
  expectPose(shapeInWorld(*scene, table, table.shapes[1]),
             X_W_table * origin(Eigen::Vector3d(0.55, 0.35, -0.37), Eigen::Vector3d::Zero()) *
                 origin(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0.1, 0)));
  EXPECT_EQ(table.shapes[1].link_index, 1);
  // The world's own collision belongs to no body: said so.
  ASSERT_EQ(scene->warnings.size(), 1u);
  EXPECT_NE(scene->warnings[0].find("link 'world' is the world frame: its collisions are ignored"),
            std::string::npos)
      << scene->warnings[0];
  const std::string summary = sceneSummary(*scene, "auto");
  EXPECT_NE(summary.find("    collision shapes: 2 (1 box, 1 cylinder)\n"), std::string::npos)
      << summary;
}

// --- contact parameters -------------------------------------------------------------------

// Truth: the decimal numbers written below; the loader parses them with from_chars (correctly
// rounded), as the compiler rounds the same literals, so they compare exactly.
const char* const kSurfaces =
    R"(<robot name="surfaces" xmlns:cga_rigid_sim="urn:cga_rigid_sim:urdf_extension">
  <link name="world"/>
  <joint name="j1" type="floating"><parent link="world"/><child link="gz_equal"/></joint>
  <link name="gz_equal">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><geometry><sphere radius="0.1"/></geometry></collision>
  </link>
  <joint name="j2" type="floating"><parent link="world"/><child link="gz_differ"/></joint>
  <link name="gz_differ">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><geometry><sphere radius="0.1"/></geometry></collision>
  </link>
  <joint name="j3" type="floating"><parent link="world"/><child link="both"/></joint>
  <link name="both">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision name="pad">
      <geometry><box size="0.1 0.1 0.1"/></geometry>
      <cga_rigid_sim:contact mu="0.25" restitution="0.6"/>
    </collision>
    <collision name="rim">
      <geometry><box size="0.1 0.1 0.1"/></geometry>
      <cga_rigid_sim:contact restitution="0.3"/>
    </collision>
  </link>
  <joint name="j4" type="floating"><parent link="world"/><child link="plain"/></joint>
  <link name="plain">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><geometry><sphere radius="0.1"/></geometry></collision>
    <collision><geometry><sphere radius="0.1"/></geometry><cga_rigid_sim:contact/></collision>
  </link>
  <gazebo reference="gz_equal"><mu1>0.7</mu1><mu2>0.7</mu2><material>Gazebo/Red</material></gazebo>
  <gazebo reference="gz_differ"><mu1>0.9</mu1></gazebo>
  <gazebo reference="gz_differ"><mu2>
    0.4
  </mu2></gazebo>
  <gazebo reference="both"><mu1>1.5</mu1><mu2>1.5</mu2></gazebo>
  <gazebo reference="j1"><mu1>0.1</mu1></gazebo>
  <gazebo><static>false</static></gazebo>
</robot>)";

TEST(ContactParameters, FromGazeboFromTheExtensionAndTheExtensionWins) {
  const auto scene = loadUrdfString(kSurfaces, "surfaces", SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_EQ(scene->bodies.size(), 4u);
  const auto surface = [&](int body, int shape) {
    return scene->bodies.at(body).shapes.at(shape).surface;
  };
  // Gazebo, mu1 = mu2: that μ; Gazebo gives no restitution.
  EXPECT_EQ(surface(0, 0).mu, 0.7);
  EXPECT_FALSE(surface(0, 0).restitution);
  // Gazebo, mu1 = 0.9 and mu2 = 0.4 (from two <gazebo> of the link): the smaller, with a warning.
  EXPECT_EQ(surface(1, 0).mu, 0.4);
  // The extension wins over Gazebo's 1.5 where it gives μ; where it gives only e, Gazebo's μ.
  EXPECT_EQ(surface(2, 0).mu, 0.25);
  EXPECT_EQ(surface(2, 0).restitution, 0.6);
  EXPECT_EQ(surface(2, 1).mu, 1.5);
  EXPECT_EQ(surface(2, 1).restitution, 0.3);
  // Nothing given (or an empty element): unset, the node's default.
  for (int k = 0; k < 2; ++k) {
    EXPECT_FALSE(surface(3, k).mu);
    EXPECT_FALSE(surface(3, k).restitution);
  }
  ASSERT_EQ(scene->warnings.size(), 2u);
  EXPECT_NE(scene->warnings[0].find("<gazebo reference='j1'> gives <mu1>/<mu2>, but 'j1' is not "
                                    "a link: ignored"),
            std::string::npos)
      << scene->warnings[0];
  EXPECT_NE(scene->warnings[1].find("link 'gz_differ': <gazebo> mu1 = 0.9 and mu2 = 0.4 differ; "
                                    "the friction cone is isotropic: using the smaller, mu = 0.4"),
            std::string::npos)
      << scene->warnings[1];
}

TEST(ContactParameters, OnlyMu2GivenIsUsedAsItIs) {
  std::string xml = kSurfaces;
  const std::string from = "<mu1>0.9</mu1>";
  xml.replace(xml.find(from), from.size(), "");
  const auto scene = loadUrdfString(xml, "surfaces", SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  EXPECT_EQ(scene->bodies.at(1).shapes.at(0).surface.mu, 0.4);
  EXPECT_EQ(scene->warnings.size(), 1u);  // only the joint reference: nothing differs
}

// --- meshes -------------------------------------------------------------------------------

// Every "v x y z" (OBJ) or "vertex x y z" (ASCII STL) of a file, in file order.
std::vector<Eigen::Vector3d> verticesInFile(const fs::path& file) {
  std::ifstream in(file);
  std::vector<Eigen::Vector3d> out;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string word;
    Eigen::Vector3d x;
    if ((words >> word) && (word == "v" || word == "vertex") && (words >> x.x() >> x.y() >> x.z()))
      out.push_back(x);
  }
  return out;
}

TEST(CollisionShapes, MeshVerticesAreTheFilesScaledAndOpenMeshesAreAccepted) {
  // The corpus' open box (ASCII STL, 10 of a cube's 12 triangles) and its cube with one
  // triangle wound the wrong way (OBJ): neither encloses a volume (no mass from them), both are
  // fine collision surfaces. Scale (2, 3, −0.5) mirrors z: the winding is turned back.
  // Truth: the files' numbers, parsed here, times the scale. The loader does the same single
  // multiplication of the same correctly rounded doubles, so they compare exactly.
  const fs::path dir = fs::temp_directory_path() / "cga_rigid_sim_collision_shapes_test";
  fs::create_directories(dir);
  const fs::path file = dir / "meshes.urdf";
  std::ofstream(file) << "<robot name=\"m\">\n"
                         "  <link name=\"world\"/>\n"
                         "  <joint name=\"fix\" type=\"fixed\"><parent link=\"world\"/>"
                         "<child link=\"bin\"/></joint>\n"
                         "  <link name=\"bin\">\n"
                         "    <collision><geometry><mesh filename=\"file://"
                      << (kMeshes / "open_box.stl").string()
                      << "\" scale=\"2 3 -0.5\"/></geometry></collision>\n"
                         "    <collision><geometry><mesh filename=\"file://"
                      << (kMeshes / "flipped_triangle.obj").string()
                      << "\"/></geometry></collision>\n"
                         "  </link>\n</robot>\n";
  const auto scene = loadUrdfFile(file.string(), SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  const auto& shapes = scene->bodies.at(0).shapes;
  ASSERT_EQ(shapes.size(), 2u);
  const Eigen::Vector3d scale(2, 3, -0.5);
  for (int k = 0; k < 2; ++k) {
    const CollisionShape& s = shapes[k];
    const fs::path source = kMeshes / (k == 0 ? "open_box.stl" : "flipped_triangle.obj");
    SCOPED_TRACE(source.string());
    EXPECT_EQ(s.kind, Kind::kMesh);
    EXPECT_EQ(s.mesh_file, source.string());
    const Eigen::Vector3d sc = k == 0 ? scale : Eigen::Vector3d::Ones();
    std::vector<Eigen::Vector3d> truth;
    for (const auto& x : verticesInFile(source)) truth.push_back(x.cwiseProduct(sc));
    // Every vertex of the shape is a file vertex, and every file vertex is in the shape (the
    // STL's repeated corners are merged into one).
    for (const auto& x : s.mesh.vertices)
      EXPECT_NE(std::find(truth.begin(), truth.end(), x), truth.end()) << x.transpose();
    for (const auto& x : truth)
      EXPECT_NE(std::find(s.mesh.vertices.begin(), s.mesh.vertices.end(), x), s.mesh.vertices.end())
          << x.transpose();
    EXPECT_EQ(s.mesh.vertices.size(), 8u);  // a cube's corners
    EXPECT_EQ(s.mesh.triangles.size(), k == 0 ? 10u : 12u);
  }
  // The STL's triangles in file order: the scaled triangle's normal, with the winding turned
  // back, is a positive multiple of the mapped normal A⁻ᵀ n (A = diag(scale), det A < 0).
  const std::vector<Eigen::Vector3d> file_vertices = verticesInFile(kMeshes / "open_box.stl");
  const Eigen::Vector3d inverse_transpose = scale.cwiseInverse();
  for (std::size_t t = 0; t < shapes[0].mesh.triangles.size(); ++t) {
    const Eigen::Vector3d& a = file_vertices[3 * t];
    const Eigen::Vector3d n_file =
        (file_vertices[3 * t + 1] - a).cross(file_vertices[3 * t + 2] - a);
    const auto& tri = shapes[0].mesh.triangles[t];
    const auto& v = shapes[0].mesh.vertices;
    const Eigen::Vector3d n = (v[tri[1]] - v[tri[0]]).cross(v[tri[2]] - v[tri[0]]);
    EXPECT_GT(n.dot(inverse_transpose.cwiseProduct(n_file)), 0.0) << "triangle " << t;
  }
  fs::remove_all(dir);
}

TEST(CollisionShapes, MeshFileNameTheSystemRefusesIsAnErrorNotACrash) {
  // A name longer than the system allows (NAME_MAX is 255 bytes on Linux): opening it fails with
  // ENAMETOOLONG, and the loader must say so instead of letting a filesystem exception escape
  // (found by fuzz_urdf).
  const std::string name = "/tmp/" + std::string(5000, 'a') + ".stl";
  const std::string urdf =
      "<robot name=\"m\"><link name=\"bin\"><collision><geometry>"
      "<mesh filename=\"file://" +
      name + "\"/></geometry></collision></link></robot>";
  const auto scene = loadUrdfString(urdf, "long_name", SceneOptions());
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().find("cannot open mesh file"), std::string::npos) << scene.error();
  EXPECT_NE(scene.error().find(std::strerror(ENAMETOOLONG)), std::string::npos) << scene.error();
}

TEST(CollisionShapes, SummaryCountsShapesByKind) {
  const auto scene = loadUrdfString(kTwoLinks, "two", SceneOptions());
  ASSERT_TRUE(scene.ok()) << scene.error();
  const std::string text = sceneSummary(*scene, "auto");
  EXPECT_NE(text.find("    links: base, arm (merged by fixed joint weld)\n"
                      "    collision shapes: 3 (1 box, 1 sphere, 1 cylinder)\n"),
            std::string::npos)
      << text;
  const auto bare = loadUrdfFile(std::string(CGA_RIGID_SIM_SOURCE_DIR) + "/urdf/tennis_racket.urdf",
                                 SceneOptions());
  ASSERT_TRUE(bare.ok()) << bare.error();
  // A body without shapes adds no line (the summary of 20 bodies stays on one screen).
  EXPECT_EQ(sceneSummary(*bare, "auto").find("collision shapes"), std::string::npos);
}

}  // namespace collision_shapes_test
}  // namespace scene
}  // namespace cga_rigid_sim
