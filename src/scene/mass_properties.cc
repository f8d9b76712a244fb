#include "cga_rigid_sim/scene/mass_properties.h"

#include <cmath>
#include <limits>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/math/constants.h"

namespace cga_rigid_sim {
namespace scene {

namespace {
using math::kPi;

// The inertia tensor about the centre of mass from the central second moment
// C = ∫ρ (x − c)(x − c)ᵀ dV:  J = tr(C) 1 − C.
Eigen::Matrix3d inertiaFromSecondMoment(const Eigen::Matrix3d& C) {
  return C.trace() * Eigen::Matrix3d::Identity() - C;
}
}  // namespace

MassProperties boxMassProperties(const Eigen::Vector3d& size, double density) {
  MassProperties p;
  p.mass = density * size.x() * size.y() * size.z();
  const Eigen::Vector3d s2 = size.cwiseProduct(size);
  p.J_F.diagonal() << s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y();
  p.J_F *= p.mass / 12.0;
  return p;
}

MassProperties cylinderMassProperties(double radius, double length, double density) {
  MassProperties p;
  p.mass = density * kPi * radius * radius * length;
  const double side = p.mass * (3.0 * radius * radius + length * length) / 12.0;
  p.J_F.diagonal() << side, side, 0.5 * p.mass * radius * radius;
  return p;
}

MassProperties sphereMassProperties(double radius, double density) {
  MassProperties p;
  p.mass = density * 4.0 / 3.0 * kPi * radius * radius * radius;
  p.J_F.diagonal().setConstant(0.4 * p.mass * radius * radius);
  return p;
}

// Derivation (summarised in doc/conventions.md#mass-properties, (E25)). We need V = ∫dV, the
// first moments ∫x dV and the second moments ∫x xᵀ dV of the solid.
// For f homogeneous of degree k, div(f x) = (3 + k) f, so by the divergence theorem
//   ∫_V f dV = 1/(3 + k) ∮ f (x·n) dA.
// On a flat triangle T = (a, b, c) with N = (b − a)×(c − a) (|N| = 2 area, outward), x·n is the
// constant a·N/|N|, and with barycentric coordinates φ (∫ over the unit simplex of
// φ_p φ_q = 1/12 if p = q else 1/24, of φ_p = 1/6, of 1 = 1/2; the Jacobian is |N|):
//   ∫_T 1 dA = |N|/2,   ∫_T x dA = |N| s/6,   ∫_T x xᵀ dA = |N|/24 (a aᵀ + b bᵀ + c cᵀ + s sᵀ),
// with s = a + b + c. Putting the pieces together with v_T = a·N/6 = a·(b×c)/6:
//   V = Σ v_T,   ∫x dV = Σ v_T s/4,   ∫x xᵀ dV = Σ v_T/20 (a aᵀ + b bᵀ + c cᵀ + s sᵀ).
// (These are the moments of the signed tetrahedra (0, a, b, c): the surface integral and the
// tetrahedral decomposition agree, as they must.) The sums cancel heavily when the mesh lies far
// from the origin, so we integrate about o, one of the mesh's vertices, and shift back.
Result<MassProperties> meshMassProperties(const TriangleMesh& mesh, double density,
                                          const std::string& name) {
  const Result<bool> closed = checkClosedMesh(mesh, name);
  if (!closed) return Error{closed.error()};
  if (mesh.triangles.empty()) return Error{"mesh '" + name + "' has no triangles"};
  const Eigen::Vector3d o = mesh.vertices[mesh.triangles.front()[0]];
  double V = 0.0;
  Eigen::Vector3d S1 = Eigen::Vector3d::Zero();
  Eigen::Matrix3d S2 = Eigen::Matrix3d::Zero();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]] - o;
    const Eigen::Vector3d b = mesh.vertices[t[1]] - o;
    const Eigen::Vector3d c = mesh.vertices[t[2]] - o;
    const double v = a.dot(b.cross(c)) / 6.0;
    const Eigen::Vector3d s = a + b + c;
    V += v;
    S1 += (v / 4.0) * s;
    S2 += (v / 20.0) *
          (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  // Scale of the mesh: a volume below round-off of its bounding box is no volume at all.
  Eigen::Vector3d lo = mesh.vertices.front(), hi = lo;
  for (const auto& x : mesh.vertices) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const double extent = (hi - lo).maxCoeff();
  const double kVolumeTol = 1e3 * std::numeric_limits<double>::epsilon() * extent * extent * extent;
  if (V < -kVolumeTol)
    return Error{"mesh '" + name + "' encloses a negative volume (" + formatNumber(V, 10) +
                 " m^3): its triangles are wound clockwise seen from outside (normals point "
                 "inwards); reverse the winding"};
  if (!(V > kVolumeTol))
    return Error{"mesh '" + name + "' encloses no volume (" + formatNumber(V, 10) + " m^3)"};
  const Eigen::Vector3d c_o = S1 / V;
  MassProperties p;
  p.mass = density * V;
  p.com_F = o + c_o;
  const Eigen::Matrix3d C = density * (S2 - V * c_o * c_o.transpose());
  p.J_F = inertiaFromSecondMoment(0.5 * (C + C.transpose()));
  return p;
}

MassProperties transformed(const MassProperties& part, const Eigen::Isometry3d& X_GF) {
  MassProperties p;
  const Eigen::Matrix3d R = X_GF.linear();
  p.mass = part.mass;
  p.com_F = X_GF * part.com_F;
  p.J_F = R * part.J_F * R.transpose();
  return p;
}

MassProperties combine(const std::vector<MassProperties>& parts) {
  MassProperties sum;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const auto& p : parts) {
    sum.mass += p.mass;
    moment += p.mass * p.com_F;
  }
  if (!(sum.mass > 0)) return MassProperties{};
  sum.com_F = moment / sum.mass;
  for (const auto& p : parts) {
    if (p.mass == 0) continue;
    const Eigen::Vector3d d = p.com_F - sum.com_F;
    sum.J_F += p.J_F + p.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  return sum;
}

}  // namespace scene
}  // namespace cga_rigid_sim
