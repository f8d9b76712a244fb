// Engine-independent truth of the articulated cases (articulated_cases.h): the joint state at T.
//
// Method: the equations of motion M a = -b (articulated_cases.h: forwardDynamics, body
// Jacobians and a recursive Newton-Euler pass, written for this benchmark, no engine code)
// integrated with the classical fourth-order Runge-Kutta method in long double at a fixed step
// (kReferenceStep), every stage in long double. A floating base's orientation is a unit
// quaternion (dq/dt = (0, w_b) q / 2, renormalised after every step), its position p_b. For the
// double pendulum the Lagrange equations written out by hand (articulated_reference.cc) give a
// second, independent right-hand side; bench_articulated_reference prints how far the two and the
// steps h and h/2 disagree at T. Cached per case in <out>/reference_articulated_<case>.csv, keyed
// by every case parameter and the method.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "articulated_cases.h"

namespace bench {
namespace articulated {

constexpr double kReferenceStep = 1e-5;  // s; see bench_articulated_reference for its accuracy

struct ArticulatedReference {
  std::vector<double> q, qd;  // at T
  double E0 = 0;              // energy at t = 0 (articulated_cases.h: energy)
  // Floating base at T (world): orientation (w, x, y, z), origin, angular velocity, velocity.
  std::array<double, 4> base_quat{1, 0, 0, 0};
  std::array<double, 3> base_p{0, 0, 0}, base_w{0, 0, 0}, base_v{0, 0, 0};
};

// Which right-hand side the reference integration uses.
enum class Rhs { kGeneric, kLagrangeDoublePendulum };

struct ReferenceRun {
  std::vector<long double> q, qd;        // at T
  BaseState<long double> base;           // at T (floating base)
  long double max_energy_drift_rel = 0;  // max_t |E(t) - E(0)| / E(0) of the reference itself
  std::vector<double> q_min, q_max;      // range of each joint over [0, T]
  long steps = 0;
};

// RK4 in long double from (q0, qd0) to T with step h (T/h rounded to an integer number of steps).
ReferenceRun integrateReference(const ArticulatedCase& c, double h, Rhs rhs = Rhs::kGeneric);

// The truth at T, from the cache or computed (kReferenceStep, generic right-hand side).
ArticulatedReference articulatedReference(const ArticulatedCase& c, const std::string& out_dir);

// Errors of a state at T against the reference: the largest joint-angle error (wrapped to
// (-pi, pi]) and the largest joint-velocity error; a floating base's orientation error (the
// angle of R_ref^T R, rad) and angular-velocity error (|w - w_ref|, rad/s).
double jointPositionError(const std::vector<double>& q, const ArticulatedReference& ref);
double jointVelocityError(const std::vector<double>& qd, const ArticulatedReference& ref);
double baseOrientationError(const Eigen::Matrix3d& R, const ArticulatedReference& ref);
double baseAngularVelocityError(const Eigen::Vector3d& w, const ArticulatedReference& ref);

}  // namespace articulated
}  // namespace bench
