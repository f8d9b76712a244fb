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
  os << " q0";
  for (double v : c.q0) os << "," << v;
  os << " qd0";
  for (double v : c.qd0) os << "," << v;
  return os.str();
}

}  // namespace

ReferenceRun integrateReference(const ArticulatedCase& c, double h_in, Rhs rhs) {
  const int n = c.n();
  const long N = std::lround(c.T / h_in);
  const LD h = LD(c.T) / LD(N);
  VX y(2 * n);
  for (int i = 0; i < n; ++i) {
    y(i) = c.q0[i];
    y(n + i) = c.qd0[i];
  }
  auto f = [&](const VX& s) {
    VX d(2 * n);
    d.head(n) = s.tail(n);
    d.tail(n) = rhs == Rhs::kLagrangeDoublePendulum
                    ? lagrangeDoublePendulum(c, s.data(), s.data() + n)
                    : forwardDynamics<LD>(c, s.data(), s.data() + n);
    return d;
  };
  ReferenceRun run;
  run.q_min.assign(c.q0.begin(), c.q0.end());
  run.q_max = run.q_min;
  const EnergyMeter<LD> energy_of(c);
  const LD E0 = energy_of(y.data(), y.data() + n);
  const long every = std::max(1L, N / 20000);  // energy sampled ~20000 times
  for (long k = 1; k <= N; ++k) {
    const VX k1 = f(y);
    const VX k2 = f(y + (h / 2) * k1);
    const VX k3 = f(y + (h / 2) * k2);
    const VX k4 = f(y + h * k3);
    y += (h / 6) * (k1 + 2 * k2 + 2 * k3 + k4);
    for (int i = 0; i < n; ++i) {
      run.q_min[i] = std::min(run.q_min[i], double(y(i)));
      run.q_max[i] = std::max(run.q_max[i], double(y(i)));
    }
    if (k % every == 0 || k == N) {
      const LD E = energy_of(y.data(), y.data() + n);
      run.max_energy_drift_rel =
          std::max(run.max_energy_drift_rel, std::fabs(E - E0) / std::fabs(E0));
    }
  }
  run.q.assign(y.data(), y.data() + n);
  run.qd.assign(y.data() + n, y.data() + 2 * n);
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
      int got = 0;
      while (std::getline(in, line)) {
        int i = 0;
        double q = 0, qd = 0;
        if (std::sscanf(line.c_str(), "%d,%lf,%lf", &i, &q, &qd) == 3 && i >= 0 && i < n) {
          ref.q[i] = q;
          ref.qd[i] = qd;
          ++got;
        }
      }
      if (got == n) return ref;
    }
  }
  std::fprintf(stderr, "[reference] %s: RK4 in long double, h = %g, %ld steps ...\n",
               c.name.c_str(), kReferenceStep, std::lround(c.T / kReferenceStep));
  const ReferenceRun run = integrateReference(c, kReferenceStep);
  ref.q.assign(run.q.begin(), run.q.end());
  ref.qd.assign(run.qd.begin(), run.qd.end());
  FILE* f = std::fopen(path.c_str(), "w");
  if (f) {
    std::fprintf(f, "# %s\njoint,q,qd\n", key.c_str());
    for (int i = 0; i < n; ++i) std::fprintf(f, "%d,%.17g,%.17g\n", i, ref.q[i], ref.qd[i]);
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

}  // namespace articulated
}  // namespace bench
