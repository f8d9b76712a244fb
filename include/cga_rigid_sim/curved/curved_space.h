// CurvedSpace: a three-dimensional space of constant curvature in the "1 up" model
// (doc/curved_space.md). A signed radius R selects it: R > 0 the sphere S³ of radius R in the
// algebra Cl(4,0) of e1, e2, e3, e4 = e (e4² = σ = +1); R < 0 the hyperbolic space H³ of radius
// |R|, the sheet of X·X = −R² through −R e4 in Cl(3,1) with e4 = ē (σ = −1). In both, points
// satisfy X·X = σR², the origin is O = −R e4 (the ē-fixed or e-fixed image of the conformal
// origin −½n̄), and the sectional curvature is K = σ/R².
//
// The chart: the stereographic projection from the antipode R e4 of the origin (for R < 0 the
// Poincaré ball of radius 2|R|), scaled to be an isometry at the origin:
//   x = 2R y / (R − y4),       X = (y, y4)  (y the e1, e2, e3 part),
//   y = x / (1 + K|x|²/4),     y4 = −R (1 − K|x|²/4) / (1 + K|x|²/4),
// conformal with the metric ds = |dx| / (1 + K|x|²/4): angles and orientations are kept,
// lengths are shrunk (sphere) or stretched (hyperbolic space) away from the origin. It is the
// inverse of the conformal embedding of Euclidean points with ē (or e) held fixed.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cga_rigid_sim/cga/rotor4.h"
#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace dynamics {

class CurvedSpace {
 public:
  /// Refuses R not finite or 0 (Euclidean space is the "2 up" simulator, not a radius).
  static Result<CurvedSpace> fromRadius(double R);

  double radius() const { return R_; }                     ///< signed R, m
  double rho() const { return std::abs(R_); }              ///< |R|, m
  int sigma() const { return sigma_; }                     ///< e4² = sign R
  double curvature() const { return sigma_ / (R_ * R_); }  ///< K = σ/R², 1/m²
  /// The origin O = −R e4 (the centre of a body at rest at the chart's origin).
  Eigen::Vector4d origin() const { return {0.0, 0.0, 0.0, -R_}; }

  /// The geodesic translation by the vector d of the tangent space at the origin (|d| is the
  /// distance travelled): exp(−½ Σ (d_i/|R|) e_i∧e4). It carries O to the point at distance |d|
  /// along d, and the frame e1, e2, e3 there by parallel transport.
  cga::Rotor4 translator(const Eigen::Vector3d& d) const;

  /// The chart x of a point X of the space (X·X = σR²).
  Eigen::Vector3d toChart(const Eigen::Vector4d& X) const;
  /// The point X of the chart point x; for R < 0, |x| < 2|R| (the Poincaré ball).
  Eigen::Vector4d fromChart(const Eigen::Vector3d& x) const;
  /// The true length of a unit chart length at x: 1 / (1 + K|x|²/4).
  double chartScale(const Eigen::Vector3d& x) const;
  /// The geodesic distance from the origin to the chart point x: 2|R| atan(|x|/(2|R|)) on the
  /// sphere, 2|R| atanh(|x|/(2|R|)) in hyperbolic space.
  double chartDistance(const Eigen::Vector3d& x) const;

  /// The pose ψ = T R0 of a body whose centre is at the chart point x and whose axes are the
  /// rotation q of the chart's axes there (T the geodesic translation from the origin).
  /// Refuses x outside the chart (|x| ≥ 2|R| for R < 0) or non-finite.
  Result<cga::Rotor4> poseFromChart(const Eigen::Vector3d& x, const Eigen::Quaterniond& q) const;
  /// The chart position of the centre ψOψ̃ and the attitude of the body's axes ψ e_i ψ̃ seen in
  /// the chart (the chart is conformal, so its differential is a scale times this rotation).
  void chartPose(const cga::Rotor4& psi, Eigen::Vector3d& x, Eigen::Quaterniond& q) const;

  /// The rotor of a rotation given as a Hamilton quaternion (w, x, y, z), with the dictionary of
  /// doc/conventions.md: ψ = w − x e23 − y e31 − z e12.
  static cga::Rotor4 rotorOfQuaternion(const Eigen::Quaterniond& q);

 private:
  CurvedSpace(double R) : R_(R), sigma_(cga::signatureOfRadius(R)) {}
  double R_;
  int sigma_;
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
