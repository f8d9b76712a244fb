#include "articulated_reference.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

namespace bench {
namespace articulated {
namespace {

using LD = long double;
using VX = Eigen::Matrix<LD, Eigen::Dynamic, 1>;

// Double pendulum of two equal rods, Lagrange's equations in absolute angles th1 = q1,
// th2 = q1 + q2 (from hanging down, about +y): with a = CoM distance from the joint, l = rod
// length, I = moment about the CoM across the rod,
//   M11 = m a^2 + I + m l^2,  M22 = m a^2 + I,  M12 = m l a cos(th1 - th2),
//   M11 th1'' + M12 th2'' + m l a sin(th1 - th2) th2'^2 + m (a + l) g sin th1 = 0,
//   M12 th1'' + M22 th2'' - m l a sin(th1 - th2) th1'^2 + m a g sin th2 = 0.
VX lagrangeDoublePendulum(const ArticulatedCase& c, const LD* q, const LD* qd) {
  const JointSpec& j = c.joints[0];
  const LD m = j.mass, a = -LD(j.com[2]), l = -LD(c.joints[1].origin_xyz[2]);
  const LD I = j.inertia_diag[1], g = -LD(c.gravity[2]);
  const LD th1 = q[0], th2 = q[0] + q[1], w1 = qd[0], w2 = qd[0] + qd[1];
  const LD d = th1 - th2;
  const LD M11 = m * a * a + I + m * l * l, M22 = m * a * a + I, M12 = m * l * a * std::cos(d);
  const LD r1 = -(m * l * a * std::sin(d) * w2 * w2 + m * (a + l) * g * std::sin(th1));
  const LD r2 = -(-m * l * a * std::sin(d) * w1 * w1 + m * a * g * std::sin(th2));
  const LD det = M11 * M22 - M12 * M12;
  const LD a1 = (M22 * r1 - M12 * r2) / det, a2 = (M11 * r2 - M12 * r1) / det;
  VX out(2);
  out << a1, a2 - a1;
  return out;
}

std::string cacheKey(const ArticulatedCase& c) {
  std::ostringstream os;
  os.precision(17);
  os << "rk4-longdouble-generic h=" << kReferenceStep << " T=" << c.T << " g=" << c.gravity[0]
     << "," << c.gravity[1] << "," << c.gravity[2];
  for (const JointSpec& j : c.joints) {
    os << " [" << j.parent;
    for (double v : j.origin_xyz) os << "," << v;
    for (double v : j.origin_R) os << "," << v;
    for (double v : j.axis) os << "," << v;
    os << "," << j.mass;
    for (double v : j.com) os << "," << v;
    for (double v : j.inertia_diag) os << "," << v;
    os << "]";
  }
  if (c.base.floating) {
    os << " base " << c.base.mass;
    for (double v : c.base.com) os << "," << v;
    for (double v : c.base.inertia_diag) os << "," << v;
    for (double v : c.base.w0) os << "," << v;
    for (double v : c.base.v0) os << "," << v;
  }
  os << " q0";
  for (double v : c.q0) os << "," << v;
  os << " qd0";
  for (double v : c.qd0) os << "," << v;
  return os.str();
}

}  // namespace

ReferenceRun integrateReference(const ArticulatedCase& c, double h_in, Rhs rhs) {
  using V3 = Eigen::Matrix<LD, 3, 1>;
  const int n = c.n();
  const bool fl = c.base.floating;
  // Layout: fixed (q, qd); floating (p_b, quat_b (w, x, y, z), q, v_b, w_b, qd).
  const int np = fl ? 7 + n : n, nv = fl ? 6 + n : n, oq = fl ? 7 : 0;
  const long N = std::lround(c.T / h_in);
  const LD h = LD(c.T) / LD(N);
  VX y = VX::Zero(np + nv);
  if (fl) {
    y(3) = 1;
    for (int i = 0; i < 3; ++i) {
      y(np + i) = c.base.v0[i];
      y(np + 3 + i) = c.base.w0[i];
    }
  }
  for (int i = 0; i < n; ++i) {
    y(oq + i) = c.q0[i];
    y(np + nv - n + i) = c.qd0[i];
  }
  auto baseOf = [&](const VX& s) {
    BaseState<LD> b;
    if (fl) {
      const Eigen::Quaternion<LD> qb(s(3), s(4), s(5), s(6));
      b.R = qb.toRotationMatrix();
      b.p = s.head(3);
      b.v = s.segment(np, 3);
      b.w = s.segment(np + 3, 3);
    }
    return b;
  };
  auto f = [&](const VX& s) {
    VX d(np + nv);
    const LD* q = s.data() + oq;
    const LD* qd = s.data() + np + nv - n;
    if (fl) {
      const V3 w = s.segment(np + 3, 3);
      const LD qw = s(3), qx = s(4), qy = s(5), qz = s(6);
      d.head(3) = s.segment(np, 3);
      // (0, w) * (qw, qx, qy, qz) / 2: w in world axes multiplies from the left.
      d(3) = LD(0.5) * (-w(0) * qx - w(1) * qy - w(2) * qz);
      d(4) = LD(0.5) * (w(0) * qw + w(1) * qz - w(2) * qy);
      d(5) = LD(0.5) * (w(1) * qw + w(2) * qx - w(0) * qz);
      d(6) = LD(0.5) * (w(2) * qw + w(0) * qy - w(1) * qx);
    }
    d.segment(oq, n) = s.tail(n);
    d.tail(nv) = rhs == Rhs::kLagrangeDoublePendulum ? lagrangeDoublePendulum(c, q, qd)
                                                     : forwardDynamics<LD>(c, baseOf(s), q, qd);
    return d;
  };
  ReferenceRun run;
  run.q_min.assign(c.q0.begin(), c.q0.end());
  run.q_max = run.q_min;
  const EnergyMeter<LD> energy_of(c);
  auto energyOf = [&](const VX& s) {
    return energy_of(baseOf(s), s.data() + oq, s.data() + np + nv - n);
  };
  const LD E0 = energyOf(y);
  const long every = std::max(1L, N / 20000);  // energy sampled ~20000 times
  for (long k = 1; k <= N; ++k) {
    const VX k1 = f(y);
    const VX k2 = f(y + (h / 2) * k1);
    const VX k3 = f(y + (h / 2) * k2);
    const VX k4 = f(y + h * k3);
    y += (h / 6) * (k1 + 2 * k2 + 2 * k3 + k4);
    if (fl) y.segment(3, 4).normalize();
    for (int i = 0; i < n; ++i) {
      run.q_min[i] = std::min(run.q_min[i], double(y(oq + i)));
      run.q_max[i] = std::max(run.q_max[i], double(y(oq + i)));
    }
    if (k % every == 0 || k == N) {
      const LD E = energyOf(y);
      run.max_energy_drift_rel =
          std::max(run.max_energy_drift_rel, std::fabs(E - E0) / std::fabs(E0));
    }
  }
  run.q.assign(y.data() + oq, y.data() + oq + n);
  run.qd.assign(y.data() + np + nv - n, y.data() + np + nv);
  run.base = baseOf(y);
  run.steps = N;
  return run;
}

ArticulatedReference articulatedReference(const ArticulatedCase& c, const std::string& out_dir) {
  ::mkdir(out_dir.c_str(), 0755);
  const std::string path = out_dir + "/reference_articulated_" + c.name + ".csv";
  const std::string key = cacheKey(c);
  const int n = c.n();
  ArticulatedReference ref;
  ref.E0 = energy(c, c.q0, c.qd0);
  {
    std::ifstream in(path);
    std::string line;
    if (std::getline(in, line) && line == "# " + key) {
      std::getline(in, line);  // header
      ref.q.resize(n);
      ref.qd.resize(n);
      int got = 0, base = 0;
      while (std::getline(in, line)) {
        int i = 0;
        double q = 0, qd = 0;
        auto& bq = ref.base_quat;
        auto &bp = ref.base_p, &bw = ref.base_w, &bv = ref.base_v;
        if (std::sscanf(line.c_str(), "base,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf",
                        &bq[0], &bq[1], &bq[2], &bq[3], &bp[0], &bp[1], &bp[2], &bw[0], &bw[1],
                        &bw[2], &bv[0], &bv[1], &bv[2]) == 13) {
          base = 1;
        } else if (std::sscanf(line.c_str(), "%d,%lf,%lf", &i, &q, &qd) == 3 && i >= 0 && i < n) {
          ref.q[i] = q;
          ref.qd[i] = qd;
          ++got;
        }
      }
      if (got == n && base == (c.base.floating ? 1 : 0)) return ref;
    }
  }
  std::fprintf(stderr, "[reference] %s: RK4 in long double, h = %g, %ld steps ...\n",
               c.name.c_str(), kReferenceStep, std::lround(c.T / kReferenceStep));
  const ReferenceRun run = integrateReference(c, kReferenceStep);
  ref.q.assign(run.q.begin(), run.q.end());
  ref.qd.assign(run.qd.begin(), run.qd.end());
  if (c.base.floating) {
    const Eigen::Quaternion<LD> qb(run.base.R);
    ref.base_quat = {double(qb.w()), double(qb.x()), double(qb.y()), double(qb.z())};
    for (int i = 0; i < 3; ++i) {
      ref.base_p[i] = double(run.base.p(i));
      ref.base_w[i] = double(run.base.w(i));
      ref.base_v[i] = double(run.base.v(i));
    }
  }
  FILE* f = std::fopen(path.c_str(), "w");
  if (f) {
    std::fprintf(f, "# %s\njoint,q,qd\n", key.c_str());
    for (int i = 0; i < n; ++i) std::fprintf(f, "%d,%.17g,%.17g\n", i, ref.q[i], ref.qd[i]);
    if (c.base.floating) {
      std::fprintf(f, "base");
      for (double v : ref.base_quat) std::fprintf(f, ",%.17g", v);
      for (const auto* a : {&ref.base_p, &ref.base_w, &ref.base_v})
        for (double v : *a) std::fprintf(f, ",%.17g", v);
      std::fprintf(f, "\n");
    }
    std::fclose(f);
  }
  return ref;
}

double jointPositionError(const std::vector<double>& q, const ArticulatedReference& ref) {
  double e = 0;
  for (size_t i = 0; i < ref.q.size(); ++i) {
    const double d = i < q.size() ? std::fabs(wrapAngle(q[i] - ref.q[i]))
                                  : std::numeric_limits<double>::infinity();
    e = std::isnan(d) ? d : std::max(e, d);
    if (std::isnan(e)) break;
  }
  return e;
}

double jointVelocityError(const std::vector<double>& qd, const ArticulatedReference& ref) {
  double e = 0;
  for (size_t i = 0; i < ref.qd.size(); ++i) {
    const double d =
        i < qd.size() ? std::fabs(qd[i] - ref.qd[i]) : std::numeric_limits<double>::infinity();
    e = std::isnan(d) ? d : std::max(e, d);
    if (std::isnan(e)) break;
  }
  return e;
}

double baseOrientationError(const Eigen::Matrix3d& R, const ArticulatedReference& ref) {
  const Eigen::Quaterniond qr(ref.base_quat[0], ref.base_quat[1], ref.base_quat[2],
                              ref.base_quat[3]);
  const Eigen::Quaterniond d(qr.toRotationMatrix().transpose() * R);
  return 2 * std::atan2(d.vec().norm(), std::fabs(d.w()));
}

double baseAngularVelocityError(const Eigen::Vector3d& w, const ArticulatedReference& ref) {
  return (w - Eigen::Vector3d(ref.base_w[0], ref.base_w[1], ref.base_w[2])).norm();
}

}  // namespace articulated
}  // namespace bench
