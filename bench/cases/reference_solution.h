// Engine-independent reference ("truth") for the cases in cases.h, and the
// error metrics every benchmark reports against it.
//
// Method
// ------
// Rotation: the state (q, w_body) in R^7 (q = Hamilton quaternion w,x,y,z,
// world-from-body; w = body angular velocity) obeys
//     dq/dt = 1/2 q (x) (0, w),
//     J dw/dt = (J w) x w + R(q)^T tau_world,
// integrated with a fixed-macro-step Gragg-Bulirsch-Stoer scheme (modified
// midpoint + Richardson/Neville extrapolation over n = 2, 4, ..., 16
// substeps: order 16) in long double (64-bit mantissa). R(q) is evaluated
// with the homogeneous formula (divided by |q|^2), so it is an exact rotation
// even if |q| drifts by roundoff; q is normalised only at the end.
// The sequences and the extrapolation act on the increment y_new - y, which
// is added with Kahan summation: without that, roundoff amplified by the
// extrapolation limited thin_rod to ~6e-11 rad. The macro step is
// H = T/ceil(T w_bound / 0.25), w_bound = (|L0| + |tau| T) / J_min >= max|w|,
// i.e. at most 0.25 rad of rotation per macro step (truncation error is far
// below roundoff there: 2x fewer or 2x more steps change nothing above 1e-14).
//
// Translation: forces are uniform (gravity only; the torque is a pure couple),
// so the CoM is exactly ballistic: x = v0 t + g t^2 / 2, v = v0 + g t.
//
// Accuracy (see reference_check, which prints the table; numbers recorded
// in bench/peers/README.md): the orientation at T = 100 s obtained with H
// and with H/2 agree to <= ~1e-14 rad for every case, the double-precision
// run of the same scheme differs from the long double one by the roundoff
// amplification of the problem, and symmetric_top matches its closed-form
// solution to ~1e-15 rad.
//
// Caching: referenceSolution() stores the state at T in
// <cache_dir>/reference_<case>.csv together with the case parameters and a
// method tag; a later call with identical parameters reads it back.
#pragma once

#include <array>
#include <string>

#include "cases.h"

namespace bench {

// Rigid-body state as any engine reports it (double precision).
struct BodyState {
  std::array<double, 4> q;        // orientation, Hamilton (w, x, y, z), world-from-body
  std::array<double, 3> w_world;  // angular velocity, world axes (rad/s)
  std::array<double, 3> x;        // CoM position, world (m)
  std::array<double, 3> v;        // CoM velocity, world (m/s)
};

struct Reference {
  BodyState state;        // at t = T
  double energy = 0;      // kinetic + gravitational potential at T (J)
  double L_norm = 0;      // |L_world| at T (spin angular momentum about the CoM)
  double macro_step = 0;  // H used
  long macro_steps = 0;   // T / H
  // |angle(q_H, q_{H/2})| at T, the convergence estimate (rad); filled by
  // referenceSolution() (computed once, then cached).
  double est_orientation_err = -1;
};

// Reference state at t = c.T. Reads/writes the cache in cache_dir (created if
// missing) unless cache_dir is empty. Verifies convergence (H vs H/2) when it
// has to compute.
Reference referenceSolution(const Case& c, const std::string& cache_dir);

// Raw integration without cache or convergence check, with `macro_steps`
// macro steps over [0, t_end] (<= 0: the default choice above).
// use_long_double = false runs the identical scheme in double (roundoff study).
Reference integrateReference(const Case& c, double t_end, long macro_steps,
                             bool use_long_double = true);

// Default number of macro steps for c over [0, c.T].
long defaultMacroSteps(const Case& c);

// Closed-form torque-free solution for an axisymmetric body (J1 == J2),
// used to validate the integrator. Returns false if c is not such a case.
bool analyticSymmetricTorqueFree(const Case& c, double t, BodyState* out);

// ---- metrics (shared by every benchmark) ----

// Kinetic (translational + rotational) plus gravitational potential energy
// -m g.x (zero at the origin).
double energyOf(const Case& c, const BodyState& s);
// Spin angular momentum about the CoM, world axes: R J R^T w_world.
std::array<double, 3> angularMomentumWorld(const Case& c, const BodyState& s);
// Rotation angle (rad, in [0, pi]) of q_ref^-1 q, computed as
// 2 atan2(|vec|, |scalar|) (stable for small angles). Inputs need not be unit.
double orientationError(const std::array<double, 4>& q,
                        const std::array<double, 4>& q_ref);

struct Errors {
  double orientation_rad;  // orientationError(q, q_ref) at T
  double com_m;            // |x - x_ref| at T
  double energy_rel;       // |E - E_ref| / |E_ref|
  double L_rel;            // | |L| - |L_ref| | / |L_ref|
};
Errors computeErrors(const Case& c, const Reference& ref, const BodyState& s);

}  // namespace bench
