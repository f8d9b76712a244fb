// Fuzz target: the mesh readers (scene/mesh.h) that the URDF loader uses for <mesh> collisions
// and <cga_rigid_sim:mass_from_geometry>. The first byte chooses the reader (even: STL, binary
// or ASCII by the size rule; odd: OBJ), the rest is the file's content. A mesh that is read is
// welded, scaled (mirroring included), checked for closure and, when closed, integrated for its
// mass properties — the path a URDF mesh takes.
//
// Checks: no crash or sanitizer report; errors are non-empty and name the file; a mesh read
// has triangle indices inside its vertex list; mass properties computed are finite (for meshes
// within 1e50 m of their origin).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "cga_rigid_sim/scene/mass_properties.h"
#include "cga_rigid_sim/scene/mesh.h"
#include "common/finite_scene.h"

using namespace cga_rigid_sim;

namespace {

void checkIndices(const scene::TriangleMesh& mesh, const std::string& what) {
  const int n = static_cast<int>(mesh.vertices.size());
  for (const auto& t : mesh.triangles)
    for (int i : t)
      if (i < 0 || i >= n)
        fuzz::fail(what + ": triangle index " + std::to_string(i) + " outside [0, " +
                   std::to_string(n) + ")");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool obj = (data[0] & 1) != 0;
  const std::string name = obj ? "fuzz.obj" : "fuzz.stl";
  const std::string bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  const Result<scene::TriangleMesh> mesh =
      obj ? scene::readObj(bytes, name) : scene::readStl(bytes, name);
  if (!mesh.ok()) {
    if (mesh.error().find(name) == std::string::npos)
      fuzz::fail("error does not name the file: " + mesh.error());
    return 0;
  }
  checkIndices(*mesh, "read");
  const scene::TriangleMesh welded = scene::weldVertices(*mesh);
  checkIndices(welded, "welded");
  // A mirroring scale (odd number of negative factors) must keep the winding outward.
  const scene::TriangleMesh scaled = scene::scaledMesh(welded, Eigen::Vector3d(-1.0, 2.0, 0.5));
  checkIndices(scaled, "scaled");
  const Result<bool> closed = scene::checkClosedMesh(scaled, name);
  if (!closed.ok()) return 0;
  const Result<scene::MassProperties> mp = scene::meshMassProperties(scaled, 1000.0, name);
  if (!mp.ok()) return 0;
  // Volume and moments grow with the 3rd and 5th power of the size: beyond 1e50 m they may
  // overflow (the loader's own checks on mass and inertia are the URDF target's business).
  double extent = 0.0;
  for (const Eigen::Vector3d& v : scaled.vertices)
    extent = std::max(extent, v.cwiseAbs().maxCoeff());
  if (extent > 1e50) return 0;
  if (!std::isfinite(mp->mass) || !mp->com_F.allFinite() || !mp->J_F.allFinite())
    fuzz::fail("mass properties of a closed mesh not finite");
  return 0;
}
