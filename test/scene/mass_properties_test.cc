// Mass properties from geometry (the <cga_rigid_sim:mass_from_geometry> extension) against the
// closed forms of a solid box, cylinder and sphere, written out independently below; and the
// surface integrals of a triangle mesh (a box of 12 triangles) against the box's closed form,
// in place, moved and turned, and read from ASCII STL, binary STL and OBJ files.
//
// Tolerance: 1e-12 relative to the largest entry. The closed forms take a handful of roundings;
// the mesh sums add 12 terms of products of three coordinates, each exact to a few ε relative
// to the box's size (the mesh is integrated about one of its vertices, so a far-away placement
// costs no cancellation beyond the final shift). A wrong formula is off by O(1).
#include "cga_rigid_sim/scene/mass_properties.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "cga_rigid_sim/math/constants.h"
#include "cga_rigid_sim/scene/mesh.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

namespace cga_rigid_sim {
namespace scene {
namespace mass_properties_test {

namespace fs = std::filesystem;
using math::kPi;
constexpr double kRelTol = 1e-12;

void expectClose(const MassProperties& got, double mass, const Eigen::Vector3d& com,
                 const Eigen::Matrix3d& J) {
  EXPECT_NEAR(got.mass, mass, kRelTol * mass);
  EXPECT_LT((got.com_F - com).cwiseAbs().maxCoeff(), kRelTol * std::max(1.0, com.norm()))
      << got.com_F.transpose();
  EXPECT_LT((got.J_F - J).cwiseAbs().maxCoeff(), kRelTol * J.cwiseAbs().maxCoeff()) << got.J_F;
}

// Box a × b × c, density ρ: m = ρabc, J = m/12 diag(b² + c², a² + c², a² + b²).
TEST(MassProperties, BoxClosedForm) {
  const MassProperties p = boxMassProperties(Eigen::Vector3d(0.3, 0.2, 0.1), 700.0);
  const double m = 700.0 * 0.3 * 0.2 * 0.1;  // 4.2 kg
  expectClose(
      p, m, Eigen::Vector3d::Zero(),
      Eigen::Vector3d(m * (0.04 + 0.01) / 12, m * (0.09 + 0.01) / 12, m * (0.09 + 0.04) / 12)
          .asDiagonal());
}

// Cylinder radius r, length l (axis z), density ρ: m = ρπr²l,
// Ixx = Iyy = m(3r² + l²)/12, Izz = m r²/2.
TEST(MassProperties, CylinderClosedForm) {
  const MassProperties p = cylinderMassProperties(0.1, 0.4, 1000.0);
  const double m = 1000.0 * kPi * 0.01 * 0.4;
  const double side = m * (0.03 + 0.16) / 12;
  expectClose(p, m, Eigen::Vector3d::Zero(),
              Eigen::Vector3d(side, side, m * 0.01 / 2).asDiagonal());
}

// Sphere radius r, density ρ: m = (4/3)πr³ρ, J = (2/5) m r² on every axis.
TEST(MassProperties, SphereClosedForm) {
  const MassProperties p = sphereMassProperties(0.2, 500.0);
  const double m = 4.0 / 3.0 * kPi * 0.008 * 500.0;
  expectClose(p, m, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity() * (0.4 * m * 0.04));
}

// A box of half-sizes h as 12 outward triangles (counter-clockwise seen from outside).
TriangleMesh boxMesh(const Eigen::Vector3d& h) {
  TriangleMesh mesh;
  for (int k = 0; k < 8; ++k)
    mesh.vertices.emplace_back((k & 1 ? 1 : -1) * h.x(), (k & 2 ? 1 : -1) * h.y(),
                               (k & 4 ? 1 : -1) * h.z());
  // corner index = x + 2y + 4z (bits); two triangles per face.
  mesh.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                    {2, 6, 7}, {2, 7, 3}, {1, 3, 7}, {1, 7, 5}, {0, 4, 6}, {0, 6, 2}};
  return mesh;
}

// Dyadic sizes, exact in float as well (binary STL stores floats).
const Eigen::Vector3d kSize(0.5, 0.25, 0.125);
constexpr double kDensity = 800.0;

MassProperties boxClosedForm() { return boxMassProperties(kSize, kDensity); }

TEST(MassProperties, MeshedBoxBySurfaceIntegralsEqualsClosedForm) {
  const auto p = meshMassProperties(boxMesh(kSize / 2), kDensity, "box");
  ASSERT_TRUE(p.ok()) << p.error();
  const MassProperties c = boxClosedForm();
  expectClose(*p, c.mass, Eigen::Vector3d::Zero(), c.J_F);
}

TEST(MassProperties, MovedAndTurnedMeshedBox) {
  // Moving the mesh moves the centre of mass; turning it turns the tensor: J' = R J Rᵀ.
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())).toRotationMatrix();
  const Eigen::Vector3d t(10.0, -20.0, 30.0);
  TriangleMesh mesh = boxMesh(kSize / 2);
  for (auto& x : mesh.vertices) x = R * x + t;
  const auto p = meshMassProperties(mesh, kDensity, "box");
  ASSERT_TRUE(p.ok()) << p.error();
  const MassProperties c = boxClosedForm();
  expectClose(*p, c.mass, t, R * c.J_F * R.transpose());
}

TEST(MassProperties, MeshErrors) {
  TriangleMesh open = boxMesh(kSize / 2);
  open.triangles.pop_back();
  const auto a = meshMassProperties(open, 1.0, "open");
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().find("mesh 'open' is not closed"), std::string::npos) << a.error();
  TriangleMesh inward = boxMesh(kSize / 2);
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  const auto b = meshMassProperties(inward, 1.0, "inward");
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().find("negative volume"), std::string::npos) << b.error();
  TriangleMesh flipped = boxMesh(kSize / 2);
  std::swap(flipped.triangles[3][1], flipped.triangles[3][2]);
  const auto c = meshMassProperties(flipped, 1.0, "flipped");
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().find("not consistently oriented"), std::string::npos) << c.error();
}

// Parallel-axis theorem by hand: two 1 kg point masses at x = ±1 about their centre have
// Iyy = Izz = 2, Ixx = 0.
TEST(MassProperties, CombineIsTheParallelAxisTheorem) {
  MassProperties a, b;
  a.mass = b.mass = 1.0;
  a.com_F = Eigen::Vector3d(-1, 0, 0);
  b.com_F = Eigen::Vector3d(1, 0, 0);
  expectClose(combine({a, b}), 2.0, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 2, 2).asDiagonal());
  EXPECT_EQ(combine({MassProperties{}}).mass, 0.0);
}

// --- files -----------------------------------------------------------------------------------

fs::path tempDir() {
  const fs::path dir = fs::temp_directory_path() / "cga_rigid_sim_mass_properties_test";
  fs::create_directories(dir);
  return dir;
}

void writeAsciiStl(const fs::path& path, const TriangleMesh& m) {
  std::ofstream out(path);
  out.precision(17);
  out << "solid box\n";
  for (const auto& t : m.triangles) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (int i : t) out << "      vertex " << m.vertices[i].transpose() << "\n";
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid box\n";
}

void writeBinaryStl(const fs::path& path, const TriangleMesh& m) {
  std::ofstream out(path, std::ios::binary);
  const std::string header(80, ' ');
  out.write(header.data(), 80);
  const auto put32 = [&](std::uint32_t u) {
    const unsigned char b[4] = {static_cast<unsigned char>(u), static_cast<unsigned char>(u >> 8),
                                static_cast<unsigned char>(u >> 16),
                                static_cast<unsigned char>(u >> 24)};
    out.write(reinterpret_cast<const char*>(b), 4);
  };
  const auto putFloat = [&](double x) {
    const float f = static_cast<float>(x);
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    put32(u);
  };
  put32(static_cast<std::uint32_t>(m.triangles.size()));
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) putFloat(0.0);  // normal: unused
    for (int i : t)
      for (int k = 0; k < 3; ++k) putFloat(m.vertices[i][k]);
    out.write("\0\0", 2);
  }
}

// OBJ with one quad per face (the reader splits polygons into fans) and mixed index forms.
void writeObj(const fs::path& path, const TriangleMesh& m) {
  std::ofstream out(path);
  out.precision(17);
  out << "# box\no box\n";
  for (const auto& v : m.vertices) out << "v " << v.transpose() << "\n";
  out << "vn 0 0 1\nvt 0 0\n";
  for (std::size_t k = 0; k < m.triangles.size(); k += 2) {
    const auto& a = m.triangles[k];
    const auto& b = m.triangles[k + 1];  // (a0, a2, b2) continue the quad a0 a1 a2 b2
    out << "f " << a[0] + 1 << "/1/1 " << a[1] + 1 << "//1 " << a[2] + 1 << " "
        << static_cast<int>(b[2]) - static_cast<int>(m.vertices.size()) << "\n";
  }
}

TEST(MassProperties, MeshFilesAsciiStlBinaryStlObj) {
  const fs::path dir = tempDir();
  const TriangleMesh mesh = boxMesh(kSize / 2);
  writeAsciiStl(dir / "box_ascii.stl", mesh);
  writeBinaryStl(dir / "box_binary.stl", mesh);
  writeObj(dir / "box.obj", mesh);
  const MassProperties c = boxClosedForm();
  for (const char* name : {"box_ascii.stl", "box_binary.stl", "box.obj"}) {
    SCOPED_TRACE(name);
    const auto read = readMeshFile((dir / name).string());
    ASSERT_TRUE(read.ok()) << read.error();
    EXPECT_EQ(read->vertices.size(), 8u);  // corners merged
    EXPECT_EQ(read->triangles.size(), 12u);
    const auto p = meshMassProperties(*read, kDensity, name);
    ASSERT_TRUE(p.ok()) << p.error();
    expectClose(*p, c.mass, Eigen::Vector3d::Zero(), c.J_F);
  }
  const auto bad = readMeshFile((dir / "missing.stl").string());
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("cannot open mesh file"), std::string::npos);
  // A name the system refuses (longer than NAME_MAX): an error naming the reason, no exception.
  const auto too_long = readMeshFile((dir / (std::string(300, 'a') + ".stl")).string());
  ASSERT_FALSE(too_long.ok());
  EXPECT_NE(too_long.error().find(std::strerror(ENAMETOOLONG)), std::string::npos)
      << too_long.error();
  // Other formats go to assimp, which refuses a file it cannot read, with its reason.
  std::ofstream(dir / "box.ply") << "ply\n";
  const auto ply = readMeshFile((dir / "box.ply").string());
  ASSERT_FALSE(ply.ok());
  EXPECT_NE(ply.error().find("cannot read mesh file"), std::string::npos) << ply.error();
  EXPECT_NE(ply.error().find("box.ply': assimp"), std::string::npos) << ply.error();
}

// --- through the loader: the extension element -------------------------------------------

Result<Scene> loadWithExtension(const std::string& link_body, const fs::path& file) {
  {
    std::ofstream out(file);
    out << "<robot name=\"ext\" xmlns:cga_rigid_sim=\"https://example.invalid/cga_rigid_sim\">\n"
           "  <link name=\"world\"/>\n"
           "  <joint name=\"j\" type=\"floating\"><parent link=\"world\"/>"
           "<child link=\"part\"/></joint>\n"
           "  <link name=\"part\">\n"
        << link_body << "\n  </link>\n</robot>\n";
  }
  return loadUrdfFile(file.string(), SceneOptions());
}

// The body's composite in its root link frame (see composite_inertia_test.cc).
MassProperties bodyInLinkFrame(const Scene& scene) {
  const BodyModel& b = scene.bodies.at(0);
  const cga::Motor M_RB = b.links.at(0).M_BL.reverse();
  const Eigen::Matrix3d R = M_RB.rotation().toRotationMatrix();
  MassProperties p;
  p.mass = b.inertia->mass();
  p.com_F = M_RB.translation(scene.lambda);
  p.J_F = R * b.inertia->principalMoments().asDiagonal() * R.transpose();
  return p;
}

TEST(MassFromGeometry, PrimitivesThroughTheLoader) {
  const fs::path file = tempDir() / "primitive.urdf";
  struct Case {
    const char* geometry;
    MassProperties expected;
  };
  const Case cases[] = {
      {"<box size=\"0.3 0.2 0.1\"/>", boxMassProperties(Eigen::Vector3d(0.3, 0.2, 0.1), 700)},
      {"<cylinder radius=\"0.1\" length=\"0.4\"/>", cylinderMassProperties(0.1, 0.4, 700)},
      {"<sphere radius=\"0.2\"/>", sphereMassProperties(0.2, 700)},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.geometry);
    const auto scene = loadWithExtension(
        std::string("<cga_rigid_sim:mass_from_geometry density=\"700\"/>\n<collision>"
                    "<geometry>") +
            c.geometry + "</geometry></collision>",
        file);
    ASSERT_TRUE(scene.ok()) << scene.error();
    expectClose(bodyInLinkFrame(*scene), c.expected.mass, Eigen::Vector3d::Zero(), c.expected.J_F);
  }
}

TEST(MassFromGeometry, CollisionOriginAndMassAttribute) {
  // A cylinder turned onto the x axis (pitch π/2) and moved to (0.1, 0.2, 0.3), scaled to a
  // mass of 3 kg: J = 3 diag(r²/2, (3r² + l²)/12, (3r² + l²)/12), com at the origin offset.
  const fs::path file = tempDir() / "origin.urdf";
  const auto scene = loadWithExtension(
      "<cga_rigid_sim:mass_from_geometry mass=\"3\"/>\n<collision>"
      "<origin xyz=\"0.1 0.2 0.3\" rpy=\"0 1.5707963267948966 0\"/>"
      "<geometry><cylinder radius=\"0.1\" length=\"0.4\"/></geometry></collision>",
      file);
  ASSERT_TRUE(scene.ok()) << scene.error();
  const double side = 3.0 * (0.03 + 0.16) / 12;
  expectClose(bodyInLinkFrame(*scene), 3.0, Eigen::Vector3d(0.1, 0.2, 0.3),
              Eigen::Vector3d(3.0 * 0.01 / 2, side, side).asDiagonal());
}

TEST(MassFromGeometry, MeshWithScaleAndMirror) {
  // The mesh is a box of kSize; scale (2, 1, −1) doubles x and mirrors z (the loader restores
  // the winding), which is the box 2a × b × c.
  const fs::path dir = tempDir();
  writeBinaryStl(dir / "unit_box.stl", boxMesh(kSize / 2));
  const auto scene = loadWithExtension(
      "<cga_rigid_sim:mass_from_geometry density=\"800\"/>\n<collision><geometry>"
      "<mesh filename=\"unit_box.stl\" scale=\"2 1 -1\"/></geometry></collision>",
      dir / "mesh.urdf");  // the mesh path is relative to the URDF file's directory
  ASSERT_TRUE(scene.ok()) << scene.error();
  const MassProperties c =
      boxMassProperties(Eigen::Vector3d(2 * kSize.x(), kSize.y(), kSize.z()), kDensity);
  expectClose(bodyInLinkFrame(*scene), c.mass, Eigen::Vector3d::Zero(), c.J_F);
}

TEST(MassFromGeometry, SeveralCollisionsAreSummed) {
  // Two 0.1 m cubes of density 1000 (1 kg each) centred at x = ±0.5: the parallel-axis terms
  // add 2·1·0.5² = 0.5 to Iyy and Izz; each cube has J = (1/12)(0.01 + 0.01) = 1/600.
  const fs::path file = tempDir() / "two_boxes.urdf";
  const auto scene = loadWithExtension(
      "<cga_rigid_sim:mass_from_geometry density=\"1000\"/>\n"
      "<collision><origin xyz=\"-0.5 0 0\"/><geometry><box size=\"0.1 0.1 0.1\"/></geometry>"
      "</collision>\n"
      "<collision><origin xyz=\"0.5 0 0\"/><geometry><box size=\"0.1 0.1 0.1\"/></geometry>"
      "</collision>",
      file);
  ASSERT_TRUE(scene.ok()) << scene.error();
  const double cube = 1.0 / 600.0;
  expectClose(bodyInLinkFrame(*scene), 2.0, Eigen::Vector3d::Zero(),
              Eigen::Vector3d(2 * cube, 2 * cube + 0.5, 2 * cube + 0.5).asDiagonal());
}

}  // namespace mass_properties_test
}  // namespace scene
}  // namespace cga_rigid_sim
