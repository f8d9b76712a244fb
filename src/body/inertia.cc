#include "cga_rigid_sim/body/inertia.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace cga_rigid_sim {
namespace dynamics {

const char* toString(InertiaClass c) {
  switch (c) {
    case InertiaClass::kSpherical:
      return "spherical";
    case InertiaClass::kSymmetric:
      return "symmetric";
    case InertiaClass::kAsymmetric:
      return "asymmetric";
  }
  return "unknown";
}

namespace {

bool nearlyEqual(double a, double b) {
  return std::abs(a - b) <= kEqualMomentsRelTol * std::max(std::abs(a), std::abs(b));
}

Error refuse(const std::string& body, const std::string& rule) {
  return Error{"body '" + body + "': " + rule};
}

// Principal moments in ascending order and the rotation whose columns are the principal axes.
// A tensor that is already diagonal is sorted by an exact permutation, so a diagonal URDF
// inertia reaches the integrators without the eigen-solver's round-off.
void diagonalise(const Eigen::Matrix3d& J, Eigen::Vector3d* moments, Eigen::Matrix3d* axes) {
  const bool diagonal =
      J(0, 1) == 0 && J(0, 2) == 0 && J(1, 2) == 0 && J(1, 0) == 0 && J(2, 0) == 0 && J(2, 1) == 0;
  if (diagonal) {
    std::array<int, 3> idx = {0, 1, 2};
    std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return J(a, a) < J(b, b); });
    for (int k = 0; k < 3; ++k) {
      (*moments)[k] = J(idx[k], idx[k]);
      axes->col(k) = Eigen::Vector3d::Unit(idx[k]);
    }
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(J);
    *moments = solver.eigenvalues();
    *axes = solver.eigenvectors();
  }
  if (axes->determinant() < 0) axes->col(0) = -axes->col(0);
}

}  // namespace

Result<Inertia> Inertia::fromTensor(const std::string& body, double mass,
                                    const Eigen::Matrix3d& J_F, TrianglePolicy policy,
                                    std::string* warning) {
  std::ostringstream os;
  os.precision(17);
  if (!std::isfinite(mass))
    return refuse(body, "mass must be finite (got " + std::to_string(mass) + ")");
  if (mass <= 0) {
    os << "mass must be > 0 (got " << mass << ")";
    return refuse(body, os.str());
  }
  if (!J_F.allFinite()) return refuse(body, "inertia tensor entries must be finite");
  const double scale = J_F.cwiseAbs().maxCoeff();
  static const char* const kNames[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (std::abs(J_F(i, j) - J_F(j, i)) > kTriangleRelSlack * scale) {
        os << "inertia tensor is not symmetric (i" << kNames[i] << kNames[j] << " = " << J_F(i, j)
           << " but i" << kNames[j] << kNames[i] << " = " << J_F(j, i) << ")";
        return refuse(body, os.str());
      }
  const Eigen::Matrix3d J = 0.5 * (J_F + J_F.transpose());

  Eigen::Vector3d m;
  Eigen::Matrix3d axes;
  diagonalise(J, &m, &axes);
  if (!(m[0] > 0)) {
    os << "inertia tensor is not positive definite (principal moments " << m[0] << ", " << m[1]
       << ", " << m[2] << " kg m^2)";
    return refuse(body, os.str());
  }
  // Triangle inequality: the largest moment may not exceed the sum of the other two.
  if (m[2] > (m[0] + m[1]) * (1.0 + kTriangleRelSlack)) {
    os << "inertia breaks the triangle inequality I1 + I2 >= I3 (principal moments " << m[0]
       << " + " << m[1] << " < " << m[2] << " kg m^2)";
    if (policy == TrianglePolicy::kRefuse) return refuse(body, os.str());
    // Nearest physical moments (Euclidean distance in principal moments): project onto the
    // plane I1 + I2 = I3 along its normal (1, 1, −1).
    const double d = (m[2] - m[0] - m[1]) / 3.0;
    m += Eigen::Vector3d(d, d, -d);
    if (warning) {
      std::ostringstream w;
      w.precision(17);
      w << "body '" << body << "': " << os.str() << "; using the nearest physical moments " << m[0]
        << ", " << m[1] << ", " << m[2];
      *warning = w.str();
    }
    std::array<int, 3> idx = {0, 1, 2};  // the projection can reorder the moments
    std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return m[a] < m[b]; });
    Eigen::Vector3d ms;
    Eigen::Matrix3d as;
    for (int k = 0; k < 3; ++k) {
      ms[k] = m[idx[k]];
      as.col(k) = axes.col(idx[k]);
    }
    if (as.determinant() < 0) as.col(0) = -as.col(0);
    m = ms;
    axes = as;
  }

  if (!(m[0] >= kMinMomentRatio * m[2])) {
    os.precision(6);  // the moments as the URDF gives them, not their 17 digits
    os << "inertia is too thin to simulate: its smallest principal moment " << m[0]
       << " kg m^2 is below " << kMinMomentRatio << " of its largest " << m[2]
       << " kg m^2 (kMinMomentRatio: round-off would spin it about that axis)";
    return refuse(body, os.str());
  }

  Inertia I;
  I.mass_ = mass;
  const bool eq01 = nearlyEqual(m[0], m[1]), eq12 = nearlyEqual(m[1], m[2]);
  if (eq01 && eq12) {
    // Spherical: every axis is principal; keep F's axes.
    I.class_ = InertiaClass::kSpherical;
    I.J_.setConstant(m.mean());
    I.R_FB_.setIdentity();
    return I;
  }
  if (eq01 || eq12) {
    // Symmetric: put the distinct axis on e3 by a cyclic (proper) permutation of the columns.
    I.class_ = InertiaClass::kSymmetric;
    if (eq12) {  // distinct is the smallest (prolate): columns (1, 2, 0)
      const double e = 0.5 * (m[1] + m[2]);
      I.J_ = Eigen::Vector3d(e, e, m[0]);
      Eigen::Matrix3d c;
      c << axes.col(1), axes.col(2), axes.col(0);
      axes = c;
    } else {
      const double e = 0.5 * (m[0] + m[1]);
      I.J_ = Eigen::Vector3d(e, e, m[2]);
    }
  } else {
    I.class_ = InertiaClass::kAsymmetric;
    I.J_ = m;
  }
  I.R_FB_ = Eigen::Quaterniond(axes);
  I.R_FB_.normalize();
  return I;
}

Result<Inertia> Inertia::fromPrincipal(const std::string& body, double mass,
                                       const Eigen::Vector3d& moments) {
  return fromTensor(body, mass, moments.asDiagonal().toDenseMatrix());
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
