#include "cga_rigid_sim/scene/mesh.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/LU>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <system_error>
#include <unordered_map>

#include "cga_rigid_sim/format.h"

namespace cga_rigid_sim {
namespace scene {

namespace {

namespace fs = std::filesystem;

// A finite number in C syntax (locale-independent), the whole token.
bool parseFinite(const std::string& token, double* out) {
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (first != last && *first == '+') ++first;
  const auto r = std::from_chars(first, last, *out);
  return r.ec == std::errc() && r.ptr == last && std::isfinite(*out);
}

std::string lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::uint32_t readU32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

float readF32(const unsigned char* p) {
  const std::uint32_t u = readU32(p);  // IEEE-754 single, little-endian in the file
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

Result<TriangleMesh> readBinaryStl(const std::string& bytes, const std::string& name) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::uint32_t n = readU32(data + 80);
  TriangleMesh mesh;
  mesh.vertices.reserve(3 * static_cast<std::size_t>(n));
  mesh.triangles.reserve(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    const unsigned char* rec = data + 84 + 50 * static_cast<std::size_t>(t);
    for (int k = 0; k < 3; ++k) {
      const unsigned char* v = rec + 12 + 12 * k;  // after the facet normal
      const Eigen::Vector3d x(readF32(v), readF32(v + 4), readF32(v + 8));
      if (!x.allFinite())
        return Error{"mesh '" + name + "': triangle " + std::to_string(t) +
                     " has a non-finite vertex"};
      mesh.vertices.push_back(x);
    }
    const int i = static_cast<int>(3 * t);
    mesh.triangles.push_back({i, i + 1, i + 2});
  }
  return weldVertices(mesh);
}

Result<TriangleMesh> readAsciiStl(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  std::string line;
  TriangleMesh mesh;
  int line_no = 0, in_loop = -1;  // vertices seen in the current "outer loop", -1 outside
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream words(line);
    std::string word;
    if (!(words >> word)) continue;
    word = lowercase(word);
    const std::string where = "mesh '" + name + "' line " + std::to_string(line_no) + ": ";
    if (word == "outer") {
      in_loop = 0;
    } else if (word == "vertex") {
      std::string xs[3];
      Eigen::Vector3d x;
      if (in_loop < 0) return Error{where + "'vertex' outside an 'outer loop'"};
      if (!(words >> xs[0] >> xs[1] >> xs[2]) || !parseFinite(xs[0], &x.x()) ||
          !parseFinite(xs[1], &x.y()) || !parseFinite(xs[2], &x.z()))
        return Error{where + "a vertex needs three finite numbers"};
      mesh.vertices.push_back(x);
      ++in_loop;
    } else if (word == "endloop") {
      if (in_loop != 3)
        return Error{where + "a facet must have exactly 3 vertices (got " +
                     std::to_string(std::max(in_loop, 0)) + ")"};
      const int i = static_cast<int>(mesh.vertices.size()) - 3;
      mesh.triangles.push_back({i, i + 1, i + 2});
      in_loop = -1;
    }
  }
  if (in_loop >= 0) return Error{"mesh '" + name + "': file ends inside a facet"};
  if (mesh.triangles.empty()) return Error{"mesh '" + name + "': no facets found (ASCII STL)"};
  return weldVertices(mesh);
}

// Wavefront OBJ vertex reference of a face: "i", "i/t", "i//n" or "i/t/n"; 1-based, negative
// counts back from the last vertex read so far.
bool parseObjIndex(const std::string& ref, int vertex_count, int* index) {
  const std::string head = ref.substr(0, ref.find('/'));
  int i = 0;
  const auto r = std::from_chars(head.data(), head.data() + head.size(), i);
  if (r.ec != std::errc() || r.ptr != head.data() + head.size() || i == 0) return false;
  *index = i > 0 ? i - 1 : vertex_count + i;
  return *index >= 0 && *index < vertex_count;
}

// A mesh file in one of the formats robot packages ship besides STL and OBJ (Collada .dae above
// all; also .ply, .3ds, .fbx, .gltf/.glb, .off, …) through assimp: its triangles, every node's
// transform applied (points and lines dropped, polygons split into triangles). Collada
// declares its unit and up axis: assimp folds both into the root node as a scale and a turn to
// its own Y-up convention; turning Y back to Z gives the file's coordinates in metres with the
// declared up axis along +Z, the convention of ROS (REP 103), so a Z_UP file keeps its
// coordinates and a Y_UP file is turned by +90° about x. Other formats' coordinates are kept
// as the file stores them.
Result<TriangleMesh> readWithAssimp(const std::string& path, bool collada,
                                    std::vector<std::string>* notes) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    const std::string why = importer.GetErrorString();
    return Error{"cannot read mesh file '" + path + "': assimp " +
                 (why.empty() ? std::string("could not import it") : "says: " + why)};
  }
  const auto toEigen = [](const aiMatrix4x4& m) {
    Eigen::Matrix4d x;
    x << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
        m.d4;
    return x;
  };
  Eigen::Matrix4d Y_to_Z = Eigen::Matrix4d::Identity();  // (x, y, z) ↦ (x, −z, y)
  if (collada) {
    Y_to_Z.block<3, 3>(0, 0) << 1, 0, 0, 0, 0, -1, 0, 1, 0;
    // What the root holds: the unit's scale times the turn from the declared up axis to Y.
    const Eigen::Matrix3d root = toEigen(scene->mRootNode->mTransformation).block<3, 3>(0, 0);
    const double unit = std::cbrt(std::abs(root.determinant()));
    const Eigen::Matrix3d turn = Y_to_Z.block<3, 3>(0, 0) * root / unit;
    if (notes && unit > 0 && !turn.isIdentity(1e-9)) {
      const char* axis =
          (turn * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ()) ? "Y_UP" : "X_UP";
      notes->push_back("mesh '" + path + "' declares <up_axis>" + axis +
                       "</up_axis>: turned so that its up axis is +z (rviz, Gazebo and MoveIt "
                       "draw Collada meshes without this turn: if the mesh looks right there, "
                       "its author meant Z_UP)");
    }
  }
  TriangleMesh mesh;
  // Depth first over the nodes, each with its transform to the file's frame.
  std::vector<std::pair<const aiNode*, Eigen::Matrix4d>> stack{
      {scene->mRootNode, Y_to_Z * toEigen(scene->mRootNode->mTransformation)}};
  while (!stack.empty()) {
    const auto [node, X] = stack.back();
    stack.pop_back();
    for (unsigned c = 0; c < node->mNumChildren; ++c)
      stack.emplace_back(node->mChildren[c], X * toEigen(node->mChildren[c]->mTransformation));
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      const aiMesh* in = scene->mMeshes[node->mMeshes[m]];
      const int first = static_cast<int>(mesh.vertices.size());
      for (unsigned v = 0; v < in->mNumVertices; ++v) {
        const aiVector3D& p = in->mVertices[v];
        const Eigen::Vector3d x = (X * Eigen::Vector4d(p.x, p.y, p.z, 1.0)).head<3>();
        if (!x.allFinite())
          return Error{"mesh '" + path + "': vertex " + std::to_string(v) + " is not finite"};
        mesh.vertices.push_back(x);
      }
      for (unsigned f = 0; f < in->mNumFaces; ++f) {
        const aiFace& face = in->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines have no area
        mesh.triangles.push_back({first + static_cast<int>(face.mIndices[0]),
                                  first + static_cast<int>(face.mIndices[1]),
                                  first + static_cast<int>(face.mIndices[2])});
      }
    }
  }
  return weldVertices(mesh);
}

}  // namespace

TriangleMesh weldVertices(const TriangleMesh& mesh) {
  // Ordered by value, so −0 and +0 are one vertex.
  std::map<std::array<double, 3>, int> index;
  std::vector<int> renumber(mesh.vertices.size());
  TriangleMesh out;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const auto& x = mesh.vertices[i];
    const auto [it, added] =
        index.emplace(std::array<double, 3>{x.x(), x.y(), x.z()}, out.vertices.size());
    if (added) out.vertices.push_back(x);
    renumber[i] = it->second;
  }
  out.triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    out.triangles.push_back({renumber[t[0]], renumber[t[1]], renumber[t[2]]});
  return out;
}

TriangleMesh scaledMesh(const TriangleMesh& mesh, const Eigen::Vector3d& scale) {
  TriangleMesh out = mesh;
  for (auto& x : out.vertices) x = x.cwiseProduct(scale);
  if (scale.prod() < 0)
    for (auto& t : out.triangles) std::swap(t[1], t[2]);
  return out;
}

Result<TriangleMesh> readStl(const std::string& bytes, const std::string& name) {
  if (bytes.size() >= 84) {
    const std::uint32_t n = readU32(reinterpret_cast<const unsigned char*>(bytes.data()) + 80);
    if (bytes.size() == 84 + 50 * static_cast<std::uint64_t>(n)) return readBinaryStl(bytes, name);
  }
  const std::size_t start = bytes.find_first_not_of(" \t\r\n");
  if (start != std::string::npos && lowercase(bytes.substr(start, 5)) == "solid")
    return readAsciiStl(bytes, name);
  return Error{"mesh '" + name +
               "' is neither a binary STL (84 + 50 n bytes) nor an ASCII STL (starting with "
               "'solid')"};
}

Result<TriangleMesh> readObj(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  std::string line;
  TriangleMesh mesh;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream words(line);
    std::string word;
    if (!(words >> word)) continue;
    const std::string where = "mesh '" + name + "' line " + std::to_string(line_no) + ": ";
    if (word == "v") {
      std::string xs[3];
      Eigen::Vector3d x;
      if (!(words >> xs[0] >> xs[1] >> xs[2]) || !parseFinite(xs[0], &x.x()) ||
          !parseFinite(xs[1], &x.y()) || !parseFinite(xs[2], &x.z()))
        return Error{where + "a vertex 'v' needs three finite numbers"};
      mesh.vertices.push_back(x);
    } else if (word == "f") {
      std::vector<int> face;
      std::string ref;
      while (words >> ref) {
        int i = 0;
        if (!parseObjIndex(ref, static_cast<int>(mesh.vertices.size()), &i))
          return Error{where + "face refers to vertex '" + ref + "', which is not defined (" +
                       std::to_string(mesh.vertices.size()) + " vertices so far)"};
        face.push_back(i);
      }
      if (face.size() < 3) return Error{where + "a face needs at least 3 vertices"};
      // A polygon is split into a fan around its first vertex (exact for convex polygons).
      for (std::size_t k = 1; k + 1 < face.size(); ++k)
        mesh.triangles.push_back({face[0], face[k], face[k + 1]});
    }  // other statements (vn, vt, o, g, s, usemtl, mtllib, …) carry no geometry we need
  }
  if (mesh.triangles.empty()) return Error{"mesh '" + name + "': no faces found (OBJ)"};
  return weldVertices(mesh);
}

Result<TriangleMesh> readMeshFile(const std::string& path, std::vector<std::string>* notes) {
  std::ifstream file(path, std::ios::binary);
  const int open_errno = errno;
  // The error_code overload: the throwing one raises when the name cannot be looked up at all
  // (longer than the system allows, or in a directory the process may not search), and a URDF
  // can give any name.
  std::error_code ec;
  const bool is_directory = fs::is_directory(path, ec);
  if (!file || is_directory)
    return Error{"cannot open mesh file '" + path + "': " +
                 (is_directory ? std::string("is a directory") : std::strerror(open_errno))};
  const std::string ext = lowercase(fs::path(path).extension().string());
  if (ext != ".obj" && ext != ".stl") return readWithAssimp(path, ext == ".dae", notes);
  std::ostringstream buffer;
  buffer << file.rdbuf();
  if (ext == ".obj") return readObj(buffer.str(), path);
  return readStl(buffer.str(), path);
}

Result<bool> checkClosedMesh(const TriangleMesh& mesh, const std::string& name) {
  const auto key = [](int u, int v) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(u)) << 32) |
           static_cast<std::uint32_t>(v);
  };
  const int nv = static_cast<int>(mesh.vertices.size());
  std::unordered_map<std::uint64_t, int> directed;
  directed.reserve(3 * mesh.triangles.size());
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const auto& t = mesh.triangles[k];
    for (int i : t)
      if (i < 0 || i >= nv)
        return Error{"mesh '" + name + "': triangle " + std::to_string(k) +
                     " refers to a vertex that does not exist"};
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;  // degenerate: no area
    for (int e = 0; e < 3; ++e) ++directed[key(t[e], t[(e + 1) % 3])];
  }
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const auto& t = mesh.triangles[k];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
    for (int e = 0; e < 3; ++e) {
      const int u = t[e], v = t[(e + 1) % 3];
      const std::string edge = "the edge from " + formatVector(mesh.vertices[u], 9) + " to " +
                               formatVector(mesh.vertices[v], 9) + " (triangle " +
                               std::to_string(k) + ")";
      if (directed[key(u, v)] > 1)
        return Error{"mesh '" + name + "' is not consistently oriented or not manifold: " + edge +
                     " is traversed in the same direction by " +
                     std::to_string(directed[key(u, v)]) +
                     " triangles; every edge must be shared by exactly two triangles wound in "
                     "opposite directions"};
      const auto back = directed.find(key(v, u));
      if (back == directed.end() || back->second == 0)
        return Error{"mesh '" + name + "' is not closed: " + edge +
                     " belongs to only one triangle (or its neighbour is wound the other way); "
                     "mass from geometry needs a closed, consistently oriented surface"};
    }
  }
  return true;
}

Result<std::string> resolveMeshPath(const std::string& uri, const std::string& base_dir) {
  static const std::string kFile = "file://", kPackage = "package://";
  if (uri.empty()) return Error{"empty mesh file name"};
  if (uri.compare(0, kFile.size(), kFile) == 0) return uri.substr(kFile.size());
  if (uri.compare(0, kPackage.size(), kPackage) == 0) {
    const std::string rest = uri.substr(kPackage.size());
    const std::size_t slash = rest.find('/');
    if (slash == std::string::npos || slash == 0)
      return Error{"mesh file name '" + uri + "': expected package://<package>/<path>"};
    const std::string package = rest.substr(0, slash), inside = rest.substr(slash + 1);
    const char* env = std::getenv("ROS_PACKAGE_PATH");
    const std::string paths = env ? env : "";
    std::istringstream dirs(paths);
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
      if (dir.empty()) continue;
      std::error_code ec;
      if (fs::path(dir).filename() == package && fs::exists(fs::path(dir) / inside, ec))
        return (fs::path(dir) / inside).string();
      if (fs::exists(fs::path(dir) / package / inside, ec))
        return (fs::path(dir) / package / inside).string();
      // Packages nested a few levels below a workspace's src/ directory.
      fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec);
      for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (it.depth() >= 3) {
          it.disable_recursion_pending();
          continue;
        }
        if (it->is_directory(ec) && it->path().filename() == package &&
            fs::exists(it->path() / "package.xml", ec) && fs::exists(it->path() / inside, ec))
          return (it->path() / inside).string();
      }
    }
    return Error{"mesh file name '" + uri + "': package '" + package + "' not found in " +
                 (paths.empty() ? std::string("ROS_PACKAGE_PATH, which is not set (source your "
                                              "workspace's setup.bash, or point it at the "
                                              "directory that holds '" +
                                              package + "')")
                                : "ROS_PACKAGE_PATH ('" + paths + "')")};
  }
  const fs::path p(uri);
  if (p.is_absolute() || base_dir.empty()) return p.string();
  return (fs::path(base_dir) / p).string();
}

}  // namespace scene
}  // namespace cga_rigid_sim
