#include "contact_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cga_rigid_sim {
namespace sim {
namespace {

Eigen::Matrix3d cross(const Eigen::Vector3d& r) {
  Eigen::Matrix3d m;
  m << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return m;
}

// The velocity of body slot s at arm r (zero for an immovable one or a tree side).
Eigen::Vector3d pointVelocity(const std::vector<SolverBody>& bodies, int s,
                              const Eigen::Vector3d& r) {
  if (s < 0) return Eigen::Vector3d::Zero();
  return bodies[s].v + bodies[s].w.cross(r);
}

// u = J ν of the contact's tree sides (ν or, for the position correction, pν).
template <Eigen::VectorXd SolverTree::*Nu>
Eigen::Vector3d treeVelocity(const std::vector<SolverTree>& trees, const ContactRow& c) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  if (c.ta >= 0) u.noalias() += c.ja * (trees[c.ta].*Nu);
  if (c.tb >= 0) u.noalias() -= c.jb * (trees[c.tb].*Nu);
  return u;
}

Eigen::Vector3d relativeVelocity(const std::vector<SolverBody>& bodies,
                                 const std::vector<SolverTree>& trees, const ContactRow& c) {
  Eigen::Vector3d u = pointVelocity(bodies, c.a, c.ra) - pointVelocity(bodies, c.b, c.rb);
  if (c.ta >= 0 || c.tb >= 0) u += treeVelocity<&SolverTree::nu>(trees, c);
  return u;
}

// The impulse P (world axes) at the contact, +P on a and −P on b, added to the velocities
// (v, w, ν) or, for the position correction, to the pseudo-velocities (pv, pw, pν).
template <Eigen::Vector3d SolverBody::*V, Eigen::Vector3d SolverBody::*W,
          Eigen::VectorXd SolverTree::*Nu>
void applyTo(std::vector<SolverBody>& bodies, std::vector<SolverTree>& trees, const ContactRow& c,
             const Eigen::Vector3d& P) {
  for (int side = 0; side < 2; ++side) {
    const int s = side ? c.b : c.a;
    if (s < 0) continue;
    SolverBody& body = bodies[s];
    const Eigen::Vector3d Ps = side ? Eigen::Vector3d(-P) : P;
    body.*V += body.inv_mass * Ps;
    body.*W += body.inv_inertia * (side ? c.rb : c.ra).cross(Ps);
  }
  if (c.ta >= 0) (trees[c.ta].*Nu).noalias() += c.wa * P;
  if (c.tb >= 0) (trees[c.tb].*Nu).noalias() -= c.wb * P;
}

void applyImpulse(std::vector<SolverBody>& bodies, std::vector<SolverTree>& trees,
                  const ContactRow& c, const Eigen::Vector3d& P) {
  applyTo<&SolverBody::v, &SolverBody::w, &SolverTree::nu>(bodies, trees, c, P);
}

void applyPseudo(std::vector<SolverBody>& bodies, std::vector<SolverTree>& trees,
                 const ContactRow& c, const Eigen::Vector3d& P) {
  applyTo<&SolverBody::pv, &SolverBody::pw, &SolverTree::pnu>(bodies, trees, c, P);
}

// The Jacobian of world point p on body b of tree T: column j is the point's velocity under a
// unit rate of coordinate j, v_o + ω × p, for the coordinates that move b (the joints on its
// path to the base, and the base's six).
void pointJacobian(const SolverTree& T, int b, const Eigen::Vector3d& p,
                   Eigen::Matrix<double, 3, Eigen::Dynamic>& J) {
  J.setZero(3, T.twist.cols());
  const auto column = [&](int j) {
    J.col(j) = T.twist.col(j).tail<3>() + T.twist.col(j).head<3>().cross(p);
  };
  const int base = T.floating ? 6 : 0;
  for (int x = b; x > 0; x = T.parent[x]) column(base + x - 1);
  for (int j = 0; j < base; ++j) column(j);
}

// A tangent basis of the plane ⟂ n (any; the friction cone is circular).
void tangents(const Eigen::Vector3d& n, Eigen::Vector3d& t1, Eigen::Vector3d& t2) {
  const Eigen::Vector3d ref =
      std::abs(n.x()) < 0.57735 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  t1 = n.cross(ref).normalized();
  t2 = n.cross(t1);
}

// Each row's target from the velocities before any contact impulse.
void setTargets(const SolverSettings& st, const std::vector<SolverBody>& bodies,
                const std::vector<SolverTree>& trees, bool bounce, std::vector<ContactRow>& rows) {
  for (ContactRow& c : rows) {
    const double u_n = c.n.dot(relativeVelocity(bodies, trees, c));
    const double h = st.h;
    const double d = c.depth;
    c.impact = 0.0;
    // A gap may close, no more; a gap within round-off of contact is contact (targets of
    // ±1e-12 m / h under the four corners of a face would disagree, and Gauss–Seidel would
    // chase them for ever).
    double target = d >= -st.touching ? 0.0 : d / h;
    // An impact: the bodies approach faster than the resting threshold and touch within the
    // step. Newton's law sends them apart at e times the approach speed.
    if (bounce && c.restitution > 0 && u_n < -st.bounce_speed && (d > 0 || u_n * h < d)) {
      c.impact = -u_n;
      target = std::max(target, c.restitution * c.impact);
    }
    c.target = target;
  }
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
    // the velocity change at the point per unit impulse there.
    Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
    for (int side = 0; side < 2; ++side) {
      const int s = side ? c.b : c.a;
      if (s < 0) continue;
      const Eigen::Matrix3d R = cross(side ? c.rb : c.ra);
      K += bodies[s].inv_mass * Eigen::Matrix3d::Identity() - R * bodies[s].inv_inertia * R;
    }
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
    const Eigen::Matrix3d Kc = B.transpose() * K * B;
    c.k_n = K * c.n;
    // A free body's K is positive definite; a tree side's J M⁻¹ Jᵀ has the rank of the motions
    // the link can make at the point (one for a pendulum's bob): directions it cannot move in
    // get no impulse (their inverse is taken as zero, their k as infinite), and an impulse
    // that could only act along them is none. Round-off decides below 1e-12 of K's trace.
    const double cutoff = 1e-12 * K.trace();
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
    c.mu = ct.mu;
    c.restitution = ct.restitution;
    c.depth = ct.depth;
    c.lambda_p = 0.0;
  }
}

double kineticEnergy(const std::vector<SolverBody>& bodies, const std::vector<SolverTree>& trees) {
  double T = 0.0;
  for (const SolverBody& b : bodies)
    T += 0.5 * (b.mass * b.v.squaredNorm() + b.w.dot(b.inertia * b.w));
  for (const SolverTree& t : trees) T += 0.5 * t.nu.dot(t.M.selfadjointView<Eigen::Lower>() * t.nu);
  return T;
}

SolveStats solveVelocities(const SolverSettings& st, std::vector<SolverBody>& bodies,
                           std::vector<SolverTree>& trees, std::vector<ContactRow>& rows) {
  SolveStats stats;
  // The velocities before any contact impulse: the warm start is applied after the targets
  // are read from them.
  for (SolverBody& b : bodies) {
    b.v_start = b.v;
    b.w_start = b.w;
  }
  for (SolverTree& t : trees) t.nu_start = t.nu;
  stats.kinetic_before = kineticEnergy(bodies, trees);
  for (SolverBody& b : bodies) b.reach = 0.0;
  for (const ContactRow& c : rows) {
    if (c.a >= 0) bodies[c.a].reach = std::max(bodies[c.a].reach, c.ra.norm());
    if (c.b >= 0) bodies[c.b].reach = std::max(bodies[c.b].reach, c.rb.norm());
  }
  double speed = 0.0;  // the fastest contact point's speed before the impulses
  for (const SolverBody& b : bodies) speed = std::max(speed, b.v.norm() + b.reach * b.w.norm());
  for (const ContactRow& c : rows)
    if (c.ta >= 0 || c.tb >= 0)
      speed = std::max(speed, treeVelocity<&SolverTree::nu>(trees, c).norm());
  const double tolerance = st.tolerance + st.tolerance_of_kick * st.kick +
                           st.tolerance_of_speed * std::max(0.0, speed - 2.0 * st.kick);

  for (int attempt = 0; attempt < 2; ++attempt) {
    const bool bounce = attempt == 0;
    if (!bounce) {  // start again from the velocities before the contacts, cold
      for (SolverBody& b : bodies) {
        b.v = b.v_start;
        b.w = b.w_start;
      }
      for (SolverTree& t : trees) t.nu = t.nu_start;
      for (ContactRow& c : rows) {
        c.lambda_n = 0.0;
        c.lambda_t.setZero();
      }
    }
    setTargets(st, bodies, trees, bounce, rows);
    for (ContactRow& c : rows) {  // warm start, inside the cone
      c.lambda_n = std::max(0.0, c.lambda_n);
      const double tmax = c.mu * c.lambda_n, t = c.lambda_t.norm();
      if (t > tmax) c.lambda_t *= t > 0 ? tmax / t : 0.0;
      applyImpulse(bodies, trees, c,
                   c.lambda_n * c.n + c.lambda_t.x() * c.t1 + c.lambda_t.y() * c.t2);
    }
    int it = 0;
    for (; it < st.max_iterations; ++it) {
      for (SolverBody& b : bodies) {
        b.v_sweep = b.v;
        b.w_sweep = b.w;
      }
      for (SolverTree& t : trees) t.nu_sweep = t.nu;
      for (ContactRow& c : rows) {
        // Normal: the impulse that brings u_n to its target, kept ≥ 0.
        Eigen::Vector3d u = relativeVelocity(bodies, trees, c);
        const double ln = std::max(0.0, c.lambda_n + (c.target - c.n.dot(u)) / c.k_nn);
        const double dn = ln - c.lambda_n;
        c.lambda_n = ln;
        u += dn * c.k_n;  // the velocity after it, without applying it yet
        // Friction: the impulse that stops the sliding, projected onto the cone's disc.
        const Eigen::Vector2d u_t(c.t1.dot(u), c.t2.dot(u));
        const double tmax = c.mu * c.lambda_n;
        Eigen::Vector2d lt = c.lambda_t - c.k_tt_inv * u_t;  // sticks, if the cone allows
        if (lt.norm() > tmax) {                              // slides
          lt = c.lambda_t - u_t / c.k_t;
          const double t = lt.norm();
          if (t > tmax) lt *= t > 0 ? tmax / t : 0.0;
        }
        const Eigen::Vector2d dt = lt - c.lambda_t;
        c.lambda_t = lt;
        // Both at once: one application per contact and sweep.
        if (dn != 0.0 || !dt.isZero(0.0))
          applyImpulse(bodies, trees, c, dn * c.n + dt.x() * c.t1 + dt.y() * c.t2);
      }
      double change = 0.0;
      for (const SolverBody& b : bodies)
        change = std::max(change, (b.v - b.v_sweep).norm() + b.reach * (b.w - b.w_sweep).norm());
      // A tree's change as its contact points see it.
      for (SolverTree& t : trees) t.nu_sweep = t.nu - t.nu_sweep;
      for (const ContactRow& c : rows)
        if (c.ta >= 0 || c.tb >= 0)
          change = std::max(change, treeVelocity<&SolverTree::nu_sweep>(trees, c).norm());
      if (change < tolerance) {
        ++it;
        break;
      }
    }
    stats.iterations += it;
    stats.kinetic_after = kineticEnergy(bodies, trees);
    bool any_bounce = false;
    for (const ContactRow& c : rows) any_bounce = any_bounce || c.impact > 0;
    // The energy guard: restitution in several simultaneous impacts can add energy; e = 0
    // cannot (doc/contacts.md#energy).
    if (!any_bounce || stats.kinetic_after <= stats.kinetic_before * (1 + 1e-12) + 1e-300) break;
  }
  return stats;
}

void solvePositions(const SolverSettings& st, std::vector<SolverBody>& bodies,
                    std::vector<SolverTree>& trees, std::vector<ContactRow>& rows) {
  for (SolverTree& t : trees) t.pnu.setZero(t.nu.size());
  double max_bias = 0.0;
  for (ContactRow& c : rows) {
    c.bias = c.depth > st.slop ? st.correction * (c.depth - st.slop) / st.h : 0.0;
    c.lambda_p = 0.0;
    max_bias = std::max(max_bias, c.bias);
  }
  if (max_bias == 0.0) return;
  for (int it = 0; it < st.position_iterations; ++it) {
    for (SolverBody& b : bodies) {
      b.v_sweep = b.pv;
      b.w_sweep = b.pw;
    }
    for (SolverTree& t : trees) t.pnu_sweep = t.pnu;
    for (ContactRow& c : rows) {
      if (c.bias <= 0 && c.lambda_p == 0.0) continue;
      const Eigen::Vector3d pa = c.a >= 0
                                     ? Eigen::Vector3d(bodies[c.a].pv + bodies[c.a].pw.cross(c.ra))
                                     : Eigen::Vector3d::Zero();
      const Eigen::Vector3d pb = c.b >= 0
                                     ? Eigen::Vector3d(bodies[c.b].pv + bodies[c.b].pw.cross(c.rb))
                                     : Eigen::Vector3d::Zero();
      double u = c.n.dot(pa - pb);
      if (c.ta >= 0 || c.tb >= 0) u += c.n.dot(treeVelocity<&SolverTree::pnu>(trees, c));
      const double lp = std::max(0.0, c.lambda_p + (c.bias - u) / c.k_nn);
      const double d = lp - c.lambda_p;
      c.lambda_p = lp;
      if (d != 0.0) applyPseudo(bodies, trees, c, d * c.n);
    }
    double change = 0.0;
    for (const SolverBody& b : bodies)
      change = std::max(change, (b.pv - b.v_sweep).norm() + b.reach * (b.pw - b.w_sweep).norm());
    for (SolverTree& t : trees) t.pnu_sweep = t.pnu - t.pnu_sweep;
    for (const ContactRow& c : rows)
      if (c.ta >= 0 || c.tb >= 0)
        change = std::max(change, treeVelocity<&SolverTree::pnu_sweep>(trees, c).norm());
    if (change < 1e-3 * max_bias) break;  // 0.1 % of the largest correction: plenty
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
