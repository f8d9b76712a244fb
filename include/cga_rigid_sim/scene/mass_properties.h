// Mass properties of parts and of rigid assemblies: mass, centre of mass and the inertia tensor
// about the centre of mass, all expressed in one frame F.
//
// Used by the URDF loader to merge links joined by fixed joints (parallel-axis theorem) and, for
// the extension element <cga_rigid_sim:mass_from_geometry>, to compute a link's inertia from its
// collision geometry: closed forms for box, cylinder and sphere, and for triangle meshes the
// divergence-theorem surface integrals of doc/conventions.md#mass-properties (E25).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/mesh.h"

namespace cga_rigid_sim {
namespace scene {

/// One part (or a sum of parts) in a frame F.
struct MassProperties {
  double mass = 0.0;                                ///< kg, ≥ 0 (0: massless)
  Eigen::Vector3d com_F = Eigen::Vector3d::Zero();  ///< centre of mass, m, in F
  Eigen::Matrix3d J_F = Eigen::Matrix3d::Zero();    ///< about the centre of mass, F axes, kg m²
};

/// Box of edge lengths `size` centred on the origin of its frame, edges along the axes:
/// J = m/12 diag(y² + z², x² + z², x² + y²).
MassProperties boxMassProperties(const Eigen::Vector3d& size, double density);
/// Solid cylinder of radius r and length l centred on the origin, axis along z (URDF):
/// J = diag(m(3r² + l²)/12, m(3r² + l²)/12, m r²/2).
MassProperties cylinderMassProperties(double radius, double length, double density);
/// Solid sphere of radius r centred on the origin: J = (2/5) m r² 1.
MassProperties sphereMassProperties(double radius, double density);
/// Solid bounded by a closed, consistently oriented triangle mesh (checked; the error names
/// `name`), density ρ, by surface integrals (see mass_properties.cc for the derivation).
/// Refuses an inward-oriented mesh (negative enclosed volume) and a mesh of zero volume.
Result<MassProperties> meshMassProperties(const TriangleMesh& mesh, double density,
                                          const std::string& name);

/// The part seen from frame G, when the part's frame F sits at X_GF (x_G = X_GF x_F):
/// com_G = X_GF com_F, J_G = R J_F Rᵀ.
MassProperties transformed(const MassProperties& part, const Eigen::Isometry3d& X_GF);
/// The assembly of parts given in one frame: total mass, mass-weighted centre of mass and
/// J = Σ [J_i + m_i (|d_i|² 1 − d_i d_iᵀ)], d_i = com_i − com (parallel-axis theorem).
/// Massless parts contribute nothing; an assembly without mass has com = 0 and J = 0.
MassProperties combine(const std::vector<MassProperties>& parts);

}  // namespace scene
}  // namespace cga_rigid_sim
