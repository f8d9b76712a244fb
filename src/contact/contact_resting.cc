// Resting islands solved directly (contact_resting.h, doc/contacts.md#resting-islands): an
// island of faces at rest tried as welded, its faces' wrenches from one linear solve, shared
// among their corners and accepted only when every corner pushes and sticks.
#include "contact/contact_resting.h"

#include <cmath>

namespace cga_rigid_sim {
namespace sim {
namespace {

// Φ: the twist (v at the face's centre c, ω) that body s's twist (v at x_s, ω) gives, times
// the side's sign: v_c = v + ω × r = v − [r]× ω, r = c − x_s. Its transpose carries the face's
// wrench (force P at c, couple L) to the body: (P, r × P + L).
Eigen::Matrix<double, 6, 6> faceMap(const Eigen::Vector3d& r, double sign) {
  Eigen::Matrix<double, 6, 6> phi = Eigen::Matrix<double, 6, 6>::Identity();
  phi.topRightCorner<3, 3>() = -crossMatrix(r);
  return sign * phi;
}

// The island's place of slot s (its bodies are few: a linear search).
int localIndex(const SolverWork& work, const SolverWork::Island& I, int s) {
  for (int q = 0; q < I.bodies; ++q)
    if (work.island_body[I.first_body + q] == s) return q;
  return -1;
}

// The face block of island I's f-th group.
const SolverWork::Group& faceGroup(const SolverWork& work, const SolverWork::Island& I, int f) {
  return work.groups[work.island_group[I.first_group + f]];
}

// Whether island I may be a resting one: no tree, at least two faces (one face alone already
// converges in a sweep or two: its normal block is exact) of three or four corners, none of
// which slid in the last step (its warm start on the cone's rim): a sliding island would only
// fail the corners' test (shareAmongCorners).
bool restingCandidate(const std::vector<ContactRow>& rows, const SolverWork& work,
                      const SolverWork::Island& I) {
  if (I.trees > 0 || I.groups > kMaxRestingFaces || I.groups < 2) return false;
  for (int f = 0; f < I.groups; ++f) {
    const SolverWork::Group& g = faceGroup(work, I, f);
    if (g.size < 3) return false;
    for (int i = 0; i < g.size; ++i) {
      const ContactRow& c = rows[g.first + i];
      if (c.lambda_n > 0 && c.lambda_t.norm() >= (1 - 1e-9) * c.mu * c.lambda_n) return false;
    }
  }
  return true;
}

// The faces: at rest, not on a line. Each face's centre, its corners from it, S⁻¹, its sides'
// places in the island and their maps Φ.
bool makeFaces(const std::vector<SolverBody>& bodies, const std::vector<ContactRow>& rows,
               SolverWork& work, const SolverWork::Island& I) {
  const int n = static_cast<int>(bodies.size());
  SolverWork::Resting& R = work.resting;
  for (int f = 0; f < I.groups; ++f) {
    const SolverWork::Group& g = faceGroup(work, I, f);
    SolverWork::Resting::Face& face = R.faces[f];
    const int a = work.a[g.first], b = work.b[g.first];
    face.c.setZero();
    for (int i = 0; i < g.size; ++i) {
      const ContactRow& c = rows[g.first + i];
      if (c.target != 0.0 || c.impact != 0.0) return false;
      face.p[i] = a < n ? Eigen::Vector3d(bodies[a].x + c.ra) : Eigen::Vector3d(bodies[b].x + c.rb);
      face.c += face.p[i];
    }
    face.c /= g.size;
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    for (int i = 0; i < g.size; ++i) {
      face.p[i] -= face.c;  // now ρ_i, the corner from the centre
      S +=
          face.p[i].squaredNorm() * Eigen::Matrix3d::Identity() - face.p[i] * face.p[i].transpose();
    }
    const double scale = S.trace() / 3;
    if (!(scale > 0) || S.determinant() < 1e-9 * scale * scale * scale) return false;  // a line
    face.S_inv = S.inverse();
    face.side[0] = a < n ? localIndex(work, I, a) : -1;
    face.side[1] = b < n ? localIndex(work, I, b) : -1;
    for (int side = 0; side < 2; ++side)
      if (face.side[side] >= 0)
        face.phi[side] = faceMap(face.c - bodies[side ? b : a].x, side ? -1.0 : 1.0);
  }
  return true;
}

// A W = −J v: the wrenches W_f that bring every face's relative twist to zero, with
// A_ff' = Σ over the bodies they share of Φ_fs M_s⁻¹ Φ_f'sᵀ. False when A cannot be solved.
bool solveWrenches(SolverWork& work, const SolverWork::Island& I) {
  const int F = I.groups;
  SolverWork::Resting& R = work.resting;
  R.A.setZero(6 * F, 6 * F);
  R.rhs.setZero(6 * F);
  for (int f = 0; f < F; ++f)
    for (int side = 0; side < 2; ++side) {
      const int q = R.faces[f].side[side];
      if (q < 0) continue;
      const int s = work.island_body[I.first_body + q];
      const SolverWork::Response& resp = work.response[s];
      Eigen::Matrix<double, 6, 6> Y;  // M⁻¹ Φᵀ
      const Eigen::Matrix<double, 6, 6>& phi = R.faces[f].phi[side];
      Y.topRows<3>() = resp.inv_mass * phi.transpose().topRows<3>();
      Y.bottomRows<3>() = resp.inv_inertia * phi.transpose().bottomRows<3>();
      Eigen::Matrix<double, 6, 1> twist;
      twist << work.vel[s].v, work.vel[s].w;
      R.rhs.segment<6>(6 * f) -= phi * twist;
      for (int f2 = 0; f2 < F; ++f2)
        for (int side2 = 0; side2 < 2; ++side2)
          if (R.faces[f2].side[side2] == q)
            R.A.block<6, 6>(6 * f2, 6 * f).noalias() += R.faces[f2].phi[side2] * Y;
    }
  R.ldlt.compute(R.A);
  if (R.ldlt.info() != Eigen::Success) return false;
  R.W = R.ldlt.solve(R.rhs);
  return R.W.allFinite() && !((R.A * R.W - R.rhs).norm() > 1e-9 * R.rhs.norm() + 1e-300);
}

// Each face's wrench shared among its corners with the least squares of impulses:
// P_i = P/m + β × ρ_i, β = S⁻¹ L (Σ P_i = P, Σ ρ_i × P_i = L). Every corner must push and
// stick: λ_n ≥ 0, |λ_t| ≤ μ λ_n.
bool shareAmongCorners(const std::vector<ContactRow>& rows, SolverWork& work,
                       const SolverWork::Island& I) {
  SolverWork::Resting& R = work.resting;
  for (int f = 0; f < I.groups; ++f) {
    const SolverWork::Group& g = faceGroup(work, I, f);
    SolverWork::Resting::Face& face = R.faces[f];
    const Eigen::Vector3d P = R.W.segment<3>(6 * f), L = R.W.segment<3>(6 * f + 3);
    const Eigen::Vector3d beta = face.S_inv * L;
    for (int i = 0; i < g.size; ++i) {
      const ContactRow& c = rows[g.first + i];
      face.impulse[i] = P / g.size + beta.cross(face.p[i]);
      const double ln = c.n.dot(face.impulse[i]);
      const Eigen::Vector2d lt(c.t1.dot(face.impulse[i]), c.t2.dot(face.impulse[i]));
      if (!(ln >= 0) || lt.norm() > c.mu * ln) return false;
    }
  }
  return true;
}

// Accepted: the rows' impulses, and the island's velocities after them.
void acceptResting(int n, std::vector<ContactRow>& rows, SolverWork& work,
                   const SolverWork::Island& I) {
  for (int f = 0; f < I.groups; ++f) {
    const SolverWork::Group& g = faceGroup(work, I, f);
    const SolverWork::Resting::Face& face = work.resting.faces[f];
    const int a = work.a[g.first], b = work.b[g.first];
    Eigen::Vector3d P = Eigen::Vector3d::Zero(), Ma = P, Mb = P;
    for (int i = 0; i < g.size; ++i) {
      ContactRow& c = rows[g.first + i];
      const Eigen::Vector3d& Pi = face.impulse[i];
      c.lambda_n = c.n.dot(Pi);
      c.lambda_t = {c.t1.dot(Pi), c.t2.dot(Pi)};
      P += Pi;
      Ma += c.ra.cross(Pi);
      Mb += c.rb.cross(Pi);
    }
    if (a < n) {
      work.vel[a].v += work.response[a].inv_mass * P;
      work.vel[a].w += work.response[a].inv_inertia * Ma;
    }
    if (b < n) {
      work.vel[b].v -= work.response[b].inv_mass * P;
      work.vel[b].w -= work.response[b].inv_inertia * Mb;
    }
  }
}

}  // namespace

bool solveResting(const std::vector<SolverBody>& bodies, std::vector<ContactRow>& rows,
                  SolverWork& work, const SolverWork::Island& I) {
  if (!restingCandidate(rows, work, I) || !makeFaces(bodies, rows, work, I) ||
      !solveWrenches(work, I) || !shareAmongCorners(rows, work, I))
    return false;
  acceptResting(static_cast<int>(bodies.size()), rows, work, I);
  return true;
}

}  // namespace sim
}  // namespace cga_rigid_sim
