// The 1-up value types (Rotor4, Bivector4, 4-d vectors) written out as full Cl(4,1) reference
// multivectors, so tests compare the 1-up algebra with the reference algebra: e1, e2, e3 are
// the reference's, and e4 is e (σ = +1, square +1: Cl(4,0) is the subalgebra of e1, e2, e3, e)
// or ē (σ = −1, square −1: Cl(3,1)). Nothing here shares code with rotor4.cc.
#pragma once

#include <Eigen/Core>

#include "cga_rigid_sim/cga/bivector4.h"
#include "cga_rigid_sim/cga/multivector.h"
#include "cga_rigid_sim/cga/rotor4.h"

namespace cga_rigid_sim {
namespace testing {

using cga::Multivector;

inline Multivector e4Of(int sigma) { return sigma > 0 ? Multivector::e() : Multivector::ebar(); }
inline Multivector basis4(int a, int sigma) {
  switch (a) {
    case 0:
      return Multivector::e1();
    case 1:
      return Multivector::e2();
    case 2:
      return Multivector::e3();
    default:
      return e4Of(sigma);
  }
}
/// The six basis bivectors in Bivector4's order e23, e31, e12, e14, e24, e34.
inline Multivector blade4(int k, int sigma) {
  static const int kA[6] = {1, 2, 0, 0, 1, 2}, kB[6] = {2, 0, 1, 3, 3, 3};
  return basis4(kA[k], sigma) * basis4(kB[k], sigma);
}
inline Multivector toMV(const cga::Bivector4& B, int sigma) {
  Multivector m;
  for (int k = 0; k < 6; ++k) m += B[k] * blade4(k, sigma);
  return m;
}
inline Multivector toMV(const cga::Rotor4& r, int sigma) {
  Multivector m = Multivector::scalar(r.c[0]);
  for (int k = 0; k < 6; ++k) m += r.c[k + 1] * blade4(k, sigma);
  const Multivector I = basis4(0, sigma) * basis4(1, sigma) * basis4(2, sigma) * basis4(3, sigma);
  return m + r.c[7] * I;
}
inline Multivector vectorMV(const Eigen::Vector4d& v, int sigma) {
  Multivector m;
  for (int a = 0; a < 4; ++a) m += v[a] * basis4(a, sigma);
  return m;
}
/// Reads the bivector coefficients back (the blades are orthogonal: c_k = ⟨M e_k⁻¹⟩).
inline cga::Bivector4 bivectorOf(const Multivector& M, int sigma) {
  cga::Bivector4 B;
  for (int k = 0; k < 6; ++k) {
    const Multivector e = blade4(k, sigma);
    const double sq = (e * e).scalarPart();  // ±1
    B[k] = (M * e).scalarPart() / sq;
  }
  return B;
}
inline Eigen::Vector4d vectorOf(const Multivector& M, int sigma) {
  Eigen::Vector4d v;
  for (int a = 0; a < 4; ++a) {
    const Multivector e = basis4(a, sigma);
    v[a] = cga::inner(M, e).scalarPart() / (e * e).scalarPart();
  }
  return v;
}

}  // namespace testing
}  // namespace cga_rigid_sim
