// Elliptic integrals and Jacobi elliptic functions for the torque-free flow of asymmetric
// bodies (free_flow_constants.cc, free_flow_phase.h; doc/conventions.md (E22)): Carlson's symmetric integrals R_F, R_C and
// R_J, and sn, cn, dn by the arithmetic–geometric mean. Internal to the dynamics layer; inline,
// as they sit on the hot path of every asymmetric step.
#pragma once

#include <algorithm>
#include <boost/math/policies/policy.hpp>
#include <boost/math/special_functions/ellint_rf.hpp>
#include <cmath>
#include <limits>

#include "cga_rigid_sim/body/free_flow.h"
#include "cga_rigid_sim/math/sin_cos.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace elliptic {

// Carlson's R_F from Boost.Math, evaluated in double (Boost would otherwise promote to long
// double) and never throwing (the core does not throw; the arguments passed below are always in
// its domain: at most one of x, y, z zero). Used only when the cache is built.
namespace bmp = boost::math::policies;
using CarlsonPolicy =
    bmp::policy<bmp::promote_double<false>, bmp::domain_error<bmp::ignore_error>,
                bmp::pole_error<bmp::ignore_error>, bmp::overflow_error<bmp::ignore_error>,
                bmp::evaluation_error<bmp::ignore_error>>;
inline double carlsonRF(double x, double y, double z) {
  return boost::math::ellint_rf(x, y, z, CarlsonPolicy());
}

// R_C(1, 1 + e) for e ≥ 0: atan(√e)/√e. Below e = 1e-3 the series 1 − e/3 + e²/5 − … − e⁵/11
// is used instead; its first omitted term e⁶/13 is below ε/10⁴.
inline double carlsonRC1p(double e) {
  if (e < 1e-3) {
    return 1.0 + e * (-1.0 / 3.0 + e * (1.0 / 5.0 + e * (-1.0 / 7.0 + e * (1.0 / 9.0 - e / 11.0))));
  }
  const double s = std::sqrt(e);
  return std::atan(s) / s;
}

// Carlson's R_J(x, y, z, p) for 0 ≤ x, y, z ≤ p, at most one of x, y, z zero (the only case the
// flow needs: p = 1 − n sn² ≥ 1 ≥ cn², dn²). The duplication algorithm of B. C. Carlson,
// "Numerical computation of real or complex elliptic integrals", Numer. Algorithms 10 (1995)
// 13–26, with the seventh-order closing series and the stopping rule of Boost.Math's ellint_rj
// (4^−m Q < A_m, Q = (ε/5)^(−1/8) · spread), which it reproduces to a few ε (checked against
// 50-digit values on the arguments the flow produces: ≤ 9e-16 relative). Written here rather
// than called from Boost because p ≥ max(x, y, z) makes every duplication term e_m ≥ 0, so the
// R_C terms need neither the Cauchy principal value nor the cancellation-prone branches, and
// the small ones (all but the first one or two) are a short series instead of an atan: about
// 1.5× faster, and R_J is the largest cost of a step.
inline double carlsonRJ(double x, double y, double z, double p) {
  static const double kQ = std::pow(std::numeric_limits<double>::epsilon() / 5.0, -1.0 / 8.0);
  const double A0 = (x + y + z + 2.0 * p) / 5.0;
  double delta = (p - x) * (p - y) * (p - z);
  const double Q = kQ * std::max(std::max(std::abs(A0 - x), std::abs(A0 - y)),
                                 std::max(std::abs(A0 - z), std::abs(A0 - p)));
  double xm = x, ym = y, zm = z, pm = p, A = A0, f = 1.0, sum = 0.0;
  for (int m = 0; m < 64; ++m) {
    const double rx = std::sqrt(xm), ry = std::sqrt(ym), rz = std::sqrt(zm), rp = std::sqrt(pm);
    const double d = (rp + rx) * (rp + ry) * (rp + rz);
    sum += f / d * carlsonRC1p(delta / (d * d));
    const double lam = rx * ry + rx * rz + ry * rz;
    A = 0.25 * (A + lam);
    f *= 0.25;
    if (f * Q < A) break;
    xm = 0.25 * (xm + lam);
    ym = 0.25 * (ym + lam);
    zm = 0.25 * (zm + lam);
    pm = 0.25 * (pm + lam);
    delta *= 1.0 / 64.0;
  }
  const double X = f * (A0 - x) / A, Y = f * (A0 - y) / A, Z = f * (A0 - z) / A;
  const double P = -0.5 * (X + Y + Z);
  const double E2 = X * Y + X * Z + Y * Z - 3.0 * P * P;
  const double E3 = X * Y * Z + 2.0 * E2 * P + 4.0 * P * P * P;
  const double E4 = (2.0 * X * Y * Z + E2 * P + 3.0 * P * P * P) * P;
  const double E5 = X * Y * Z * P * P;
  const double series = 1.0 - 3.0 * E2 / 14.0 + E3 / 6.0 + 9.0 * E2 * E2 / 88.0 - 3.0 * E4 / 22.0 -
                        9.0 * E2 * E3 / 52.0 + 3.0 * E5 / 26.0 - E2 * E2 * E2 / 16.0 +
                        3.0 * E3 * E3 / 40.0 + 3.0 * E2 * E4 / 20.0 + 45.0 * E2 * E2 * E3 / 272.0 -
                        9.0 * (E3 * E4 + E2 * E5) / 68.0;
  return f / (A * std::sqrt(A)) * series + 6.0 * sum;
}

// Jacobi's sn, cn, dn of modulus k for |u| ≤ K, by Bulirsch's descending Gauss transformation
// (R. Bulirsch, "Numerical calculation of elliptic integrals and elliptic functions", Numer.
// Math. 7 (1965) 78–90): the arithmetic–geometric mean of (1, k') is cached; one evaluation is
// a single sin/cos of the limit argument followed by a rational backward recurrence on the
// ratio cn/sn, and sn, cn are then formed from that ratio, so sn² + cn² = 1 to round-off. The
// recurrence takes k' (not k), so it keeps full precision as k → 1, where k itself would round
// to 1. Checked against 50-digit values for k' from 0.9 to 1e-14: sn, cn within 3.3e-16
// absolute, dn within 8e-15 relative.
//
// The AGM stops when |a − b| ≤ √ε a: one more step squares the relative gap, so the limit it
// stands for is exact to ε.
inline void buildAgm(double kp2, FreeFlowCache& c) {
  static const double kTol = std::sqrt(std::numeric_limits<double>::epsilon());
  double a = 1.0, b = std::sqrt(kp2);
  c.agm_levels = 0;
  for (;;) {
    c.agm_b[c.agm_levels] = b;
    ++c.agm_levels;
    const double mean = 0.5 * (a + b);
    if (std::abs(a - b) <= kTol * a || c.agm_levels == FreeFlowCache::kMaxAgm) {
      c.agm_limit = mean;
      return;
    }
    b = std::sqrt(a * b);
    a = mean;
  }
}

// The table keeps b_j only (FreeFlowCache): a_j is re-formed by the AGM's own mean, the same
// operations as buildAgm, so each a_j and 1/a_j are bit for bit the values it had. This forward
// pass does not depend on u, so it runs beside the sine and cosine below (a few additions and
// independent divisions, off the recurrence's chain).
inline void jacobiSnCnDn(double u, const FreeFlowCache& c, double& sn, double& cn, double& dn) {
  const int levels = c.agm_levels;
  double a[FreeFlowCache::kMaxAgm], inv_a[FreeFlowCache::kMaxAgm];
  a[0] = 1.0;
  inv_a[0] = 1.0;
  for (int j = 1; j < levels; ++j) {
    a[j] = 0.5 * (a[j - 1] + c.agm_b[j - 1]);
    inv_a[j] = 1.0 / a[j];
  }
  const double v = u * c.agm_limit;  // |v| ≤ K · agm = π/2
  double s, co, d = 1.0;
  math::sinCosReduced(v, s, co);
  if (s != 0.0) {
    double ratio = co / s;  // cot v
    double q = c.agm_limit * ratio;
    for (int j = levels - 1; j >= 0; --j) {
      ratio *= q;
      q *= d;
      d = (c.agm_b[j] + ratio) / (a[j] + ratio);
      ratio = q * inv_a[j];
    }
    const double r = 1.0 / std::sqrt(q * q + 1.0);
    s = s >= 0.0 ? r : -r;
    co = q * s;
  }
  sn = s;
  cn = co;
  dn = d;
}

}  // namespace elliptic
}  // namespace dynamics
}  // namespace cga_rigid_sim
