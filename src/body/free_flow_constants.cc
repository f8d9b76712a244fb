// The constants of the exact free flow: the per-body cache of free_flow.h, built from the moments
// and the rotational state by inertia class (doc/conventions.md (E20), (E21); for an asymmetric
// body the amplitudes, modulus, coefficients and phase of (E26)-(E31)).
#include "body/free_flow_constants.h"

#include <cmath>
#include <limits>

#include "body/free_flow_psi.h"
#include "cga_rigid_sim/math/elliptic.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace free_flow {
namespace {

using elliptic::buildAgm;
using elliptic::carlsonRF;

// |L|² (kg² m⁴/s²) below which a spin counts as still. The asymmetric amplitudes square the
// components of L and multiply them by ratios of J-differences (down to about 1e-12 × J_a/J_b,
// kEqualMomentsRelTol), so |L|² has to stay far above the smallest normal double (2.2e-308)
// for none of them to underflow to 0 and turn the amplitudes into 0/0: with 1e-250 they stay
// above 1e-280 for moments within 1e18 of each other. Such a spin (|L| < 1e-125 kg m²/s, i.e.
// |w| < 1e-113 rad/s even for J = 1e-12 kg m²) turns the body by less than 1e-95 rad in the
// age of the universe.
constexpr double kStillMomentumSquared = 1e-250;

// The shortest rotation taking the unit vector u to the unit vector a: (1 + u·a, u × a),
// normalised. Well conditioned while u·a stays away from −1; the callers keep u·a ≥ 0.
inline Eigen::Quaterniond swing(const Eigen::Vector3d& u, const Eigen::Vector3d& a) {
  const Eigen::Vector3d x = u.cross(a);
  Eigen::Quaterniond p(1.0 + u.dot(a), x.x(), x.y(), x.z());
  p.normalize();
  return p;
}

inline Eigen::Vector3d referenceAxis(const FreeFlowCache& c) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  u[c.ic] = c.sigma;
  return u;
}

// Builds the cache of an asymmetric body (J1 < J2 < J3) from its rotor r and body w ≠ 0.
void buildAsymmetric(const Eigen::Vector3d& J, const Eigen::Quaterniond& r,
                     const Eigen::Vector3d& w, FreeFlowCache& c) {
  const Eigen::Vector3d L = J.cwiseProduct(w);
  // A spin about a principal axis is a steady rotation (for e2 an unstable one; it stays exact).
  const int zeros = (L[0] == 0.0) + (L[1] == 0.0) + (L[2] == 0.0);
  if (zeros >= 2) {
    c.path = Path::kUniform;
    c.Q = r;
    c.axis = w.normalized();
    c.rate = w.norm();
    return;
  }
  // D − E J2 (D = |L|², E = 2T), from the components: its sign says which axis the polhode
  // circles (> 0: e3, < 0: e1; 0: the separatrix).
  const double d_minus_ej2 =
      L[2] * L[2] * ((J[2] - J[1]) / J[2]) - L[0] * L[0] * ((J[1] - J[0]) / J[0]);
  c.ic = d_minus_ej2 >= 0.0 ? 2 : 0;
  c.ia = 2 - c.ic;
  c.ib = 1;
  const double Ja = J[c.ia], Jb = J[c.ib], Jc = J[c.ic];
  const double La = L[c.ia], Lb = L[c.ib], Lc = L[c.ic];
  // The ratios of J-differences below are positive for either choice of c (for c = e1 all three
  // differences change sign), and each amplitude is a sum of non-negative terms.
  const double d_minus_eja = Lb * Lb * ((Jb - Ja) / Jb) + Lc * Lc * ((Jc - Ja) / Jc);
  const double La2 = La * La, Lb2 = Lb * Lb, Lc2 = Lc * Lc;
  const double Ba2 = La2 + Lb2 * (Ja * (Jc - Jb)) / (Jb * (Jc - Ja));
  const double Bb2 = Lb2 + La2 * (Jb * (Jc - Ja)) / (Ja * (Jc - Jb));
  const double Bc2 = Lc2 + Lb2 * (Jc * (Jb - Ja)) / (Jb * (Jc - Ja));
  // B_b² − B_a² = k² B_c², formed without cancellation.
  const double G = Jc * (Jb - Ja) * (La2 / (Ja * (Jc - Jb)) + Lb2 / (Jb * (Jc - Ja)));
  c.Ba = std::sqrt(Ba2);
  c.Bb = std::sqrt(Bb2);
  c.Bc = std::sqrt(Bc2);
  c.sigma = Lc < 0.0 ? -1.0 : 1.0;
  c.kp2 = ((Jc - Ja) * d_minus_ej2) / ((Jc - Jb) * d_minus_eja);
  if (c.kp2 < 0.0) c.kp2 = 0.0;  // round-off at the separatrix only
  c.omega_p = std::sqrt(((Jc - Jb) * d_minus_eja) / (Ja * Jb * Jc));
  c.G = G;
  c.ell = L.norm();
  c.inv_ell = 1.0 / c.ell;
  c.inv_J = J.cwiseInverse();
  const double beta = c.ell * (Jc - Ja) / (Ja * Jc * c.omega_p);
  const double gamma = c.Ba * c.Bc * (Jc - Ja) / (Ja * Jc * c.omega_p * c.Bb);
  // The two characteristics n = −G/B_a² and N = k²/n = −B_a²/B_c² (nN = k² ≤ 1): use the
  // smaller in magnitude, so |ν| ≤ k and no coefficient below grows like 1/ω_p times an O(1)
  // function (doc/conventions.md (E28)).
  c.dual = G * Bc2 > Ba2 * Ba2;

  // The phase of the current state: (sn, cn) ∝ (σ L_b/B_b, L_a/B_a); the sign ρ puts cn ≥ 0,
  // i.e. the phase in [−K, K].
  double sn = c.sigma * Lb / c.Bb, cn = La / c.Ba;
  c.rho = cn < 0.0 ? -1.0 : 1.0;
  sn *= c.rho;
  cn *= c.rho;
  const double norm = std::hypot(sn, cn);
  sn /= norm;
  cn /= norm;

  // Q: R(t) = Q Rot(u, ψ) P(t)⁻¹ with ψ = 0 now, so Q = R(0) P(0).
  const Eigen::Vector3d u = referenceAxis(c);
  c.Q = r * swing(u, L / c.ell);
  c.psi = 0.0;

  if (c.kp2 == 0.0) {
    // The separatrix: sn = tanh τ, cn = dn = sech τ; always the dual form.
    c.path = Path::kSeparatrix;
    c.dual = true;
    c.rate = c.ell / Jc + beta * c.omega_p * Ba2 / (c.ell * c.ell);
    c.coef_pi = -beta * c.Ba * c.Bc / (c.ell * c.ell);
    c.coef_atan = gamma;
    c.tau = cn > 0.0 ? std::asinh(sn / cn) : std::copysign(std::numeric_limits<double>::max(), sn);
    c.g_tau = separatrixPsi(c, sn, cn);
    return;
  }
  c.path = Path::kElliptic;
  c.step_ready = false;
  c.run_steps = 0;
  buildAgm(c.kp2, c);
  c.K = kPi / (2.0 * c.agm_limit);
  if (c.dual) {
    c.nchar = -Ba2 / Bc2;
    c.rate = c.ell / Jc;
    c.coef_pi = -beta;
    c.coef_atan = gamma;
  } else {
    c.nchar = -G / Ba2;
    c.rate = c.ell / Ja;
    c.coef_pi = beta;
    c.coef_atan = -gamma;
  }
  c.dpsi_half_ready = false;  // computed by the first step that crosses a half period
  const double dn2 = cn * cn + c.kp2 * sn * sn;
  // τ0 = F(φ0, k) = sn R_F(cn², dn², 1) (Carlson's form of F, valid for |φ0| ≤ π/2).
  c.tau = sn * carlsonRF(cn * cn, dn2, 1.0);
  c.g_tau = periodicPsi(c, sn, cn, std::sqrt(dn2));
}

}  // namespace

void build(const Inertia& inertia, const Eigen::Quaterniond& r, const Eigen::Vector3d& w,
           FreeFlowCache& c) {
  const Eigen::Vector3d& J = inertia.principalMoments();
  c.Q = r;
  c.psi = 0.0;
  // At rest; or not a state at all (non-finite w: left as it is for the caller's validation,
  // rather than fed to iterations that would never converge); or a spin so slow that the
  // squares below underflow (kStillMomentumSquared; e.g. after a couple of 1e-230 N m, or a
  // force of 2e-159 N at 1 m for one step): the amplitudes would be 0/0.
  if (w.isZero(0.0) || !w.allFinite() ||
      !(J.cwiseProduct(w).squaredNorm() >= kStillMomentumSquared)) {
    c.path = Path::kStill;
    return;
  }
  switch (inertia.inertiaClass()) {
    case InertiaClass::kSpherical:
      c.path = Path::kUniform;
      c.axis = w.normalized();
      c.rate = w.norm();
      return;
    case InertiaClass::kSymmetric: {
      const Eigen::Vector3d L = J.cwiseProduct(w);
      c.path = Path::kSymmetric;
      c.axis = L.normalized();
      c.rate = L.norm() / J[0];
      c.beta = w[2] * (1.0 - J[2] / J[0]);
      c.psi3 = 0.0;
      c.w0 = w;
      return;
    }
    case InertiaClass::kAsymmetric:
      buildAsymmetric(J, r, w, c);
      return;
  }
}

}  // namespace free_flow
}  // namespace dynamics
}  // namespace cga_rigid_sim
