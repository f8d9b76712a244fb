// Robots like the published ones, written here so that the tests own them: links that overlap
// at the zero pose two joints apart (as an industrial arm's forearm and palm do), a floating
// humanoid-like tree whose links are meshes, a gripper whose fingers close on each other. The
// meshes are written at test time (ASCII STL) into a temporary folder: boxes with chamfered
// edges, 24 vertices each, so that contacts meet real mesh hulls rather than primitives.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace cga_rigid_sim {
namespace test {

inline std::string num(double x) {
  std::ostringstream os;
  os << std::setprecision(17) << x;
  return os.str();
}

// A solid box's inertia tag (mass m, sizes s).
inline std::string boxInertial(double m, const Eigen::Vector3d& s,
                               const Eigen::Vector3d& at = Eigen::Vector3d::Zero()) {
  const double ixx = m * (s.y() * s.y() + s.z() * s.z()) / 12,
               iyy = m * (s.x() * s.x() + s.z() * s.z()) / 12,
               izz = m * (s.x() * s.x() + s.y() * s.y()) / 12;
  return "<inertial><origin xyz='" + num(at.x()) + " " + num(at.y()) + " " + num(at.z()) +
         "'/><mass value='" + num(m) + "'/><inertia ixx='" + num(ixx) + "' iyy='" + num(iyy) +
         "' izz='" + num(izz) + "' ixy='0' ixz='0' iyz='0'/></inertial>";
}

inline std::string boxCollision(const Eigen::Vector3d& s,
                                const Eigen::Vector3d& at = Eigen::Vector3d::Zero()) {
  return "<collision><origin xyz='" + num(at.x()) + " " + num(at.y()) + " " + num(at.z()) +
         "'/><geometry><box size='" + num(s.x()) + " " + num(s.y()) + " " + num(s.z()) +
         "'/></geometry></collision>";
}

/// Writes an ASCII STL of a box of sizes s centred at c whose 12 edges are chamfered by b (a
/// convex polyhedron of 24 vertices: 6 faces, 12 edge bevels, 8 corner triangles) and returns
/// its path.
inline std::string writeChamferedBox(const std::string& dir, const std::string& name,
                                     const Eigen::Vector3d& s, const Eigen::Vector3d& c, double b) {
  std::vector<Eigen::Vector3d> v;  // the 24 vertices: per corner, one moved in from each face
  const Eigen::Vector3d h = 0.5 * s;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d sign(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1);
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Vector3d p = sign.cwiseProduct(h);
      for (int other = 0; other < 3; ++other)
        if (other != axis) p[other] -= sign[other] * b;
      v.push_back(c + p);
    }
  }
  // The hull of those points is the chamfered box; its facets, outward.
  std::vector<std::array<int, 3>> tris;
  const int n = static_cast<int>(v.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        const Eigen::Vector3d nrm = (v[j] - v[i]).cross(v[k] - v[i]);
        if (nrm.norm() < 1e-12) continue;
        int above = 0, below = 0;
        for (int q = 0; q < n; ++q) {
          const double d = nrm.dot(v[q] - v[i]);
          if (d > 1e-12) ++above;
          if (d < -1e-12) ++below;
        }
        if (above && below) continue;
        tris.push_back(above ? std::array<int, 3>{i, k, j} : std::array<int, 3>{i, j, k});
      }
  const std::string path = dir + "/" + name + ".stl";
  std::ofstream out(path);
  out << std::setprecision(17) << "solid " << name << "\n";
  for (const auto& t : tris) {
    const Eigen::Vector3d nrm = (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).normalized();
    out << "facet normal " << nrm.x() << " " << nrm.y() << " " << nrm.z() << "\nouter loop\n";
    for (int q : t) out << "vertex " << v[q].x() << " " << v[q].y() << " " << v[q].z() << "\n";
    out << "endloop\nendfacet\n";
  }
  out << "endsolid " << name << "\n";
  return path;
}

/// A fresh temporary folder for one test's meshes.
inline std::string meshFolder(const std::string& tag) {
  const auto dir = std::filesystem::temp_directory_path() / ("cga_rigid_sim_" + tag);
  std::filesystem::create_directories(dir);
  return dir.string();
}

/// A fixed-base arm of four revolute joints about y and x in turn, with limits ±limit, whose
/// links are boxes 0.3 m long; the third link (two joints below the first) is folded back so
/// that it overlaps the first by `overlap` m at the zero pose, as the forearm and palm of a
/// published industrial arm do. No damping: the arm swings and its links meet.
inline std::string overlappingArmUrdf(double overlap = 0.01, double limit = 2.0) {
  std::string u =
      "<robot name='arm' xmlns:cga_rigid_sim='urn:cga_rigid_sim:urdf_extension'>"
      "<link name='world'/><link name='base'>" +
      boxCollision({0.2, 0.2, 0.1}) +
      "</link><joint name='base_fixed' type='fixed'><parent link='world'/><child link='base'/>"
      "<origin xyz='0 0 1.0'/></joint>";
  const Eigen::Vector3d s(0.08, 0.08, 0.3);
  const char* names[] = {"upper", "fore", "palm", "tip"};
  const char* axes[] = {"0 1 0", "1 0 0", "0 1 0", "1 0 0"};
  for (int k = 0; k < 4; ++k) {
    // Link k hangs below its joint by 0.15 m (its centre); the palm's joint sits 0.1 m up the
    // forearm and the palm reaches back up beside the upper arm.
    const double zc = k == 2 ? 0.15 : -0.15;
    u += std::string("<link name='") + names[k] + "'>" + boxInertial(1.0, s, {0, 0, zc}) +
         boxCollision(s, {0, 0, zc}) + "</link>";
    const std::string parent = k == 0 ? "base" : names[k - 1];
    double z = k == 0 ? -0.06 : -0.32;
    double x = 0.0;
    if (k == 2) z = -0.12, x = 0.08 - overlap;  // beside the forearm's side, folded up
    u += std::string("<joint name='j") + std::to_string(k + 1) +
         "' type='revolute'><parent link='" + parent + "'/><child link='" + names[k] +
         "'/><origin xyz='" + num(x) + " 0 " + num(z) + "'/><axis xyz='" + axes[k] +
         "'/><limit lower='" + num(-limit) + "' upper='" + num(limit) +
         "' effort='100' velocity='10'/></joint>";
  }
  return u + "</robot>";
}

/// A floating humanoid-like tree of ten mesh links (chamfered boxes written into `dir`): pelvis,
/// torso, two arms of two links, two legs of thigh and shin, on revolute joints with limits of
/// ±limit rad and the given damping, sized like a 1.2 m robot of ~35 kg. Its arms hang beside its
/// torso 5 mm away and its thighs 1 cm apart, each turning about y (sideways, towards the body:
/// a positive rate swings the left limbs in, a negative one the right), the forearms and shins
/// about x: swinging limbs meet the torso and each other.
inline std::string humanoidUrdf(const std::string& dir, double limit = 2.5, double damping = 0.0) {
  struct Part {
    const char* name;
    const char* parent;
    Eigen::Vector3d joint;  // in the parent's frame
    const char* axis;
    Eigen::Vector3d size, centre;  // of the mesh box, in the link's frame
    double mass;
  };
  const double arm_x = 0.125 + 0.03 + 0.005;  // torso half width, arm half width, gap
  const Part parts[] = {
      {"torso", "pelvis", {0, 0, 0.08}, "0 1 0", {0.25, 0.15, 0.35}, {0, 0, 0.175}, 12.0},
      {"l_upper_arm", "torso", {arm_x, 0, 0.33}, "0 1 0", {0.06, 0.06, 0.25}, {0, 0, -0.125}, 2.0},
      {"l_fore_arm", "l_upper_arm", {0, 0, -0.26}, "1 0 0", {0.05, 0.05, 0.22}, {0, 0, -0.11}, 1.5},
      {"r_upper_arm", "torso", {-arm_x, 0, 0.33}, "0 1 0", {0.06, 0.06, 0.25}, {0, 0, -0.125}, 2.0},
      {"r_fore_arm", "r_upper_arm", {0, 0, -0.26}, "1 0 0", {0.05, 0.05, 0.22}, {0, 0, -0.11}, 1.5},
      {"l_thigh", "pelvis", {0.045, 0, -0.08}, "0 1 0", {0.08, 0.08, 0.3}, {0, 0, -0.15}, 4.0},
      {"l_shin", "l_thigh", {0, 0, -0.31}, "1 0 0", {0.07, 0.07, 0.3}, {0, 0, -0.15}, 3.0},
      {"r_thigh", "pelvis", {-0.045, 0, -0.08}, "0 1 0", {0.08, 0.08, 0.3}, {0, 0, -0.15}, 4.0},
      {"r_shin", "r_thigh", {0, 0, -0.31}, "1 0 0", {0.07, 0.07, 0.3}, {0, 0, -0.15}, 3.0},
  };
  const auto mesh = [&](const std::string& name, const Eigen::Vector3d& size,
                        const Eigen::Vector3d& centre) {
    const std::string path = writeChamferedBox(dir, name, size, centre, 0.01);
    return "<collision><geometry><mesh filename='file://" + path + "'/></geometry></collision>";
  };
  std::string u = "<robot name='humanoid'>";
  u += "<link name='pelvis'>" + boxInertial(6.0, {0.25, 0.15, 0.12}) +
       mesh("pelvis", {0.25, 0.15, 0.12}, Eigen::Vector3d::Zero()) + "</link>";
  for (const Part& p : parts) {
    u += std::string("<link name='") + p.name + "'>" + boxInertial(p.mass, p.size, p.centre) +
         mesh(p.name, p.size, p.centre) + "</link>";
    u += std::string("<joint name='") + p.name + "_joint' type='revolute'><parent link='" +
         p.parent + "'/><child link='" + p.name + "'/><origin xyz='" + num(p.joint.x()) + " " +
         num(p.joint.y()) + " " + num(p.joint.z()) + "'/><axis xyz='" + p.axis +
         "'/><limit lower='" + num(-limit) + "' upper='" + num(limit) +
         "' effort='200' velocity='20'/><dynamics damping='" + num(damping) + "'/></joint>";
  }
  return u + "</robot>";
}

/// A gripper: a palm fixed 0.5 m above the world's origin with two box fingers on prismatic
/// joints along x, each from its open position (q = 0, the fingers 6 cm apart) up to 4 cm
/// closed, so that closed they would overlap: fingers meet each other before their limits.
inline std::string gripperUrdf() {
  std::string u = "<robot name='gripper'><link name='world'/><link name='palm'>" +
                  boxCollision({0.2, 0.06, 0.04}) +
                  "</link><joint name='palm_fixed' type='fixed'><parent link='world'/>"
                  "<child link='palm'/><origin xyz='0 0 0.5'/></joint>";
  for (int side = 0; side < 2; ++side) {
    const std::string name = side ? "right_finger" : "left_finger";
    const double x = side ? 0.04 : -0.04;  // finger centres; 2 cm thick: 6 cm apart inside
    u += "<link name='" + name + "'>" + boxInertial(0.1, {0.02, 0.04, 0.08}, {0, 0, -0.06}) +
         boxCollision({0.02, 0.04, 0.08}, {0, 0, -0.06}) + "</link>";
    u += "<joint name='" + name + "_joint' type='prismatic'><parent link='palm'/><child link='" +
         name + "'/><origin xyz='" + num(x) + " 0 0'/><axis xyz='" + (side ? "-1" : "1") +
         " 0 0'/><limit lower='0' upper='0.04' effort='20' velocity='1'/></joint>";
  }
  return u + "</robot>";
}

}  // namespace test
}  // namespace cga_rigid_sim
