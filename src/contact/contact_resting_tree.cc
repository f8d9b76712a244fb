// A tree's island solved by Newton's method (contact_resting_tree.h,
// doc/contacts.md#resting-trees): at rest, its position correction, its normals after the sweeps.
#include "contact/contact_resting_tree.h"

#include <algorithm>
#include <cmath>

#include "contact/contact_patch.h"
#include "contact/contact_solver_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// Each row's compliance 1/D_i as a fraction of its own Delassus entry g_i M⁻¹ g_iᵀ. The
// augmented Lagrangian rounds remove the compliance's error, so ε sets their speed, not the
// answer: each round cuts a row's miss by roughly ε times its coupling to the others, while the
// Hessian's condition in the metric of M stays near 1/ε. Measured on Atlas lying
// (doc/decisions.md#a-resting-robots-island): 1e-5 and 1e-7 take more steps than 1e-6.
constexpr double kCompliance = 1e-6;
// Newton steps per round and rounds at most, and the rounds' stop: no row's velocity off its
// target by more, m/s (1e-2 of the sleep speed kSleepSpeed, contact_sleep.h).
constexpr int kMaxNewtonSteps = 30;
constexpr int kMaxRounds = 10;
constexpr double kNewtonTolerance = 1e-8;
// A warm start's edge below this fraction of its contact's λ_n is the rounding of λ_n, λ_t and
// the share it was split from (a few ulps), not an impulse: zero, so that it starts inactive.
constexpr double kSplitRounding = 1e-12;
// Rounds of the normals' solve after the sweeps at most (polishTreeNormals).
constexpr int kPolishRounds = 8;

// The contact's relative point velocity per unit ν of tree t: J_a (side a on t) or −J_b.
const Eigen::Matrix<double, 3, Eigen::Dynamic>& sideJacobian(const ContactRow& c, int t,
                                                             double* sign) {
  *sign = c.ta == t ? 1.0 : -1.0;
  return c.ta == t ? c.ja : c.jb;
}

// Whether island I is one for the Newton solve: one tree alone, every contact on it at rest.
bool eligible(const SolverSettings& st, const std::vector<SolverTree>& trees,
              std::vector<ContactRow>& rows, const SolverWork& work, const SolverWork::Island& I) {
  if (I.trees != 1 || I.bodies != 0 || patchResistance(st.model) || st.model.compliant())
    return false;
  const int t = work.island_tree[I.first_tree];
  bool ok = true;
  detail::forRows(work, rows, I, [&](std::size_t, ContactRow& c) {
    if (!ok) return;
    const bool on_a = c.ta == t, on_b = c.tb == t;
    if (on_a == on_b || c.compliant || c.impact != 0.0 || !c.target_t.isZero(0.0)) {
      ok = false;
      return;
    }
    ok = detail::treeVelocity<&SolverTree::nu_start>(trees, c).norm() <= st.resting_tree_speed;
  });
  return ok;
}

// out += Σ_i J_iᵀ P_i over the contacts rows[contacts[i]] on tree t (J_i their point's
// velocity per unit ν, signed for the tree's side), P_i = impulse(i, row) in world axes.
template <class Impulse>
void addContactImpulses(const std::vector<ContactRow>& rows, const std::vector<int>& contacts,
                        int t, Eigen::VectorXd& out, Impulse impulse) {
  for (int i = 0; i < static_cast<int>(contacts.size()); ++i) {
    const ContactRow& c = rows[contacts[i]];
    double sign = 1;
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& J = sideJacobian(c, t, &sign);
    out.noalias() += sign * J.transpose() * impulse(i, c);
  }
}

// ν = ν_f + M⁻¹ Gᵀ β: the tree's velocity under the rows' impulses β from ν_f (by default the
// velocity before the impulses; dnu: scratch).
void velocityOfImpulses(SolverTree& T, const TreeNewton& N, Eigen::VectorXd& dnu,
                        const Eigen::VectorXd* nu_f = nullptr) {
  dnu.noalias() = N.g.topRows(N.rows).transpose() * N.beta.head(N.rows);
  for (int q = 0; q < N.n_single; ++q)
    dnu[N.single[q].index] += N.single[q].sign * N.single[q].beta;
  T.factor.solveInPlace(dnu);
  T.nu = (nu_f ? *nu_f : T.nu_start) + dnu;
}

// Whether velocity v has more kinetic energy than the tree had before the impulses (beyond the
// products' round-off; Mv: scratch).
bool raisesEnergy(const SolverTree& T, const Eigen::VectorXd& v, Eigen::VectorXd& Mv) {
  Mv.noalias() = T.M.selfadjointView<Eigen::Lower>() * T.nu_start;
  const double before = T.nu_start.dot(Mv);
  Mv.noalias() = T.M.selfadjointView<Eigen::Lower>() * v;
  return v.dot(Mv) > before * (1 + 1e-9) + 1e-300;
}

// The stops' rows of tree T: one per finite limit.
int stopRowCount(const SolverTree& T) {
  int s = 0;
  for (const SolverTree::LimitRow& r : T.limits)
    s += (std::isfinite(r.lower) ? 1 : 0) + (std::isfinite(r.upper) ? 1 : 0);
  return s;
}

// The stops' rows: lower ≤ q + h ν_k ≤ upper, D = M_kk / ε (1/M_kk ≤ (M⁻¹)_kk: at least as
// stiff), each started from its impulses `lower` and `upper` (the last step's, or the sweeps').
// A joint already past a stop is held there (ν_k ≥ 0 away from it), as a contact's overlap is:
// the position correction brings it back. So ν = 0 meets every row.
void setStopRows(const SolverSettings& st, const SolverTree& T, double SolverTree::LimitRow::*lower,
                 double SolverTree::LimitRow::*upper, TreeNewton& N) {
  int j = 0;
  for (const SolverTree::LimitRow& r : T.limits) {
    const double D = T.M(r.index, r.index) / kCompliance;
    if (std::isfinite(r.lower))
      N.single[j++] = {r.index, 1.0, std::min(0.0, (r.lower - r.q) / st.h), D,
                       std::max(0.0, r.*lower)};
    if (std::isfinite(r.upper))
      N.single[j++] = {r.index, -1.0, std::min(0.0, (r.q - r.upper) / st.h), D,
                       std::max(0.0, -(r.*upper))};
  }
}

// The stops' impulses from their rows, signed (y_lower ≥ 0, y_upper ≤ 0).
void takeStopImpulses(const TreeNewton& N, SolverTree& T) {
  int j = 0;
  for (SolverTree::LimitRow& r : T.limits) {
    r.y_lower = std::isfinite(r.lower) ? N.single[j++].beta : 0.0;
    r.y_upper = std::isfinite(r.upper) ? -N.single[j++].beta : 0.0;
  }
}

}  // namespace

Eigen::Vector4d pyramidEdges(double lambda_n, const Eigen::Vector2d& lambda_t, double mu,
                             double share) {
  // The pair of edges along t_e carries s_e ≥ |λ_te| / μ of λ_n (s_1 + s_2 = λ_n), its two
  // edges (s_e ± λ_te / μ) / 2. The last solve's s_1 keeps an edge it left at zero at zero,
  // not loaded by a share of the slack, and so inactive: the Newton steps start at the last
  // step's active rows, and its targets, shifted by the impulses, at the last step's
  // (doc/decisions.md#a-resting-trees-warm-start). Friction outside the pyramid
  // (|λ_t1| + |λ_t2| > μ λ_n: the tangents turned since) is scaled onto it.
  const double ln = lambda_n;
  double a = lambda_t[0] / mu, b = lambda_t[1] / mu;
  const double l1 = std::abs(a) + std::abs(b);
  if (l1 > ln) {
    const double f = l1 > 0 ? ln / l1 : 0.0;
    a *= f;
    b *= f;
  }
  const double tiny = kSplitRounding * ln;
  const double s1 = share >= std::abs(a) - tiny && share <= ln - std::abs(b) + tiny  // NaN: no
                        ? std::clamp(share, std::abs(a), std::max(std::abs(a), ln - std::abs(b)))
                        : std::abs(a) + 0.5 * std::max(0.0, ln - std::abs(a) - std::abs(b));
  const double s2 = std::max(0.0, ln - s1);
  const auto edge = [tiny](double x) { return x > tiny ? x : 0.0; };
  return {edge(0.5 * (s1 + a)), edge(0.5 * (s1 - a)), edge(0.5 * (s2 + b)), edge(0.5 * (s2 - b))};
}

int solveRestingTree(const SolverSettings& st, std::vector<SolverTree>& trees,
                     std::vector<ContactRow>& rows, SolverWork& work, const SolverWork::Island& I) {
  if (!eligible(st, trees, rows, work, I)) return -1;
  const int t = work.island_tree[I.first_tree];
  SolverTree& T = trees[t];
  const int nv = static_cast<int>(T.nu.size());
  SolverWork::RestingTree& R = work.resting_tree;
  R.contacts.clear();
  int m = 0;
  detail::forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {
    R.contacts.push_back(static_cast<int>(k));
    m += c.mu > 0 ? 4 : 1;
  });
  const int s = stopRowCount(T);
  TreeNewton& N = R.newton;
  N.resize(m, s, nv);
  // The contacts' rows: the normal, or the pyramid's four edges d = n ± μ t, each on d·u ≥
  // target, with D = 1 / (ε dᵀ K d), K = J M⁻¹ Jᵀ the point's response.
  int i = 0;
  for (const int k : R.contacts) {
    const ContactRow& c = rows[k];
    double sign = 1;
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& J = sideJacobian(c, t, &sign);
    const Eigen::Matrix3d& K = c.ta == t ? c.ka : c.kb;
    const auto addRow = [&](const Eigen::Vector3d& d) {
      N.g.row(i).noalias() = sign * d.transpose() * J;
      N.r[i] = c.target;
      N.D[i] = 1.0 / (kCompliance * std::max(d.dot(K * d), 1e-300));
      ++i;
    };
    // The warm start: the last step's impulses on the rows, so that they give back its λ_n and
    // λ_t (a resting tree then starts at its last answer), on a contact's edges as this solve
    // left them (pyramidEdges).
    const double ln = std::max(0.0, c.lambda_n);
    if (c.mu > 0) {
      N.beta.segment<4>(i) = pyramidEdges(ln, c.lambda_t, c.mu, c.pyramid_share);
      addRow(c.n + c.mu * c.t1);
      addRow(c.n - c.mu * c.t1);
      addRow(c.n + c.mu * c.t2);
      addRow(c.n - c.mu * c.t2);
    } else {
      N.beta[i] = ln;
      addRow(c.n);
    }
  }
  // The stops, from the last step's impulses: ν = 0 meets every row, so the rows can all hold
  // and the solve never raises the energy (a projection onto a set holding 0).
  setStopRows(st, T, &SolverTree::LimitRow::y_lower_last, &SolverTree::LimitRow::y_upper_last, N);
  // The start: ν from the warm start's impulses, the stops' included (the sweeps' warm start
  // leaves them out), so that a tree at rest starts at its solution.
  R.nu_warm = T.nu;
  velocityOfImpulses(T, N, R.dnu);
  int steps = N.solve(T.M, T.nu_start, T.nu, kNewtonTolerance, kMaxNewtonSteps, kMaxRounds);
  // ν from the impulses, M (ν − ν_f) = Gᵀ β exactly: the tree's momentum changes by its
  // contacts' impulses to round-off (the step's guard checks it), at the price of the
  // minimiser's residual, round-off too.
  if (steps >= 0) velocityOfImpulses(T, N, R.dnu);
  // A solve that reached its minimiser never raises the kinetic energy (every target ≤ 0: a
  // projection in the metric of M onto a convex set holding ν = 0); one that did not is
  // refused, and the sweeps take the island.
  if (steps >= 0 && raisesEnergy(T, T.nu, R.dnu)) steps = -1;
  if (steps < 0) {
    T.nu = R.nu_warm;
    return -1;
  }
  // The impulses: a contact's normal is the sum of its edges', its friction μ times their
  // differences along t1 and t2; a stop's is its row's, signed.
  i = 0;
  for (const int k : R.contacts) {
    ContactRow& c = rows[k];
    if (c.mu > 0) {
      const double* b = N.beta.data() + i;
      c.lambda_n = b[0] + b[1] + b[2] + b[3];
      c.lambda_t = {c.mu * (b[0] - b[1]), c.mu * (b[2] - b[3])};
      c.pyramid_share = b[0] + b[1];
      i += 4;
    } else {
      c.lambda_n = N.beta[i++];
      c.lambda_t.setZero();
    }
  }
  takeStopImpulses(N, T);
  return steps;
}

bool correctTreePositions(const SolverSettings& st, std::vector<SolverTree>& trees,
                          std::vector<ContactRow>& rows, SolverWork& work,
                          const SolverWork::Island& I) {
  if (I.trees != 1 || I.bodies != 0 || st.model.compliant()) return false;
  const int t = work.island_tree[I.first_tree];
  SolverTree& T = trees[t];
  const int nv = static_cast<int>(T.nu.size());
  SolverWork::RestingTree& R = work.resting_tree;
  R.contacts.clear();
  bool ok = true;
  detail::forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {
    ok = ok && (c.ta == t) != (c.tb == t) && !c.compliant;
    R.contacts.push_back(static_cast<int>(k));
  });
  if (!ok) return false;
  const int m = static_cast<int>(R.contacts.size());
  const int s = stopRowCount(T);
  TreeNewton& N = R.newton;
  N.resize(m, s, nv);
  // Each contact's normal: its bias where it overlaps beyond the slop, else not pushed in.
  for (int i = 0; i < m; ++i) {
    const ContactRow& c = rows[R.contacts[i]];
    double sign = 1;
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& J = sideJacobian(c, t, &sign);
    N.g.row(i).noalias() = sign * c.n.transpose() * J;
    N.r[i] = std::max(0.0, c.bias);
    N.D[i] = 1.0 / (kCompliance * std::max(c.k_nn, 1e-300));
    N.beta[i] = 0.0;
  }
  // The stops: q + h (ν_k + pν_k) within them.
  int j = 0;
  for (const SolverTree::LimitRow& r : T.limits) {
    const double D = T.M(r.index, r.index) / kCompliance;
    const double v = T.nu[r.index];
    if (std::isfinite(r.lower)) N.single[j++] = {r.index, 1.0, (r.lower - r.q) / st.h - v, D, 0.0};
    if (std::isfinite(r.upper)) N.single[j++] = {r.index, -1.0, v - (r.upper - r.q) / st.h, D, 0.0};
  }
  R.nu_warm.setZero(nv);
  T.pnu.setZero(nv);
  const int steps = N.solve(T.M, R.nu_warm, T.pnu, kNewtonTolerance, kMaxNewtonSteps, kMaxRounds);
  if (steps < 0) {
    T.pnu.setZero(nv);
    return false;
  }
  R.dnu.noalias() = N.g.topRows(m).transpose() * N.beta.head(m);
  for (int q = 0; q < s; ++q) R.dnu[N.single[q].index] += N.single[q].sign * N.single[q].beta;
  T.factor.solveInPlace(R.dnu);
  T.pnu = R.dnu;
  for (int i = 0; i < m; ++i) rows[R.contacts[i]].lambda_p = N.beta[i];
  j = 0;
  for (SolverTree::LimitRow& r : T.limits) {
    r.p_lower = std::isfinite(r.lower) ? N.single[j++].beta : 0.0;
    r.p_upper = std::isfinite(r.upper) ? -N.single[j++].beta : 0.0;
  }
  return true;
}

bool polishTreeNormals(const SolverSettings& st, std::vector<SolverTree>& trees,
                       std::vector<ContactRow>& rows, SolverWork& work,
                       const SolverWork::Island& I) {
  if (st.resting_tree_speed <= 0 || I.trees != 1 || I.bodies != 0 || patchResistance(st.model) ||
      st.model.compliant())
    return false;
  const int t = work.island_tree[I.first_tree];
  SolverTree& T = trees[t];
  SolverWork::RestingTree& R = work.resting_tree;
  R.contacts.clear();
  bool ok = true;
  double sink = 0.0;  // the fastest approach past a contact's target the sweeps left
  detail::forRows(work, rows, I, [&](std::size_t k, ContactRow& c) {
    if (!ok) return;
    ok = (c.ta == t) != (c.tb == t) && !c.compliant && c.impact == 0.0 && c.target_t.isZero(0.0);
    sink = std::max(sink, c.target - c.n.dot(detail::treeVelocity<&SolverTree::nu>(trees, c)));
    R.contacts.push_back(static_cast<int>(k));
  });
  if (!ok || !(sink > st.tree_sink_speed)) return false;
  const int nv = static_cast<int>(T.nu.size());
  const int m = static_cast<int>(R.contacts.size());
  const int s = stopRowCount(T);
  TreeNewton& N = R.newton;
  N.resize(m, s, nv);
  // The rows: each contact's normal, g ν ≥ target, from the sweeps' λ_n; the stops as in the
  // resting solve, from the sweeps' impulses.
  Eigen::VectorXd& held = R.held_friction;      // per contact its λ_t, held through a round
  if (held.size() < 2 * m) held.resize(2 * m);  // (grows only: no allocation in most steps)
  for (int i = 0; i < m; ++i) {
    const ContactRow& c = rows[R.contacts[i]];
    double sign = 1;
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& J = sideJacobian(c, t, &sign);
    N.g.row(i).noalias() = sign * c.n.transpose() * J;
    N.r[i] = c.target;
    N.D[i] = 1.0 / (kCompliance * std::max(c.k_nn, 1e-300));
    N.beta[i] = std::max(0.0, c.lambda_n);
    held.segment<2>(2 * i) = c.lambda_t;
  }
  setStopRows(st, T, &SolverTree::LimitRow::y_lower, &SolverTree::LimitRow::y_upper, N);
  R.nu_warm = T.nu;
  // Rounds: the normals and stops solved with the friction held, ν_f = ν_start + M⁻¹ Σ J_tᵀ λ_t;
  // then the friction kept within μ λ_n of the new normals; again while that changed it.
  for (int round = 0; round < kPolishRounds; ++round) {
    R.dnu.setZero(nv);
    addContactImpulses(rows, R.contacts, t, R.dnu, [&](int i, const ContactRow& c) {
      return Eigen::Vector3d(held[2 * i] * c.t1 + held[2 * i + 1] * c.t2);
    });
    T.factor.solveInPlace(R.dnu);
    R.nu_f = T.nu_start + R.dnu;
    velocityOfImpulses(T, N, R.dnu, &R.nu_f);
    if (N.solve(T.M, R.nu_f, T.nu, kNewtonTolerance, kMaxNewtonSteps, kMaxRounds) < 0) {
      T.nu = R.nu_warm;
      return false;
    }
    double clamped = 0.0;
    for (int i = 0; i < m; ++i) {
      const double tn = held.segment<2>(2 * i).norm(), tmax = rows[R.contacts[i]].mu * N.beta[i];
      if (tn > tmax) {
        clamped = std::max(clamped, tn - tmax);
        held.segment<2>(2 * i) *= tmax / tn;
      }
    }
    if (clamped == 0.0) break;
  }
  // ν from every impulse (the normals solved, the friction held, the stops), so that the
  // tree's momentum changes by its contacts' impulses exactly.
  R.dnu.setZero(nv);
  addContactImpulses(rows, R.contacts, t, R.dnu, [&](int i, const ContactRow& c) {
    return Eigen::Vector3d(N.beta[i] * c.n + held[2 * i] * c.t1 + held[2 * i + 1] * c.t2);
  });
  for (int q = 0; q < s; ++q) R.dnu[N.single[q].index] += N.single[q].sign * N.single[q].beta;
  T.factor.solveInPlace(R.dnu);
  R.nu_f = T.nu_start + R.dnu;
  // It must leave no contact approaching faster than the sweeps did (friction still cut after
  // the last round can: the sweeps' answer then stands).
  double sink_after = 0.0;
  for (int i = 0; i < m; ++i) {
    const ContactRow& c = rows[R.contacts[i]];
    double sign = 1;
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& J = sideJacobian(c, t, &sign);
    sink_after = std::max(sink_after, c.target - sign * c.n.dot(J * R.nu_f));
  }
  if (!(sink_after < sink)) {
    T.nu = R.nu_warm;
    return false;
  }
  // Not above the energy before the impulses (a projection onto a set holding ν = 0 cannot
  // be; friction held from the sweeps and then clamped could): else the sweeps' answer stands.
  if (raisesEnergy(T, R.nu_f, R.dnu)) {
    T.nu = R.nu_warm;
    return false;
  }
  T.nu = R.nu_f;
  for (int i = 0; i < m; ++i) {
    ContactRow& c = rows[R.contacts[i]];
    c.lambda_n = N.beta[i];
    c.lambda_t = held.segment<2>(2 * i);
  }
  takeStopImpulses(N, T);
  return true;
}

}  // namespace sim
}  // namespace cga_rigid_sim
