// The joint frames of MidpointResidual (tree_integrator_residual.h) from its constants: the
// rotation by Rodrigues' formula and the sines and cosines of half joint angles, and the 3×3
// kernels they are used with. Shared by the
// residual passes, the end pose and the explicit stage (tree_integrator_residual.cc,
// tree_residual_pose.cc, tree_residual_dynamics.cc), which inline them into their loops. Internal;
// in an anonymous namespace, so that each of those files keeps them local as before the split.
#pragma once

#include <cmath>

#include "cga_rigid_sim/math/mat3.h"
#include "cga_rigid_sim/math/sin_cos.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

// 3×3 kernels on row-major nine numbers (math/mat3.h).
using math::cross;
using math::dot;
using math::mul;
using math::mulT;

using math::kHalfPi;  // sinCosReduced's range (a joint within ±π)
using math::sinCosReduced;

// R = R0 + sin q R0[u]× + (1 − cos q) R0[u]×² of a joint, from sq = sin q and vq = 1 − cos q.
template <typename Joint>
inline void rodrigues(const Joint& j, double sq, double vq, double* R) {
  for (int i = 0; i < 9; ++i) R[i] = j.A[i];
  for (int l = 0; l < j.term_count; ++l) {
    const auto& t = j.terms[l];
    R[t.index] += sq * t.b + vq * t.c;
  }
}

// sin and cos of a half angle: sinCosReduced within its range (within 1 ulp of std::sin and
// std::cos, at half the cost; math/sin_cos.h), else the library's.
inline void halfSinCos(double half, double& s, double& c) {
  if (std::abs(half) <= kHalfPi) return sinCosReduced(half, s, c);
  s = std::sin(half);
  c = std::cos(half);
}

}  // namespace
}  // namespace dynamics
}  // namespace cga_rigid_sim
