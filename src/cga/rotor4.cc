#include "cga_rigid_sim/cga/rotor4.h"

#include <algorithm>
#include <complex>

#include "cga_rigid_sim/math/sin_cos.h"

namespace cga_rigid_sim {
namespace cga {
namespace {

// ---- The basis-blade rule of Cl(4,0) / Cl(3,1) ---------------------------------------------
// A blade is a bitmask over e1, e2, e3, e4 (bit 0 .. bit 3) with its factors in increasing
// order; blade(a) blade(b) = sign · blade(a XOR b), sign = (−1)^(swaps to sort the factors)
// times the squares of the shared factors (e4² = σ, the others +1).
constexpr int reorderSign(unsigned a, unsigned b) {
  int swaps = 0;
  for (unsigned x = a >> 1; x != 0; x >>= 1) {
    unsigned y = x & b;
    while (y != 0) {
      swaps += static_cast<int>(y & 1u);
      y >>= 1;
    }
  }
  return (swaps & 1) ? -1 : 1;
}
constexpr int productSign(unsigned a, unsigned b, int sigma) {
  const int s = reorderSign(a, b);
  return ((a & b & 8u) != 0 && sigma < 0) ? -s : s;
}

// The even storage order 1, e23, e31, e12, e14, e24, e34, e1234 as (mask, orientation):
// e31 = −e13 is the only stored blade whose factors are not in increasing order.
constexpr unsigned kMask[8] = {0u, 6u, 5u, 3u, 9u, 10u, 12u, 15u};
constexpr int kOrient[8] = {1, 1, -1, 1, 1, 1, 1, 1};

constexpr int evenIndexOfMask(unsigned m) {
  for (int i = 0; i < 8; ++i)
    if (kMask[i] == m) return i;
  return -1;
}

// The product table of the even subalgebra: stored blade i times stored blade j is
// kSign[σ][i][j] times stored blade kIndex[i][j].
struct EvenTable {
  int index[8][8] = {};
  int sign[2][8][8] = {};  // [0]: σ = +1, [1]: σ = −1
};
constexpr EvenTable makeEvenTable() {
  EvenTable t;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const unsigned m = kMask[i] ^ kMask[j];
      const int k = evenIndexOfMask(m);
      t.index[i][j] = k;
      for (int s = 0; s < 2; ++s)
        t.sign[s][i][j] =
            kOrient[i] * kOrient[j] * kOrient[k] * productSign(kMask[i], kMask[j], s == 0 ? 1 : -1);
    }
  return t;
}
constexpr EvenTable kTable = makeEvenTable();

inline int sigmaSlot(int sigma) { return sigma > 0 ? 0 : 1; }

Rotor4 fromBivector(const Bivector4& B) {
  return Rotor4::fromCoefficients(
      {0.0, B.rot[0], B.rot[1], B.rot[2], B.trans[0], B.trans[1], B.trans[2], 0.0});
}

// The full 16-blade algebra, only for the products with vectors (off the hot path).
using Full = std::array<double, 16>;
Full mulFull(const Full& A, const Full& B, int sigma) {
  Full C{};
  for (unsigned a = 0; a < 16; ++a) {
    if (A[a] == 0.0) continue;
    for (unsigned b = 0; b < 16; ++b) {
      if (B[b] == 0.0) continue;
      C[a ^ b] += productSign(a, b, sigma) * A[a] * B[b];
    }
  }
  return C;
}
Full toFull(const Rotor4& r) {
  Full F{};
  for (int i = 0; i < 8; ++i) F[kMask[i]] = kOrient[i] * r.c[i];
  return F;
}
Full toFull(const Eigen::Vector4d& v) {
  Full F{};
  for (int a = 0; a < 4; ++a) F[1u << a] = v[a];
  return F;
}
Eigen::Vector4d vectorPart(const Full& F) { return {F[1], F[2], F[4], F[8]}; }

// C(z) = cosh √z and S(z) = sinh √z / √z for real z. Below |z| = 1e-2 S is its series through
// z⁴/9!; the first omitted term z⁵/11! is below 2.6e-18 there (ε/80). C needs no series: cosh
// and cos are accurate near 0.
constexpr double kSeriesLimit = 1e-2;
template <class T>
T sSeries(const T& z) {
  return 1.0 + z * (math::kInv3 + z * (math::kInv5 + z * (math::kInv7 + z * math::kInv9)));
}
void coshSinhcReal(double z, double& C, double& S) {
  if (z >= 0) {
    const double w = std::sqrt(z);
    C = std::cosh(w);
    S = std::abs(z) < kSeriesLimit ? sSeries(z) : std::sinh(w) / w;
  } else {
    const double w = std::sqrt(-z);
    C = std::cos(w);
    S = std::abs(z) < kSeriesLimit ? sSeries(z) : std::sin(w) / w;
  }
}
void coshSinhcComplex(std::complex<double> z, std::complex<double>& C, std::complex<double>& S) {
  // C and S are even in √z, so the branch of the square root does not matter.
  const std::complex<double> w = std::sqrt(z);
  C = std::cosh(w);
  S = std::abs(z) < kSeriesLimit ? sSeries(z) : std::sinh(w) / w;
}

// The signed permutations of bladeAction, for both signatures.
struct BladeActions {
  BladeAction action[2][6];
};
constexpr BladeActions makeBladeActions() {
  BladeActions t{};
  for (int s = 0; s < 2; ++s)
    for (int k = 0; k < 6; ++k) {
      BladeAction& a = t.action[s][k];
      const int K = k + 1;  // the blade's even storage index
      // ψ e_k: stored blade i times e_k is sign · stored blade index[i][K].
      for (int i = 0; i < 8; ++i) {
        const int m = kTable.index[i][K];
        a.rightIndex[m] = i;
        a.rightSign[m] = kTable.sign[s][i][K];
      }
      // e_k × e_j = ½(e_k e_j − e_j e_k): nonzero (= e_k e_j) when they anticommute.
      for (int m = 0; m < 6; ++m) {
        a.bracketIndex[m] = m;
        a.bracketSign[m] = 0.0;
      }
      for (int j = 0; j < 6; ++j) {
        const int J = j + 1, m = kTable.index[K][J];
        if (kTable.sign[s][K][J] == -kTable.sign[s][J][K] && m >= 1 && m <= 6) {
          a.bracketIndex[m - 1] = j;
          a.bracketSign[m - 1] = kTable.sign[s][K][J];
        }
      }
    }
  return t;
}
constexpr BladeActions kBladeActions = makeBladeActions();

}  // namespace

const BladeAction& bladeAction(int k, int sigma) {
  return kBladeActions.action[sigmaSlot(sigma)][k];
}

Rotor4 multiply(const Rotor4& a, const Rotor4& b, int sigma) {
  const int s = sigmaSlot(sigma);
  Rotor4 r;
  r.c.fill(0.0);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) r.c[kTable.index[i][j]] += kTable.sign[s][i][j] * a.c[i] * b.c[j];
  return r;
}

Rotor4 reverse(const Rotor4& a) {
  Rotor4 r = a;
  for (int i = 1; i < 7; ++i) r.c[i] = -r.c[i];
  return r;
}

double unitDrift(const Rotor4& a, int sigma) {
  Rotor4 p = multiply(a, reverse(a), sigma);
  p.c[0] -= 1.0;
  double m = 0.0;
  for (double x : p.c) m = std::max(m, std::abs(x));
  return m;
}

Rotor4 normalized(const Rotor4& a, int sigma) {
  const double s = multiply(a, reverse(a), sigma).c[0];
  Rotor4 r = a;
  const double k = 1.0 / std::sqrt(s);
  for (double& x : r.c) x *= k;
  return r;
}

Rotor4 exp(const Bivector4& B, int sigma) {
  const Rotor4 b = fromBivector(B);
  const Rotor4 z = multiply(b, b, sigma);  // α + β I, the bivector part is zero
  const double alpha = z.c[0], beta = z.c[7];
  double c0, c7, s0, s7;  // C = c0 + c7 I, S = s0 + s7 I
  if (sigma > 0) {
    // I² = +1: z = (α + β) P₊ + (α − β) P₋ with the idempotents P± = (1 ± I)/2.
    double Cp, Sp, Cm, Sm;
    coshSinhcReal(alpha + beta, Cp, Sp);
    coshSinhcReal(alpha - beta, Cm, Sm);
    c0 = 0.5 * (Cp + Cm);
    c7 = 0.5 * (Cp - Cm);
    s0 = 0.5 * (Sp + Sm);
    s7 = 0.5 * (Sp - Sm);
  } else {
    // I² = −1: I behaves as the imaginary unit.
    std::complex<double> C, S;
    coshSinhcComplex({alpha, beta}, C, S);
    c0 = C.real();
    c7 = C.imag();
    s0 = S.real();
    s7 = S.imag();
  }
  Rotor4 SB = multiply(Rotor4::fromCoefficients({s0, 0, 0, 0, 0, 0, 0, s7}), b, sigma);
  SB.c[0] += c0;
  SB.c[7] += c7;
  return SB;
}

Rotor4 expBlade(int k, double theta, int sigma) {
  Rotor4 r;
  if (bladeSquare(k, sigma) < 0) {
    r.c[0] = std::cos(theta);
    r.c[k + 1] = std::sin(theta);
  } else {
    r.c[0] = std::cosh(theta);
    r.c[k + 1] = std::sinh(theta);
  }
  return r;
}

Bivector4 commutator(const Bivector4& A, const Bivector4& B, int sigma) {
  const Rotor4 a = fromBivector(A), b = fromBivector(B);
  const Rotor4 ab = multiply(a, b, sigma), ba = multiply(b, a, sigma);
  Bivector4 r;
  for (int k = 0; k < 6; ++k) r[k] = 0.5 * (ab.c[k + 1] - ba.c[k + 1]);
  return r;
}

double scalarProduct(const Bivector4& A, const Bivector4& B, int sigma) {
  return multiply(fromBivector(A), fromBivector(B), sigma).c[0];
}

double wedge4(const Bivector4& A, const Bivector4& B) {
  // The grade-4 part of AB does not depend on the metric (no shared factors).
  return multiply(fromBivector(A), fromBivector(B), 1).c[7];
}

Bivector4 rotate(const Rotor4& psi, const Bivector4& B, int sigma) {
  return multiply(multiply(psi, fromBivector(B), sigma), reverse(psi), sigma).bivector();
}

Bivector4 rotateBack(const Rotor4& psi, const Bivector4& B, int sigma) {
  return multiply(multiply(reverse(psi), fromBivector(B), sigma), psi, sigma).bivector();
}

Eigen::Vector4d rotate(const Rotor4& psi, const Eigen::Vector4d& v, int sigma) {
  return vectorPart(mulFull(mulFull(toFull(psi), toFull(v), sigma), toFull(reverse(psi)), sigma));
}

Eigen::Matrix4d toMatrix(const Rotor4& psi, int sigma) {
  Eigen::Matrix4d M;
  for (int a = 0; a < 4; ++a) M.col(a) = rotate(psi, Eigen::Vector4d::Unit(a), sigma);
  return M;
}

Eigen::Vector4d dot(const Eigen::Vector4d& v, const Bivector4& B, int sigma) {
  const Full V = toFull(v), Bf = toFull(fromBivector(B));
  const Full vb = mulFull(V, Bf, sigma), bv = mulFull(Bf, V, sigma);
  return 0.5 * (vectorPart(vb) - vectorPart(bv));
}

}  // namespace cga
}  // namespace cga_rigid_sim
