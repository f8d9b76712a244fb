// Step (3) of the URDF loader (urdf_loading.h): each link's collision meshes read and its mass
// properties found in its own frame, from <inertial> (validated, and repaired by default when
// it breaks the triangle inequality or has inertia without mass: doc/urdf.md#inertias-from-cad)
// or from its collision geometry (<cga_rigid_sim:mass_from_geometry>).
#include <Eigen/Eigenvalues>
#include <cmath>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/scene/mass_properties.h"
#include "cga_rigid_sim/scene/mesh.h"
#include "scene/urdf/urdf_loading.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

// One link's <inertial>: mass, centre of mass and inertia in the link frame. URDF gives the
// tensor in the inertial frame I (origin xyz at the centre of mass, axes turned by rpy):
// J_L = R_LI J_I R_LIᵀ.
Result<Loader::LinkMass> Loader::linkMassFromInertial(const urdf::Link& link) {
  const urdf::Inertial& in = *link.inertial;
  const int line = linkLine(link.name);
  const std::string owner = "link " + inQuotes(link.name);
  Eigen::Matrix3d J_I;
  J_I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  if (!std::isfinite(in.mass)) return fail(line, owner + ": mass must be a finite number");
  if (!J_I.allFinite()) return fail(line, owner + ": inertia entries must be finite numbers");
  if (in.mass < 0)
    return fail(line, owner + ": negative mass " + formatNumber(in.mass, kDigits) +
                          " kg (a link's mass must be > 0, or 0 for a massless link)");
  LinkMass out;
  if (in.mass == 0) {
    if (!J_I.isZero(0.0)) {
      const std::string what = owner + ": mass is 0 but the inertia is not";
      if (strict())
        return fail(line, what +
                              "; a massless link must have zero inertia (or give the link its "
                              "mass)" +
                              kRelaxHint);
      // No mass distribution of mass 0 has a moment: the nearest physical inertia is none.
      warnings_.push_back(warnAt(line) + what + " (" + formatNumber(in.ixx, kDigits) + ", " +
                          formatNumber(in.iyy, kDigits) + ", " + formatNumber(in.izz, kDigits) +
                          " kg m^2 on the diagonal): the inertia is dropped, the link is massless" +
                          kRepairedNote);
    }
    return out;  // massless: contributes nothing
  }
  // A link's own inertia must be physical: positive semi-definite (a point mass or a thin rod
  // has zero moments, which merging can fill) and obeying the triangle inequality.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(J_I);
  Eigen::Vector3d m = eig.eigenvalues();  // ascending
  const double scale = m.cwiseAbs().maxCoeff();
  if (m[0] < -dynamics::kTriangleRelSlack * scale)
    return fail(line, owner +
                          ": inertia tensor is not positive semi-definite (principal "
                          "moments " +
                          formatNumber(m[0], kDigits) + ", " + formatNumber(m[1], kDigits) + ", " +
                          formatNumber(m[2], kDigits) +
                          " kg m^2); no mass distribution has a negative moment");
  if (m[2] > (m[0] + m[1]) * (1.0 + dynamics::kTriangleRelSlack)) {
    const std::string broken = owner +
                               ": inertia breaks the triangle inequality I1 + I2 >= I3 "
                               "(principal moments " +
                               formatNumber(m[0], kDigits) + " + " + formatNumber(m[1], kDigits) +
                               " < " + formatNumber(m[2], kDigits) + " kg m^2)";
    if (strict()) return fail(line, broken + kRelaxHint);
    // Nearest physical moments (Euclidean distance): project onto I1 + I2 = I3 along (1, 1, −1).
    const double d = (m[2] - m[0] - m[1]) / 3.0;
    m += Eigen::Vector3d(d, d, -d);
    J_I = eig.eigenvectors() * m.asDiagonal() * eig.eigenvectors().transpose();
    warnings_.push_back(warnAt(line) + broken + ": using the nearest physical moments " +
                        formatNumber(m[0], kDigits) + ", " + formatNumber(m[1], kDigits) + ", " +
                        formatNumber(m[2], kDigits) + " kg m^2 (principal axes kept)" +
                        kRepairedNote);
  }
  MassProperties p;
  p.mass = in.mass;
  p.J_F = J_I;
  out.massive = true;
  out.in_link = transformed(p, toIsometry(in.origin));
  return out;
}

// Every collision mesh of a link: its file name resolved, the file read (once per file) and the
// URDF scale applied, in the shape frame S. Errors end with "[collision '<name>']".
std::optional<Error> Loader::loadCollisionMeshes(
    const std::string& link, std::vector<detail::CollisionGeometry>* collisions) {
  const std::string owner = "link " + inQuotes(link) + ": ";
  for (detail::CollisionGeometry& g : *collisions) {
    if (g.shape.kind != CollisionShape::Kind::kMesh) continue;
    const std::string tag = " [collision " + inQuotes(g.shape.name) + "]";
    const auto path = resolveMeshPath(g.filename, base_dir_);
    if (!path) return fail(g.geometry_line, owner + path.error() + tag);
    auto read = meshes_.find(*path);
    if (read == meshes_.end()) {
      std::vector<std::string> notes;
      auto mesh = readMeshFile(*path, &notes);
      if (!mesh) return fail(g.geometry_line, owner + mesh.error() + tag);
      for (const std::string& n : notes)
        warnings_.push_back(warnAt(g.geometry_line) + owner + n + tag);
      read = meshes_.emplace(*path, std::move(*mesh)).first;
    }
    if (read->second.triangles.empty())
      return fail(g.geometry_line, owner + "mesh " + inQuotes(*path) +
                                       " has no triangles: a collision mesh needs at least one" +
                                       tag);
    g.shape.mesh_file = *path;
    g.shape.mesh = scaledMesh(read->second, g.scale);
  }
  return std::nullopt;
}

// <cga_rigid_sim:mass_from_geometry>: the collision shapes, each in its origin frame, summed
// (they are taken as disjoint), with the given density or scaled to the given mass.
Result<Loader::LinkMass> Loader::linkMassFromGeometry(
    const std::string& link, const detail::MassFromGeometry& spec,
    const std::vector<detail::CollisionGeometry>& collisions) const {
  using Kind = CollisionShape::Kind;
  const std::string owner = "link " + inQuotes(link);
  const double density = spec.by_mass ? 1.0 : spec.density;
  std::vector<MassProperties> parts;
  for (const auto& g : collisions) {
    const CollisionShape& s = g.shape;
    MassProperties p;
    switch (s.kind) {
      case Kind::kBox:
        p = boxMassProperties(s.size, density);
        break;
      case Kind::kCylinder:
        p = cylinderMassProperties(s.radius, s.length, density);
        break;
      case Kind::kSphere:
        p = sphereMassProperties(s.radius, density);
        break;
      case Kind::kMesh: {
        // Only here must a mesh be closed: a volume needs a closed surface.
        auto mp = meshMassProperties(s.mesh, density, s.mesh_file);
        if (!mp)
          return fail(g.geometry_line,
                      owner + ": " + mp.error() + " [collision " + inQuotes(s.name) + "]");
        p = *mp;
        break;
      }
    }
    parts.push_back(transformed(p, g.X_LS));
  }
  LinkMass out;
  out.massive = true;
  out.in_link = combine(parts);
  if (spec.by_mass) {
    const double k = spec.mass / out.in_link.mass;
    out.in_link.mass = spec.mass;
    out.in_link.J_F *= k;
  }
  return out;
}

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
