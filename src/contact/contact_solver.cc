#include "contact/contact_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/contact_friction.h"
#include "contact/contact_patch.h"
#include "contact/contact_resting.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

using Twist = SolverWork::Twist;

// u = J ν of the contact's tree sides (ν or, for the position correction, pν).
template <Eigen::VectorXd SolverTree::*Nu>
Eigen::Vector3d treeVelocity(const std::vector<SolverTree>& trees, const ContactRow& c) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  if (c.ta >= 0) u.noalias() += c.ja * (trees[c.ta].*Nu);
  if (c.tb >= 0) u.noalias() -= c.jb * (trees[c.tb].*Nu);
  return u;
}

bool onTree(const ContactRow& c) { return c.ta >= 0 || c.tb >= 0; }

// The relative velocity of a's point against b's (slots a, b of `vel`; the dummy for none),
// written out in scalars: this and applyTo are the sweeps' whole cost, and the compiler
// vectorises Eigen's 3-vectors here into partial stores that stall the next load.
__attribute__((always_inline)) inline Eigen::Vector3d relativeVelocity(
    const std::vector<Twist>& vel, int a, int b, const ContactRow& c) {
  const double* va = vel[a].v.data();
  const double* wa = vel[a].w.data();
  const double* vb = vel[b].v.data();
  const double* wb = vel[b].w.data();
  const double* ra = c.ra.data();
  const double* rb = c.rb.data();
  return {va[0] - vb[0] + (wa[1] * ra[2] - wa[2] * ra[1]) - (wb[1] * rb[2] - wb[2] * rb[1]),
          va[1] - vb[1] + (wa[2] * ra[0] - wa[0] * ra[2]) - (wb[2] * rb[0] - wb[0] * rb[2]),
          va[2] - vb[2] + (wa[0] * ra[1] - wa[1] * ra[0]) - (wb[0] * rb[1] - wb[1] * rb[0])};
}

// v += m⁻¹ P, w += I⁻¹ M: an impulse P with moment M about the centre of mass.
__attribute__((always_inline)) inline void kickNet(Twist& t, const SolverWork::Response& resp,
                                                   const Eigen::Vector3d& P,
                                                   const Eigen::Vector3d& M) {
  const Eigen::Matrix3d& I = resp.inv_inertia;
  double* v = t.v.data();
  double* w = t.w.data();
  v[0] += resp.inv_mass * P.x();
  v[1] += resp.inv_mass * P.y();
  v[2] += resp.inv_mass * P.z();
  w[0] += I(0, 0) * M.x() + I(0, 1) * M.y() + I(0, 2) * M.z();
  w[1] += I(1, 0) * M.x() + I(1, 1) * M.y() + I(1, 2) * M.z();
  w[2] += I(2, 0) * M.x() + I(2, 1) * M.y() + I(2, 2) * M.z();
}

// v += s m P, w += s I⁻¹ (r × P) for one side (s = ±1).
__attribute__((always_inline)) inline void kick(Twist& t, const SolverWork::Response& resp,
                                                const Eigen::Vector3d& r, double px, double py,
                                                double pz) {
  const Eigen::Vector3d P(px, py, pz);
  kickNet(t, resp, P, r.cross(P));
}

// The impulse P (world axes) at the contact, +P on a and −P on b, added to `vel` (the
// velocities or, for the position correction, the pseudo-velocities); a tree side's to its ν
// or pν.
template <Eigen::VectorXd SolverTree::*Nu>
__attribute__((noinline)) void applyToTrees(std::vector<SolverTree>& trees, const ContactRow& c,
                                            const Eigen::Vector3d& P) {
  if (c.ta >= 0) (trees[c.ta].*Nu).noalias() += c.wa * P;
  if (c.tb >= 0) (trees[c.tb].*Nu).noalias() -= c.wb * P;
}

template <Eigen::VectorXd SolverTree::*Nu>
__attribute__((always_inline)) inline void applyTo(
    std::vector<Twist>& vel, const std::vector<SolverWork::Response>& response,
    std::vector<SolverTree>& trees, int a, int b, const ContactRow& c, const Eigen::Vector3d& P) {
  kick(vel[a], response[a], c.ra, P.x(), P.y(), P.z());
  kick(vel[b], response[b], c.rb, -P.x(), -P.y(), -P.z());
  if (onTree(c)) applyToTrees<Nu>(trees, c, P);
}

// The working arrays for `bodies` and `rows`: responses, lever arms, the rows' slots (the
// dummy for none), and the velocities taken from the bodies (Pos: the pseudo-velocities).
void load(const std::vector<SolverBody>& bodies, const std::vector<ContactRow>& rows,
          SolverWork& work) {
  const int n = static_cast<int>(bodies.size());
  work.response.resize(n + 1);
  work.vel.resize(n + 1);
  work.vel_sweep.resize(n + 1);
  work.vel_start.resize(n + 1);
  for (int s = 0; s < n; ++s) {
    work.response[s].inv_mass = bodies[s].inv_mass;
    work.response[s].inv_inertia = bodies[s].inv_inertia;
    work.response[s].reach = 0.0;
  }
  work.response[n] = SolverWork::Response();
  work.vel[n] = Twist();
  work.a.resize(rows.size());
  work.b.resize(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const ContactRow& c = rows[k];
    work.a[k] = c.a >= 0 ? c.a : n;
    work.b[k] = c.b >= 0 ? c.b : n;
    if (c.a >= 0) work.response[c.a].reach = std::max(work.response[c.a].reach, c.ra.norm());
    if (c.b >= 0) work.response[c.b].reach = std::max(work.response[c.b].reach, c.rb.norm());
  }
}

// The pseudo-inverse of a block's normal Delassus matrix K (size × size, a unit diagonal
// beyond). Four corners in one plane: K = Σ Jᵀ M⁻¹ J over both bodies, whose rows span the
// ones and the in-plane components of r_i × n, so z ⟂ those three (their generalised cross
// product) is K's null vector, and K⁺ = (K + s ẑẑᵀ)⁻¹ − ẑẑᵀ/s for any s > 0 (closed form, no
// eigen-decomposition). Fewer corners are regular. Anything else (a degenerate patch): the
// eigen-decomposition, eigenvalues below 1e-9 of the largest taken as zero.
Eigen::Matrix4d pseudoInverse(const Eigen::Matrix4d& K, int size, const Eigen::Vector3d& n,
                              const Eigen::Vector3d* rn) {
  const double s = K.trace() / 4;
  Eigen::Matrix4d out;
  bool invertible = false;
  if (size == 4) {
    // K = A B Aᵀ with A's columns the ones and the components of r_i × n, which lie in the
    // plane ⟂ n: two of them (p, q, leaving out n's largest) determine them. z ⟂ A's columns:
    // z_i = (−1)^i det of A's rows without i.
    int k = 0;
    n.cwiseAbs().maxCoeff(&k);
    const int p = (k + 1) % 3, q = (k + 2) % 3;
    Eigen::Vector4d z;
    for (int i = 0; i < 4; ++i) {
      Eigen::Matrix3d M;
      for (int j = 0, row = 0; j < 4; ++j)
        if (j != i) M.row(row++) << 1.0, rn[j](p), rn[j](q);
      z(i) = (i % 2 ? -1.0 : 1.0) * M.determinant();
    }
    const double scale =
        rn[0].squaredNorm() + rn[1].squaredNorm() + rn[2].squaredNorm() + rn[3].squaredNorm();
    if (z.norm() > 1e-9 * scale) {  // a patch, not a line
      z.normalize();
      const Eigen::Matrix4d zz = z * z.transpose();
      Eigen::Matrix4d inv;
      (K + s * zz).computeInverseWithCheck(inv, invertible, 1e-300);
      out = inv - zz / s;
    }
  } else {
    Eigen::Matrix4d inv;
    K.computeInverseWithCheck(inv, invertible, 1e-300);
    out = inv;
    for (int i = size; i < 4; ++i) out.row(i).setZero(), out.col(i).setZero();
    invertible = invertible && (K * out).topLeftCorner(size, size).isIdentity(1e-9);
  }
  if (invertible) return out;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(K);
  const double cutoff = 1e-9 * eig.eigenvalues().cwiseAbs().maxCoeff();
  out.setZero();
  for (int q = 0; q < 4; ++q)
    if (eig.eigenvalues()(q) > cutoff)
      out +=
          eig.eigenvectors().col(q) * eig.eigenvectors().col(q).transpose() / eig.eigenvalues()(q);
  for (int i = size; i < 4; ++i) out.row(i).setZero(), out.col(i).setZero();
  return out;
}

// The runs of rows solved as blocks (SolverWork::Group), and each block's pseudo-inverse:
// K_ij = Σ over the movable sides of 1/m + (r_i × n)ᵀ I⁻¹ (r_j × n).
void makeGroups(std::vector<ContactRow>& rows, SolverWork& work) {
  work.groups.clear();
  for (std::size_t k = 0; k < rows.size();) {
    std::size_t e = k + 1;
    const ContactRow& c = rows[k];
    if (!onTree(c) && std::isfinite(c.k_nn))
      while (e < rows.size() && e - k < 4 && !onTree(rows[e]) && work.a[e] == work.a[k] &&
             work.b[e] == work.b[k] && (rows[e].n - c.n).squaredNorm() < 1e-18)
        ++e;
    SolverWork::Group g;
    g.first = static_cast<int>(k);
    g.size = static_cast<int>(e - k);
    for (std::size_t i = k; i < e; ++i) rows[i].face = g.size >= 3;
    if (g.size > 1) {
      Eigen::Matrix4d K = Eigen::Matrix4d::Identity();  // unused rows: a unit diagonal
      Eigen::Vector3d rn_a[4], rn_b[4];
      for (int i = 0; i < g.size; ++i) {
        rn_a[i] = rows[k + i].ra.cross(c.n);
        rn_b[i] = rows[k + i].rb.cross(c.n);
      }
      const SolverWork::Response& A = work.response[work.a[k]];
      const SolverWork::Response& B = work.response[work.b[k]];
      const bool b_moves = work.b[k] + 1 < static_cast<int>(work.response.size());
      Eigen::Vector3d Irn_a[4], Irn_b[4];
      for (int j = 0; j < g.size; ++j) {
        Irn_a[j].noalias() = A.inv_inertia * rn_a[j];
        if (b_moves) Irn_b[j].noalias() = B.inv_inertia * rn_b[j];
      }
      for (int i = 0; i < g.size; ++i)
        for (int j = i; j < g.size; ++j) {
          K(i, j) = A.inv_mass + B.inv_mass + rn_a[i].dot(Irn_a[j]);
          if (b_moves) K(i, j) += rn_b[i].dot(Irn_b[j]);
          K(j, i) = K(i, j);
        }
      g.pinv = pseudoInverse(K, g.size, c.n, rn_a);
    }
    work.groups.push_back(g);
    k = e;
  }
}

// The islands of the groups (SolverWork::Island): union-find over the slots (0 … n−1) and the
// trees (n + t); the dummy joins nothing. Islands are numbered by their first group, and each
// keeps its groups in their order, so Gauss–Seidel visits an island's contacts as a sweep over
// all of them would.
void makeIslands(const std::vector<ContactRow>& rows, int n_trees, SolverWork& work) {
  const int n = static_cast<int>(work.response.size()) - 1;
  if (work.groups.size() == 1 && !onTree(rows[work.groups[0].first])) {  // one face or contact
    const int a = work.a[work.groups[0].first], b = work.b[work.groups[0].first];
    work.island_group.assign(1, 0);
    work.island_body.clear();
    if (a < n) work.island_body.push_back(a);
    if (b < n) work.island_body.push_back(b);
    work.island_tree.clear();
    work.islands.assign(1, SolverWork::Island());
    work.islands[0].groups = 1;
    work.islands[0].bodies = static_cast<int>(work.island_body.size());
    return;
  }
  math::UnionFind& sets = work.island_sets;
  sets.reset(n + n_trees);
  // A group's node: any of its sides (a group's rows share their bodies).
  const auto nodes = [&](int k, int out[4]) {
    int m = 0;
    if (work.a[k] < n) out[m++] = work.a[k];
    if (work.b[k] < n) out[m++] = work.b[k];
    if (rows[k].ta >= 0) out[m++] = n + rows[k].ta;
    if (rows[k].tb >= 0) out[m++] = n + rows[k].tb;
    return m;
  };
  for (const SolverWork::Group& g : work.groups) {
    int nd[4];
    const int m = nodes(g.first, nd);
    for (int i = 1; i < m; ++i) sets.join(nd[i], nd[0]);
  }
  // Number the islands by their first group; collect groups, slots and trees per island.
  std::vector<int>& id = work.node_island;  // per root, then per node: its island, −1 for none
  id.assign(n + n_trees, -1);
  std::vector<int>& island_of_group = work.group_island;
  island_of_group.resize(work.groups.size());
  int islands = 0;
  for (std::size_t q = 0; q < work.groups.size(); ++q) {
    int nd[4];
    if (nodes(work.groups[q].first, nd) == 0) {  // nothing movable on either side: alone
      island_of_group[q] = islands++;
      continue;
    }
    int& i = id[sets.find(nd[0])];
    if (i < 0) i = islands++;
    island_of_group[q] = i;
  }
  work.islands.assign(islands, SolverWork::Island());
  for (const int i : island_of_group) ++work.islands[i].groups;
  for (int x = 0; x < n + n_trees; ++x) {
    const int i = id[sets.find(x)];
    if (i < 0) continue;
    if (x < n)
      ++work.islands[i].bodies;
    else
      ++work.islands[i].trees;
  }
  int g0 = 0, b0 = 0, t0 = 0;
  for (SolverWork::Island& I : work.islands) {
    I.first_group = g0;
    I.first_body = b0;
    I.first_tree = t0;
    g0 += I.groups;
    b0 += I.bodies;
    t0 += I.trees;
    I.groups = I.bodies = I.trees = 0;
  }
  work.island_group.resize(g0);
  work.island_body.resize(b0);
  work.island_tree.resize(t0);
  for (std::size_t q = 0; q < work.groups.size(); ++q) {
    SolverWork::Island& I = work.islands[island_of_group[q]];
    work.island_group[I.first_group + I.groups++] = static_cast<int>(q);
  }
  for (int x = 0; x < n + n_trees; ++x) {
    const int i = id[sets.find(x)];
    if (i < 0) continue;
    SolverWork::Island& I = work.islands[i];
    if (x < n)
      work.island_body[I.first_body + I.bodies++] = x;
    else
      work.island_tree[I.first_tree + I.trees++] = x - n;
  }
}

// The largest change of a contact point's (pseudo-)velocity since vel_sweep, over the
// island's bodies.
double bodyChange(const SolverWork& work, const SolverWork::Island& I) {
  double change = 0.0;
  for (int q = I.first_body; q < I.first_body + I.bodies; ++q) {
    const int s = work.island_body[q];
    change =
        std::max(change, (work.vel[s].v - work.vel_sweep[s].v).norm() +
                             work.response[s].reach * (work.vel[s].w - work.vel_sweep[s].w).norm());
  }
  return change;
}

// The Jacobian of world point p on body b of tree T: column j is the point's velocity under a
// unit rate of coordinate j, v_o + ω × p, for the coordinates that move b (the joints on its
// path to the base, and the base's six).
void pointJacobian(const SolverTree& T, int b, const Eigen::Vector3d& p,
                   Eigen::Matrix<double, 3, Eigen::Dynamic>& J) {
  J.setZero(3, T.M.cols());
  const int base = T.floating ? 6 : 0;
  // A joint's column goes to its coordinate's, times its multiplier (mimic joints; else itself).
  for (int x = b; x > 0; x = T.parent[x]) {
    const int j = base + x - 1;
    J.col(T.column[x - 1]) +=
        T.multiplier[x - 1] * (T.twist.col(j).tail<3>() + T.twist.col(j).head<3>().cross(p));
  }
  for (int j = 0; j < base; ++j)
    J.col(j) = T.twist.col(j).tail<3>() + T.twist.col(j).head<3>().cross(p);
}

// A tangent basis of the plane ⟂ n (any; the friction cone is circular).
void tangents(const Eigen::Vector3d& n, Eigen::Vector3d& t1, Eigen::Vector3d& t2) {
  const Eigen::Vector3d ref =
      std::abs(n.x()) < 0.57735 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  t1 = n.cross(ref).normalized();
  t2 = n.cross(t1);
}

// Row k's target from the velocities before any contact impulse.
void setTarget(const SolverSettings& st, const SolverWork& work,
               const std::vector<SolverTree>& trees, bool bounce, std::size_t k, ContactRow& c) {
  Eigen::Vector3d u = relativeVelocity(work.vel, work.a[k], work.b[k], c);
  if (onTree(c)) u += treeVelocity<&SolverTree::nu>(trees, c);
  const double u_n = c.n.dot(u);
  const double h = st.h;
  const double d = c.depth;
  c.mu = frictionCoefficient(st.model,
                             c.face ? st.model.face_friction_ratio * c.mu_surface : c.mu_surface,
                             (u - u_n * c.n).norm());
  c.impact = 0.0;
  c.compliant = st.model.compliant() && !onTree(c);
  if (c.compliant) {  // the spring's impulse; no target, no bounce
    // δ̇ at the step's start: against an immovable side, without the step's gravity kick
    // (at rest the kick's g h would read as an approach and the damper would push too hard).
    const bool one_sided = work.b[k] + 1 == static_cast<int>(work.response.size());
    const double approach = -u_n + (one_sided ? c.n.dot(st.gravity_kick_W) : 0.0);
    c.lambda_fixed = compliantImpulse(st.model, d, approach, h);
    c.target = -std::numeric_limits<double>::infinity();
    return;
  }
  // A gap may close, no more; a gap within round-off of contact is contact (targets of
  // ±1e-12 m / h under the four corners of a face would disagree, and Gauss–Seidel would
  // chase them for ever).
  double target = d >= -st.touching ? 0.0 : d / h;
  // An impact: the bodies approach faster than the resting threshold and touch within the
  // step. Newton's law sends them apart at e times the approach speed.
  c.target_t.setZero();
  if (bounce && (c.restitution > 0 || st.model.tangential_restitution > 0) &&
      u_n < -st.bounce_speed && (d > 0 || u_n * h < d)) {
    c.impact = -u_n;
    target = std::max(target, restitutionCoefficient(st.model, c.restitution, c.impact) * c.impact);
    // Tangential restitution (doc/contact_model.md): the slip reversed, if the cone allows.
    if (st.model.tangential_restitution > 0)
      c.target_t = -st.model.tangential_restitution * Eigen::Vector2d(c.t1.dot(u), c.t2.dot(u));
  }
  c.target = target;
}

// Friction: the impulse that stops the sliding at relative velocity u, projected onto the
// cone's disc; updates λ_t and returns its change. `relax` > 1 over-relaxes the step (then
// projects onto the disc again): λ_t + relax (λ_t' − λ_t). It has the same fixed points (where
// the step is zero, so is the relaxed one; on the rim a relaxed step that projects back onto
// λ_t would need a step pointing out of the disc, which a projected λ_t' cannot have).
__attribute__((always_inline)) inline Eigen::Vector2d frictionStep(ContactRow& c,
                                                                   const Eigen::Vector3d& u,
                                                                   double relax = 1.0) {
  const Eigen::Vector2d u_t = Eigen::Vector2d(c.t1.dot(u), c.t2.dot(u)) - c.target_t;
  const double tmax = c.mu * c.lambda_n;
  Eigen::Vector2d lt = c.lambda_t - c.k_tt_inv * u_t;  // sticks, if the cone allows
  if (lt.squaredNorm() > tmax * tmax) {                // slides
    lt = c.lambda_t - u_t * c.inv_k_t;
    const double t = lt.norm();
    if (t > tmax) lt *= t > 0 ? tmax / t : 0.0;
  }
  if (relax != 1.0) {
    lt = c.lambda_t + relax * (lt - c.lambda_t);
    const double t2 = lt.squaredNorm();
    if (t2 > tmax * tmax) lt *= tmax > 0 ? tmax / std::sqrt(t2) : 0.0;
  }
  const Eigen::Vector2d dt = lt - c.lambda_t;
  c.lambda_t = lt;
  return dt;
}

// The over-relaxation of the friction at a face's corners (successive over-relaxation): each
// corner's friction step tilts the box and changes its neighbours' slip, and plain Gauss–Seidel
// (1) converges slowly on the columns of a landed pile (their change per sweep falls by ~0.5 %
// a sweep). 1.5 settles the 1000-box pile ~0.1 s sooner and makes its landing ~20 % cheaper
// (1.3: about the same; 1.7 and 1.9: dearer). Single contacts keep the exact step: a rolling
// ball's one contact converges in one sweep, and a relaxed step would only make it oscillate.
constexpr double kFaceFrictionRelaxation = 1.5;

// The friction (and patch couples) of a block's corners, corner by corner.
void sweepFriction(const SolverWork::Group& g, SolverWork& work, std::vector<SolverTree>& trees,
                   std::vector<ContactRow>& rows, const ContactModel& model, bool patch) {
  const int a = work.a[g.first], b = work.b[g.first];
  for (int i = 0; i < g.size; ++i) {
    ContactRow& c = rows[g.first + i];
    const Eigen::Vector2d dt =
        frictionStep(c, relativeVelocity(work.vel, a, b, c), kFaceFrictionRelaxation);
    if (dt.x() != 0.0 || dt.y() != 0.0)
      applyTo<&SolverTree::nu>(work.vel, work.response, trees, a, b, c,
                               dt.x() * c.t1 + dt.y() * c.t2);
    if (patch) patchStep(model, c, work.vel[a], work.vel[b], work.response[a], work.response[b]);
  }
}

// One sweep over a block of a face's corners: their normal impulses together (the block's
// pseudo-inverse brings every normal velocity to its target at once), or one by one when that
// would make one negative; then each corner's friction.
void sweepGroup(const SolverWork::Group& g, SolverWork& work, std::vector<SolverTree>& trees,
                std::vector<ContactRow>& rows, const ContactModel& model, bool patch) {
  const int a = work.a[g.first], b = work.b[g.first];
  if (rows[g.first].compliant) {  // the springs' impulses are fixed: friction alone
    for (int i = 0; i < g.size; ++i) {
      ContactRow& c = rows[g.first + i];
      const double dn = c.lambda_fixed - c.lambda_n;
      c.lambda_n = c.lambda_fixed;
      if (dn != 0.0) applyTo<&SolverTree::nu>(work.vel, work.response, trees, a, b, c, dn * c.n);
    }
    sweepFriction(g, work, trees, rows, model, patch);
    return;
  }
  Eigen::Vector4d r = Eigen::Vector4d::Zero();
  for (int i = 0; i < g.size; ++i) {
    const ContactRow& c = rows[g.first + i];
    r(i) = c.target - c.n.dot(relativeVelocity(work.vel, a, b, c));
  }
  const Eigen::Vector4d d = g.pinv * r;
  bool feasible = true;
  for (int i = 0; i < g.size; ++i) feasible = feasible && rows[g.first + i].lambda_n + d(i) >= 0;
  if (feasible) {  // all at once: one kick per side with the block's net impulse and moment
    Eigen::Vector3d P = Eigen::Vector3d::Zero(), Ma = P, Mb = P;
    for (int i = 0; i < g.size; ++i) {
      ContactRow& c = rows[g.first + i];
      c.lambda_n += d(i);
      const Eigen::Vector3d Pi = d(i) * c.n;
      P += Pi;
      Ma += c.ra.cross(Pi);
      Mb += c.rb.cross(Pi);
    }
    kickNet(work.vel[a], work.response[a], P, Ma);
    kickNet(work.vel[b], work.response[b], -P, -Mb);
  }
  for (int i = 0; i < g.size && !feasible; ++i) {
    ContactRow& c = rows[g.first + i];
    // Gauss–Seidel within the block.
    const double u_n = c.n.dot(relativeVelocity(work.vel, a, b, c));
    const double dn = std::max(0.0, c.lambda_n + (c.target - u_n) * c.inv_k_nn) - c.lambda_n;
    c.lambda_n += dn;
    if (dn != 0.0) applyTo<&SolverTree::nu>(work.vel, work.response, trees, a, b, c, dn * c.n);
  }
  sweepFriction(g, work, trees, rows, model, patch);
}

}  // namespace

void prepareRows(const std::vector<Contact>& contacts, const std::vector<SolverBody>& bodies,
                 const std::vector<SolverTree>& trees, const std::vector<int>& slot_a,
                 const std::vector<int>& slot_b, std::vector<ContactRow>& rows) {
  rows.resize(contacts.size());
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& ct = contacts[k];
    ContactRow& c = rows[k];
    c.a = slot_a[k];
    c.b = slot_b[k];
    c.n = ct.normal_W;
    tangents(c.n, c.t1, c.t2);
    c.ra = c.a >= 0 ? Eigen::Vector3d(ct.point_W - bodies[c.a].x) : Eigen::Vector3d::Zero();
    c.rb = c.b >= 0 ? Eigen::Vector3d(ct.point_W - bodies[c.b].x) : Eigen::Vector3d::Zero();
    // Tree sides: their Jacobians; two links of one tree share ν, so side a keeps J_a − J_b.
    c.ta = c.a >= 0 ? bodies[c.a].tree : -1;
    c.tb = c.b >= 0 ? bodies[c.b].tree : -1;
    if (c.ta >= 0) {
      pointJacobian(trees[c.ta], bodies[c.a].tree_body, ct.point_W, c.ja);
      c.a = -1;
    }
    if (c.tb >= 0) {
      pointJacobian(trees[c.tb], bodies[c.b].tree_body, ct.point_W, c.jb);
      c.b = -1;
      if (c.tb == c.ta) {
        c.ja -= c.jb;
        c.tb = -1;
      }
    }
    // K = Σ (1/m) 1 − [r]× I⁻¹ [r]× over the movable bodies, + J M⁻¹ Jᵀ over the tree sides:
    // the velocity change at the point per unit impulse there. In the contact basis
    // B = (n, t1, t2) a body's part is Kc_ij = δ_ij / m + (r × b_i)ᵀ I⁻¹ (r × b_j), and
    // K n = n / m − r × I⁻¹ (r × n): three lever arms and their responses, not 3 × 3 products.
    Eigen::Matrix3d Kc = Eigen::Matrix3d::Zero();
    c.k_n.setZero();
    for (int side = 0; side < 2; ++side) {
      const int s = side ? c.b : c.a;
      if (s < 0) continue;
      const Eigen::Vector3d& r = side ? c.rb : c.ra;
      const Eigen::Matrix3d& Iinv = bodies[s].inv_inertia;
      const Eigen::Vector3d rn = r.cross(c.n), r1 = r.cross(c.t1), r2 = r.cross(c.t2);
      const Eigen::Vector3d In = Iinv * rn, I1 = Iinv * r1, I2 = Iinv * r2;
      const double m = bodies[s].inv_mass;
      Kc(0, 0) += m + rn.dot(In);
      Kc(0, 1) += rn.dot(I1);
      Kc(0, 2) += rn.dot(I2);
      Kc(1, 1) += m + r1.dot(I1);
      Kc(1, 2) += r1.dot(I2);
      Kc(2, 2) += m + r2.dot(I2);
      c.k_n += m * c.n - r.cross(In);
    }
    if (c.ta >= 0 || c.tb >= 0) {
      Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
      if (c.ta >= 0) {
        c.wa = c.ja.transpose();
        trees[c.ta].llt.solveInPlace(c.wa);
        K.noalias() += c.ja * c.wa;
      }
      if (c.tb >= 0) {
        c.wb = c.jb.transpose();
        trees[c.tb].llt.solveInPlace(c.wb);
        K.noalias() += c.jb * c.wb;
      }
      Eigen::Matrix3d B;
      B << c.n, c.t1, c.t2;
      Kc += B.transpose() * K * B;  // its upper triangle is kept
      c.k_n += K * c.n;
    }
    Kc(1, 0) = Kc(0, 1);
    Kc(2, 0) = Kc(0, 2);
    Kc(2, 1) = Kc(1, 2);
    const double trace = Kc.trace();  // K's: B is orthonormal
    // A free body's K is positive definite; a tree side's J M⁻¹ Jᵀ has the rank of the motions
    // the link can make at the point (one for a pendulum's bob): directions it cannot move in
    // get no impulse (their inverse is taken as zero, their k as infinite), and an impulse
    // that could only act along them is none. Round-off decides below 1e-12 of K's trace.
    const double cutoff = 1e-12 * trace;
    const double inf = std::numeric_limits<double>::infinity();
    c.k_nn = Kc(0, 0) > cutoff ? Kc(0, 0) : inf;
    const double tr = Kc(1, 1) + Kc(2, 2), det = Kc(1, 1) * Kc(2, 2) - Kc(1, 2) * Kc(2, 1);
    if (det > 1e-12 * tr * tr) {  // both tangent directions movable (always for free bodies)
      c.k_t = 0.5 * tr + std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
      c.k_tt_inv << Kc(2, 2) / det, -Kc(1, 2) / det, -Kc(2, 1) / det, Kc(1, 1) / det;
    } else {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> tangent(Kc.bottomRightCorner<2, 2>());
      c.k_tt_inv.setZero();
      const double top = tangent.eigenvalues()(1);
      if (top > cutoff)
        c.k_tt_inv =
            tangent.eigenvectors().col(1) * tangent.eigenvectors().col(1).transpose() / top;
      c.k_t = top > cutoff ? top : inf;
    }
    c.inv_k_nn = 1.0 / c.k_nn;  // 0 for an infinite k: no impulse
    c.inv_k_t = 1.0 / c.k_t;
    c.mu = c.mu_surface = ct.mu;
    c.restitution = ct.restitution;
    c.depth = ct.depth;
    c.lambda_p = 0.0;
    c.lambda_spin = 0.0;
    c.lambda_roll.setZero();
    c.couple.setZero();
    c.compliant = false;
    c.lambda_fixed = 0.0;
    c.target_t.setZero();
  }
}

double kineticEnergy(const std::vector<SolverBody>& bodies, const std::vector<SolverTree>& trees) {
  double T = 0.0;
  for (const SolverBody& b : bodies)
    T += 0.5 * (b.mass * b.v.squaredNorm() + b.w.dot(b.inertia * b.w));
  for (const SolverTree& t : trees) T += 0.5 * t.nu.dot(t.M.selfadjointView<Eigen::Lower>() * t.nu);
  return T;
}

namespace {

// The kinetic energy of an island's bodies and trees, before the contact impulses (vel_start,
// ν_start) or at the velocities now in `work` (vel, ν).
double islandKinetic(const std::vector<SolverBody>& bodies, const std::vector<SolverTree>& trees,
                     const SolverWork& work, const SolverWork::Island& I, bool before) {
  const std::vector<SolverWork::Twist>& vel = before ? work.vel_start : work.vel;
  double T = 0.0;
  for (int q = I.first_body; q < I.first_body + I.bodies; ++q) {
    const int s = work.island_body[q];
    const SolverWork::Twist& t = vel[s];
    T += 0.5 * (bodies[s].mass * t.v.squaredNorm() + t.w.dot(bodies[s].inertia * t.w));
  }
  for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {
    const SolverTree& t = trees[work.island_tree[q]];
    const Eigen::VectorXd& nu = before ? t.nu_start : t.nu;
    T += 0.5 * nu.dot(t.M.selfadjointView<Eigen::Lower>() * nu);
  }
  return T;
}

// Calls f(k, row) for the island's rows, in their order.
template <class F>
void forRows(const SolverWork& work, std::vector<ContactRow>& rows, const SolverWork::Island& I,
             F&& f) {
  for (int q = I.first_group; q < I.first_group + I.groups; ++q) {
    const SolverWork::Group& g = work.groups[work.island_group[q]];
    for (int k = g.first; k < g.first + g.size; ++k) f(static_cast<std::size_t>(k), rows[k]);
  }
}

// The column M⁻¹ e_k of a limit row, made the first time the row acts in a step.
void makeColumn(const SolverTree& t, SolverTree::LimitRow& r) {
  r.column.setZero(t.nu.size());
  r.column[r.index] = 1.0;
  t.llt.solveInPlace(r.column);
  r.a = r.column[r.index];
}

// One Gauss–Seidel pass over tree t's limit rows: the rates `nu` (ν, or pν with `base` = the
// rates it adds to: ν for the position correction) kept so that q + h (base_k + nu_k) stays
// within [lower, upper], by the accumulated impulses *y_lower ≥ 0 and *y_upper ≤ 0 on the
// joint. Returns the largest change of a rate.
template <Eigen::VectorXd SolverTree::*Nu, double SolverTree::LimitRow::*Lower,
          double SolverTree::LimitRow::*Upper>
double sweepLimits(SolverTree& t, double h, const Eigen::VectorXd* base) {
  double change = 0.0;
  Eigen::VectorXd& nu = t.*Nu;
  for (SolverTree::LimitRow& r : t.limits) {
    const double b = base ? (*base)[r.index] : 0.0;
    const double lo = (r.lower - r.q) / h - b, hi = (r.upper - r.q) / h - b;
    double v = nu[r.index];
    if (r.*Lower == 0.0 && r.*Upper == 0.0 && v >= lo && v <= hi) continue;  // free
    if (r.a == 0.0) makeColumn(t, r);
    if (!(r.a > 0.0)) continue;
    const double yl = std::max(0.0, r.*Lower + (lo - v) / r.a);
    double dy = yl - r.*Lower;
    r.*Lower = yl;
    v += dy * r.a;
    const double yu = std::min(0.0, r.*Upper + (hi - v) / r.a);
    dy += yu - r.*Upper;
    r.*Upper = yu;
    if (dy == 0.0) continue;
    nu.noalias() += dy * r.column;
    change = std::max(change, std::abs(dy * r.a));
  }
  return change;
}

// The velocity solve of one island (sweeps until its own change is below the tolerance, and
// the energy guard); returns its sweeps.
int solveIsland(const SolverSettings& st, const std::vector<SolverBody>& bodies,
                std::vector<SolverTree>& trees, std::vector<ContactRow>& rows, SolverWork& work,
                const SolverWork::Island& I) {
  const auto bodiesOf = [&](auto&& f) {
    for (int q = I.first_body; q < I.first_body + I.bodies; ++q) f(work.island_body[q]);
  };
  const auto treesOf = [&](auto&& f) {
    for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) f(trees[work.island_tree[q]]);
  };
  double speed = 0.0;  // the fastest contact point's speed before the impulses
  bodiesOf([&](int s) {
    speed = std::max(speed, work.vel[s].v.norm() + work.response[s].reach * work.vel[s].w.norm());
  });
  if (I.trees > 0)
    forRows(work, rows, I, [&](std::size_t, ContactRow& c) {
      if (onTree(c)) speed = std::max(speed, treeVelocity<&SolverTree::nu>(trees, c).norm());
    });
  const double tolerance = st.tolerance + st.tolerance_of_kick * st.kick +
                           st.tolerance_of_speed * std::max(0.0, speed - 2.0 * st.kick);
  int sweeps = 0;
  const bool patch = patchResistance(st.model);
  for (int attempt = 0; attempt < 2; ++attempt) {
    const bool bounce = attempt == 0;
    if (!bounce) {  // start again from the velocities before the contacts, cold
      bodiesOf([&](int s) { work.vel[s] = work.vel_start[s]; });
      treesOf([](SolverTree& t) {
        t.nu = t.nu_start;
        for (SolverTree::LimitRow& r : t.limits) r.y_lower = r.y_upper = 0.0;
      });
      forRows(work, rows, I, [](std::size_t, ContactRow& c) {
        c.lambda_n = 0.0;
        c.lambda_t.setZero();
        c.lambda_spin = 0.0;
        c.lambda_roll.setZero();
        c.couple.setZero();
      });
    }
    forRows(work, rows, I,
            [&](std::size_t k, ContactRow& c) { setTarget(st, work, trees, bounce, k, c); });
    // A resting island of faces solved directly; the sweeps then only confirm it.
    if (!bounce || st.model.compliant() || !solveResting(bodies, rows, work, I)) {
      forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {  // warm start, inside the cone
        c.lambda_n = c.compliant ? c.lambda_fixed : std::max(0.0, c.lambda_n);
        const double tmax = c.mu * c.lambda_n, t = c.lambda_t.norm();
        if (t > tmax) c.lambda_t *= t > 0 ? tmax / t : 0.0;
        applyTo<&SolverTree::nu>(work.vel, work.response, trees, work.a[k], work.b[k], c,
                                 c.lambda_n * c.n + c.lambda_t.x() * c.t1 + c.lambda_t.y() * c.t2);
      });
    }
    int it = 0;
    const int max_iterations = I.trees > 0 ? st.max_tree_iterations : st.max_iterations;
    for (; it < max_iterations; ++it) {
      bodiesOf([&](int s) { work.vel_sweep[s] = work.vel[s]; });
      treesOf([](SolverTree& t) { t.nu_sweep = t.nu; });
      for (int q = I.first_group; q < I.first_group + I.groups; ++q) {
        const SolverWork::Group& g = work.groups[work.island_group[q]];
        if (g.size > 1) {
          sweepGroup(g, work, trees, rows, st.model, patch);
          continue;
        }
        const std::size_t k = g.first;
        ContactRow& c = rows[k];
        const int a = work.a[k], b = work.b[k];
        // Normal: the impulse that brings u_n to its target, kept ≥ 0.
        Eigen::Vector3d u = relativeVelocity(work.vel, a, b, c);
        if (onTree(c)) u += treeVelocity<&SolverTree::nu>(trees, c);
        const double ln = c.compliant
                              ? c.lambda_fixed
                              : std::max(0.0, c.lambda_n + (c.target - c.n.dot(u)) * c.inv_k_nn);
        const double dn = ln - c.lambda_n;
        c.lambda_n = ln;
        u += dn * c.k_n;  // the velocity after it, without applying it yet
        const Eigen::Vector2d dt = frictionStep(c, u);
        // Both at once: one application per contact and sweep.
        if (dn != 0.0 || dt.x() != 0.0 || dt.y() != 0.0)
          applyTo<&SolverTree::nu>(work.vel, work.response, trees, a, b, c,
                                   dn * c.n + dt.x() * c.t1 + dt.y() * c.t2);
        if (patch && !onTree(c))
          patchStep(st.model, c, work.vel[a], work.vel[b], work.response[a], work.response[b]);
      }
      // The joints' limits, solved with the contacts (a rate's change counts as a point's at
      // 1 m).
      double limit_change = 0.0;
      treesOf([&](SolverTree& t) {
        limit_change =
            std::max(limit_change, sweepLimits<&SolverTree::nu, &SolverTree::LimitRow::y_lower,
                                               &SolverTree::LimitRow::y_upper>(t, st.h, nullptr));
      });
      double change = std::max(bodyChange(work, I), limit_change);
      if (I.trees > 0) {  // a tree's change as its contact points see it
        treesOf([](SolverTree& t) { t.nu_sweep = t.nu - t.nu_sweep; });
        forRows(work, rows, I, [&](std::size_t, ContactRow& c) {
          if (onTree(c))
            change = std::max(change, treeVelocity<&SolverTree::nu_sweep>(trees, c).norm());
        });
      }
      if (change < tolerance) {
        ++it;
        break;
      }
    }
    sweeps += it;
    bool any_bounce = false;
    forRows(work, rows, I,
            [&](std::size_t, ContactRow& c) { any_bounce = any_bounce || c.impact > 0; });
    // The energy guard: restitution in several simultaneous impacts can add energy; e = 0
    // cannot (doc/contacts.md#energy).
    if (!any_bounce || islandKinetic(bodies, trees, work, I, false) <=
                           islandKinetic(bodies, trees, work, I, true) * (1 + 1e-12) + 1e-300)
      break;
  }
  return sweeps;
}

}  // namespace

SolveStats solveVelocities(const SolverSettings& st, std::vector<SolverBody>& bodies,
                           std::vector<SolverTree>& trees, std::vector<ContactRow>& rows,
                           SolverWork& work) {
  SolveStats stats;
  load(bodies, rows, work);
  makeGroups(rows, work);
  makeIslands(rows, static_cast<int>(trees.size()), work);
  const std::size_t n = bodies.size();
  // The velocities before any contact impulse: the warm start is applied after the targets
  // are read from them.
  for (std::size_t s = 0; s < n; ++s) work.vel_start[s] = {bodies[s].v, bodies[s].w};
  work.vel_start[n] = Twist();
  std::copy(work.vel_start.begin(), work.vel_start.end(), work.vel.begin());
  for (SolverTree& t : trees) t.nu_start = t.nu;
  if (st.kinetic_energy) stats.kinetic_before = kineticEnergy(bodies, trees);
  for (const SolverWork::Island& I : work.islands)
    stats.iterations = std::max(stats.iterations, solveIsland(st, bodies, trees, rows, work, I));
  for (std::size_t s = 0; s < n; ++s) {
    bodies[s].v = work.vel[s].v;
    bodies[s].w = work.vel[s].w;
  }
  if (st.kinetic_energy) stats.kinetic_after = kineticEnergy(bodies, trees);
  return stats;
}

void solvePositions(const SolverSettings& st, std::vector<SolverBody>& bodies,
                    std::vector<SolverTree>& trees, std::vector<ContactRow>& rows,
                    SolverWork& work) {
  for (SolverTree& t : trees) t.pnu.setZero(t.nu.size());
  const std::size_t n = bodies.size();
  for (SolverBody& b : bodies) {
    b.pv.setZero();
    b.pw.setZero();
  }
  double max_bias = 0.0;
  for (ContactRow& c : rows) {
    c.bias = c.depth > st.slop && !c.compliant ? st.correction * (c.depth - st.slop) / st.h : 0.0;
    c.lambda_p = 0.0;
    max_bias = std::max(max_bias, c.bias);
  }
  if (max_bias == 0.0) return;
  std::fill(work.vel.begin(), work.vel.end(), Twist());  // the responses and islands are kept
  for (const SolverWork::Island& I : work.islands) {
    double island_bias = 0.0;
    forRows(work, rows, I,
            [&](std::size_t, ContactRow& c) { island_bias = std::max(island_bias, c.bias); });
    if (island_bias == 0.0) continue;
    for (int it = 0; it < st.position_iterations; ++it) {
      for (int q = I.first_body; q < I.first_body + I.bodies; ++q)
        work.vel_sweep[work.island_body[q]] = work.vel[work.island_body[q]];
      for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {
        SolverTree& t = trees[work.island_tree[q]];
        t.pnu_sweep = t.pnu;
      }
      forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {
        if (c.bias <= 0 && c.lambda_p == 0.0) return;
        const int a = work.a[k], b = work.b[k];
        double u = c.n.dot(relativeVelocity(work.vel, a, b, c));
        if (onTree(c)) u += c.n.dot(treeVelocity<&SolverTree::pnu>(trees, c));
        const double lp = std::max(0.0, c.lambda_p + (c.bias - u) * c.inv_k_nn);
        const double d = lp - c.lambda_p;
        c.lambda_p = lp;
        if (d != 0.0) applyTo<&SolverTree::pnu>(work.vel, work.response, trees, a, b, c, d * c.n);
      });
      double change = bodyChange(work, I);
      for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {  // within the limits
        SolverTree& t = trees[work.island_tree[q]];
        change = std::max(change, sweepLimits<&SolverTree::pnu, &SolverTree::LimitRow::p_lower,
                                              &SolverTree::LimitRow::p_upper>(t, st.h, &t.nu));
      }
      if (I.trees > 0) {
        for (int q = I.first_tree; q < I.first_tree + I.trees; ++q) {
          SolverTree& t = trees[work.island_tree[q]];
          t.pnu_sweep = t.pnu - t.pnu_sweep;
        }
        forRows(work, rows, I, [&](std::size_t, ContactRow& c) {
          if (onTree(c))
            change = std::max(change, treeVelocity<&SolverTree::pnu_sweep>(trees, c).norm());
        });
      }
      if (change < 1e-3 * island_bias) break;  // 0.1 % of the island's largest correction
    }
  }
  for (std::size_t s = 0; s < n; ++s) {
    bodies[s].pv = work.vel[s].v;
    bodies[s].pw = work.vel[s].w;
  }
  // A tree's correction moves no coordinate by more than max_tree_shift in one step: scaled
  // down as a whole (it keeps its direction, so an internal contact still leaves the tree's
  // centre of mass where it is, and stays within the limits, a convex set holding pν = 0).
  for (SolverTree& t : trees) {
    const double largest = st.h * t.pnu.cwiseAbs().maxCoeff();
    if (largest > st.max_tree_shift) t.pnu *= st.max_tree_shift / largest;
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
