// Mimic joints as the reduced coordinates of a tree (articulated_body.h,
// doc/articulated.md#mimic-joints): ν = G ν_r, forces Gᵀ f, M_r = Gᵀ M G.
#include <algorithm>

#include "cga_rigid_sim/tree/articulated_body.h"

namespace cga_rigid_sim {
namespace dynamics {

namespace {
// Without mimic joints G = 1: every map is a copy (true: done).
template <typename In, typename Out>
bool copiedWithoutMimic(const ArticulatedBody& tree, const In& in, Out& out) {
  if (tree.hasMimic()) return false;
  out = in;
  return true;
}
}  // namespace

void expandVelocity(const ArticulatedBody& tree, const Eigen::VectorXd& nu_r, Eigen::VectorXd& nu) {
  if (copiedWithoutMimic(tree, nu_r, nu)) return;
  const int base = tree.floating() ? 6 : 0;
  nu.resize(tree.velocityCount());
  nu.head(base) = nu_r.head(base);
  for (int k = 0; k < tree.jointCount(); ++k)
    nu[base + k] = tree.mimicMultiplier(k) * nu_r[tree.reducedIndex(k)];
}

void reduceVelocity(const ArticulatedBody& tree, const Eigen::VectorXd& nu, Eigen::VectorXd& nu_r) {
  if (copiedWithoutMimic(tree, nu, nu_r)) return;
  const int base = tree.floating() ? 6 : 0;
  nu_r.resize(tree.reducedCount());
  nu_r.head(base) = nu.head(base);
  const auto& coordinates = tree.coordinates();
  for (std::size_t c = 0; c < coordinates.size(); ++c)
    nu_r[base + static_cast<int>(c)] = nu[base + coordinates[c].joint];
}

void reduceForce(const ArticulatedBody& tree, const Eigen::VectorXd& f, Eigen::VectorXd& f_r) {
  if (copiedWithoutMimic(tree, f, f_r)) return;
  const int base = tree.floating() ? 6 : 0;
  f_r.resize(tree.reducedCount());
  f_r.head(base) = f.head(base);
  reduceJointForce(tree, f.tail(tree.jointCount()), f_r.tail(f_r.size() - base));
}

void reduceJointForce(const ArticulatedBody& tree, Eigen::Ref<const Eigen::VectorXd> f,
                      Eigen::Ref<Eigen::VectorXd> f_r) {
  if (copiedWithoutMimic(tree, f, f_r)) return;
  const int base = tree.floating() ? 6 : 0;
  f_r.setZero();
  for (int k = 0; k < tree.jointCount(); ++k)
    f_r[tree.reducedIndex(k) - base] += tree.mimicMultiplier(k) * f[k];
}

void reduceMatrix(const ArticulatedBody& tree, const Eigen::MatrixXd& M, Eigen::MatrixXd& M_r) {
  TreeWorkspace work;
  reduceMatrix(tree, M, M_r, work);
}

void reduceMatrix(const ArticulatedBody& tree, const Eigen::MatrixXd& M, Eigen::MatrixXd& M_r,
                  TreeWorkspace& work) {
  if (copiedWithoutMimic(tree, M, M_r)) return;
  // Gᵀ M G by rows, then by columns: each full index adds its multiple into its reduced one.
  const int base = tree.floating() ? 6 : 0, nv = tree.velocityCount(), nr = tree.reducedCount();
  const auto reducedOf = [&](int i) { return i < base ? i : tree.reducedIndex(i - base); };
  const auto weightOf = [&](int i) { return i < base ? 1.0 : tree.mimicMultiplier(i - base); };
  Eigen::MatrixXd& rows = work.reduce_rows;  // Gᵀ M
  rows.setZero(nr, nv);
  for (int i = 0; i < nv; ++i) rows.row(reducedOf(i)) += weightOf(i) * M.row(i);
  M_r.setZero(nr, nr);
  for (int j = 0; j < nv; ++j) M_r.col(reducedOf(j)) += weightOf(j) * rows.col(j);
}

void applyMimicPositions(const ArticulatedBody& tree, Eigen::VectorXd& q) {
  if (!tree.hasMimic()) return;
  for (int k = 0; k < tree.jointCount(); ++k) {
    const TreeJoint& j = tree.joints()[k];
    if (j.mimic >= 0)
      q[k] = std::clamp(j.mimic_multiplier * q[j.mimic] + j.mimic_offset, j.lower, j.upper);
  }
}

void applyMimic(const ArticulatedBody& tree, TreeState& state) {
  if (!tree.hasMimic()) return;
  applyMimicPositions(tree, state.q);
  for (int k = 0; k < tree.jointCount(); ++k) {
    const TreeJoint& j = tree.joints()[k];
    if (j.mimic >= 0) state.v[k] = j.mimic_multiplier * state.v[j.mimic];
  }
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
