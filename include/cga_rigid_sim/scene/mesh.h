// Triangle meshes for collision shapes and mass properties from geometry: small readers for STL
// (ASCII and binary) and Wavefront OBJ, assimp for the other formats, and the check that a mesh
// encloses a volume (closed, consistently oriented), which the surface integrals of
// mass_properties.h need.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace scene {

/// Vertices (metres, in the mesh's own frame) and triangles as vertex indices, counter-clockwise
/// seen from outside (the right-hand rule gives the outward normal).
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// Reads an STL (binary or ASCII, told apart by the binary size rule 84 + 50 n bytes) or an OBJ
/// (by extension .obj, case-insensitive) file with the readers below, and every other format
/// (Collada .dae, PLY, glTF, …) through assimp: the triangles with each node's transform, a
/// Collada file in metres (its <unit meter>) with its <up_axis> turned to +z. Vertices with
/// identical coordinates are merged (STL stores each triangle's corners separately). Polygons
/// are split into triangles. Errors name the file and the line or triangle, or assimp's reason.
/// `notes` (may be null) gets what the reading changed that the user should know (a Collada
/// up axis other than Z_UP).
Result<TriangleMesh> readMeshFile(const std::string& path,
                                  std::vector<std::string>* notes = nullptr);
/// The same from memory; `name` is used in messages.
Result<TriangleMesh> readStl(const std::string& bytes, const std::string& name);
Result<TriangleMesh> readObj(const std::string& text, const std::string& name);

/// The mesh with every vertex scaled per axis (URDF <mesh scale>): x ↦ scale ∘ x. A mirroring
/// scale (negative product) turns the winding inside out, so each triangle's winding is swapped
/// back: the right-hand rule still gives the outward normal.
TriangleMesh scaledMesh(const TriangleMesh& mesh, const Eigen::Vector3d& scale);

/// Merges vertices with bit-identical coordinates and renumbers the triangles.
TriangleMesh weldVertices(const TriangleMesh& mesh);

/// Refuses a mesh that does not bound a volume: every edge must be shared by exactly two
/// triangles that traverse it in opposite directions (closed, manifold, consistently oriented).
/// Triangles with a repeated vertex index are degenerate and ignored. `name` is used in messages.
Result<bool> checkClosedMesh(const TriangleMesh& mesh, const std::string& name);

/// Resolves a URDF mesh file name to a path: `file://` is stripped; `package://pkg/rest` is looked
/// up in the directories of ROS_PACKAGE_PATH (dir/pkg/rest or dir/rest when dir is named pkg);
/// a relative path is taken relative to `base_dir` (the URDF file's directory; the current
/// directory when empty).
Result<std::string> resolveMeshPath(const std::string& uri, const std::string& base_dir);

}  // namespace scene
}  // namespace cga_rigid_sim
