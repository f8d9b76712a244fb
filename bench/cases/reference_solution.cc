// See reference_solution.h for the method and its documented accuracy.
#include "reference_solution.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace bench {
namespace {

// Bump when the method changes so stale caches are recomputed.
const char* kMethodTag = "gbs16-increment-kahan-longdouble-v2";

constexpr int kN = 7;  // q(4), w_body(3)
constexpr int kLevels = 8;  // substep sequence n_j = 2 j, j = 1..8 -> order 16

template <class S>
struct Rhs {
  S J[3];
  S tau[3];  // world torque

  void operator()(const S* y, S* dy) const {
    const S qw = y[0], qx = y[1], qy = y[2], qz = y[3];
    const S wx = y[4], wy = y[5], wz = y[6];
    // dq = 1/2 q (x) (0, w)
    dy[0] = S(0.5) * (-qx * wx - qy * wy - qz * wz);
    dy[1] = S(0.5) * (qw * wx + qy * wz - qz * wy);
    dy[2] = S(0.5) * (qw * wy + qz * wx - qx * wz);
    dy[3] = S(0.5) * (qw * wz + qx * wy - qy * wx);
    // tau_body = R(q)^T tau, R from the homogeneous formula / |q|^2.
    S tb[3] = {0, 0, 0};
    if (tau[0] != 0 || tau[1] != 0 || tau[2] != 0) {
      const S n2 = qw * qw + qx * qx + qy * qy + qz * qz;
      const S s = S(2) / n2;
      const S R00 = 1 - s * (qy * qy + qz * qz), R01 = s * (qx * qy - qz * qw),
              R02 = s * (qx * qz + qy * qw);
      const S R10 = s * (qx * qy + qz * qw), R11 = 1 - s * (qx * qx + qz * qz),
              R12 = s * (qy * qz - qx * qw);
      const S R20 = s * (qx * qz - qy * qw), R21 = s * (qy * qz + qx * qw),
              R22 = 1 - s * (qx * qx + qy * qy);
      tb[0] = R00 * tau[0] + R10 * tau[1] + R20 * tau[2];
      tb[1] = R01 * tau[0] + R11 * tau[1] + R21 * tau[2];
      tb[2] = R02 * tau[0] + R12 * tau[1] + R22 * tau[2];
    }
    // J dw = (J w) x w + tau_body
    const S Lx = J[0] * wx, Ly = J[1] * wy, Lz = J[2] * wz;
    dy[4] = (Ly * wz - Lz * wy + tb[0]) / J[0];
    dy[5] = (Lz * wx - Lx * wz + tb[1]) / J[1];
    dy[6] = (Lx * wy - Ly * wx + tb[2]) / J[2];
  }
};

// One Gragg-Bulirsch-Stoer macro step of size H (in place). To keep roundoff
// small over ~1e5..1e6 macro steps, the modified-midpoint sequences and the
// Neville extrapolation work on the increment u = z - y (|u| ~ H |w|, so
// their rounding errors scale with the increment, not with |y| ~ 1), and the
// increment is added to y with Kahan-compensated summation (carry in c).
template <class S>
void gbsStep(const Rhs<S>& f, S* y, S* c, S H) {
  S T[kLevels][kN];
  S u0[kN], u1[kN], u2[kN], z[kN], dz[kN], f0[kN];
  f(y, f0);
  for (int j = 0; j < kLevels; ++j) {
    const int n = 2 * (j + 1);
    const S h = H / S(n);
    for (int i = 0; i < kN; ++i) {
      u0[i] = 0;
      u1[i] = h * f0[i];
    }
    for (int m = 1; m < n; ++m) {
      for (int i = 0; i < kN; ++i) z[i] = y[i] + u1[i];
      f(z, dz);
      for (int i = 0; i < kN; ++i) {
        u2[i] = u0[i] + S(2) * h * dz[i];
        u0[i] = u1[i];
        u1[i] = u2[i];
      }
    }
    for (int i = 0; i < kN; ++i) z[i] = y[i] + u1[i];
    f(z, dz);
    for (int i = 0; i < kN; ++i) T[j][i] = S(0.5) * (u1[i] + u0[i] + h * dz[i]);
    // Neville extrapolation to h -> 0 in h^2; T[j-k] updated in place.
    for (int k = 1; k <= j; ++k) {
      const S r = S(j + 1) / S(j + 1 - k);  // n_j / n_{j-k}
      const S den = r * r - S(1);
      for (int i = 0; i < kN; ++i) T[j - k][i] = T[j - k + 1][i] + (T[j - k + 1][i] - T[j - k][i]) / den;
    }
  }
  for (int i = 0; i < kN; ++i) {  // y += T[0] (Kahan)
    const S d = T[0][i] - c[i];
    const S t = y[i] + d;
    c[i] = (t - y[i]) - d;
    y[i] = t;
  }
}

std::array<double, 3> rotate(const std::array<double, 4>& q, const std::array<double, 3>& v) {
  // R(q) v for unit q
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  // t = 2 (u x v); v' = v + w t + u x t
  const double tx = 2 * (y * v[2] - z * v[1]);
  const double ty = 2 * (z * v[0] - x * v[2]);
  const double tz = 2 * (x * v[1] - y * v[0]);
  return {v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz),
          v[2] + w * tz + (x * ty - y * tx)};
}

std::array<double, 4> normalized(const std::array<double, 4>& q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}

std::array<double, 4> conj(const std::array<double, 4>& q) { return {q[0], -q[1], -q[2], -q[3]}; }

std::array<double, 4> qmul(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

double norm3(const std::array<double, 3>& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

void ballistic(const Case& c, double t, BodyState* s) {
  for (int i = 0; i < 3; ++i) {
    s->x[i] = c.v0_world[i] * t + 0.5 * c.gravity[i] * t * t;
    s->v[i] = c.v0_world[i] + c.gravity[i] * t;
  }
}

std::string paramString(const Case& c) {
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "%s|%.17g|%.17g,%.17g,%.17g|%.17g,%.17g,%.17g|%.17g,%.17g,%.17g|%.17g,%.17g,%.17g|"
                "%.17g,%.17g,%.17g|%.17g|%s",
                c.name.c_str(), c.mass, c.inertia[0], c.inertia[1], c.inertia[2], c.w0_body[0],
                c.w0_body[1], c.w0_body[2], c.v0_world[0], c.v0_world[1], c.v0_world[2], c.gravity[0],
                c.gravity[1], c.gravity[2], c.torque_world[0], c.torque_world[1], c.torque_world[2], c.T,
                kMethodTag);
  return buf;
}

void mkdirs(const std::string& dir) {
  std::string cur;
  std::stringstream ss(dir);
  std::string part;
  if (!dir.empty() && dir[0] == '/') cur = "/";
  while (std::getline(ss, part, '/')) {
    if (part.empty()) continue;
    cur += part + "/";
    if (::mkdir(cur.c_str(), 0755) != 0 && errno != EEXIST)
      throw std::runtime_error("cannot create directory " + cur);
  }
}

bool readCache(const std::string& path, const Case& c, Reference* r) {
  std::ifstream in(path);
  if (!in) return false;
  std::string header, params, data;
  if (!std::getline(in, header) || !std::getline(in, params) || !std::getline(in, data)) return false;
  if (params != "# " + paramString(c)) return false;
  std::stringstream ss(data);
  std::vector<double> v;
  std::string tok;
  while (std::getline(ss, tok, ',')) v.push_back(std::strtod(tok.c_str(), nullptr));
  if (v.size() != 20) return false;
  BodyState& s = r->state;
  for (int i = 0; i < 4; ++i) s.q[i] = v[i];
  for (int i = 0; i < 3; ++i) {
    s.w_world[i] = v[4 + i];
    s.x[i] = v[7 + i];
    s.v[i] = v[10 + i];
  }
  r->energy = v[13];
  r->L_norm = v[14];
  r->macro_step = v[15];
  r->macro_steps = static_cast<long>(v[16]);
  r->est_orientation_err = v[17];
  return true;
}

void writeCache(const std::string& path, const Case& c, const Reference& r) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp);
    out << "q_w,q_x,q_y,q_z,w_world_x,w_world_y,w_world_z,x,y,z,vx,vy,vz,energy,L_norm,"
           "macro_step,macro_steps,est_orientation_err_rad,spare1,spare2\n";
    out << "# " << paramString(c) << "\n";
    const BodyState& s = r.state;
    char buf[4096];
    std::snprintf(buf, sizeof buf,
                  "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                  "%.17g,%.17g,%.17g,%ld,%.6g,0,0\n",
                  s.q[0], s.q[1], s.q[2], s.q[3], s.w_world[0], s.w_world[1], s.w_world[2], s.x[0],
                  s.x[1], s.x[2], s.v[0], s.v[1], s.v[2], r.energy, r.L_norm, r.macro_step,
                  r.macro_steps, r.est_orientation_err);
    out << buf;
  }
  std::rename(tmp.c_str(), path.c_str());
}

template <class S>
Reference integrateT(const Case& c, double t_end, long n) {
  Rhs<S> f;
  for (int i = 0; i < 3; ++i) {
    f.J[i] = S(c.inertia[i]);
    f.tau[i] = S(c.torque_world[i]);
  }
  S y[kN] = {1, 0, 0, 0, S(c.w0_body[0]), S(c.w0_body[1]), S(c.w0_body[2])};
  S carry[kN] = {0, 0, 0, 0, 0, 0, 0};
  const S H = S(t_end) / S(n);
  for (long k = 0; k < n; ++k) gbsStep(f, y, carry, H);
  const S qn = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]);
  Reference r;
  for (int i = 0; i < 4; ++i) r.state.q[i] = static_cast<double>(y[i] / qn);
  const std::array<double, 3> wb = {static_cast<double>(y[4]), static_cast<double>(y[5]),
                                    static_cast<double>(y[6])};
  r.state.w_world = rotate(r.state.q, wb);
  ballistic(c, t_end, &r.state);
  r.energy = energyOf(c, r.state);
  r.L_norm = norm3(angularMomentumWorld(c, r.state));
  r.macro_step = static_cast<double>(H);
  r.macro_steps = n;
  return r;
}

}  // namespace

long defaultMacroSteps(const Case& c) {
  const double Jmin = std::min({c.inertia[0], c.inertia[1], c.inertia[2]});
  const std::array<double, 3> L0 = {c.inertia[0] * c.w0_body[0], c.inertia[1] * c.w0_body[1],
                                    c.inertia[2] * c.w0_body[2]};
  const double wb = (norm3(L0) + norm3(c.torque_world) * c.T) / Jmin;
  return std::max(100L, static_cast<long>(std::ceil(c.T * wb / 0.25)));
}

Reference integrateReference(const Case& c, double t_end, long macro_steps, bool use_long_double) {
  if (macro_steps <= 0) macro_steps = defaultMacroSteps(c);
  return use_long_double ? integrateT<long double>(c, t_end, macro_steps)
                         : integrateT<double>(c, t_end, macro_steps);
}

Reference referenceSolution(const Case& c, const std::string& cache_dir) {
  std::string path;
  Reference r;
  if (!cache_dir.empty()) {
    mkdirs(cache_dir);
    path = cache_dir + "/reference_" + c.name + ".csv";
    if (readCache(path, c, &r)) return r;
  }
  const long n = defaultMacroSteps(c);
  r = integrateReference(c, c.T, n, true);
  const Reference r2 = integrateReference(c, c.T, 2 * n, true);
  r.est_orientation_err = orientationError(r.state.q, r2.state.q);
  if (r.est_orientation_err > 1e-12) {
    std::fprintf(stderr, "reference for %s not converged: H vs H/2 differ by %.3g rad\n", c.name.c_str(),
                 r.est_orientation_err);
  }
  // Keep the finer of the two, with the H vs H/2 difference as its estimate.
  Reference out = r2;
  out.est_orientation_err = r.est_orientation_err;
  if (!path.empty()) writeCache(path, c, out);
  return out;
}

bool analyticSymmetricTorqueFree(const Case& c, double t, BodyState* out) {
  using LD = long double;
  const double J1 = c.inertia[0], J2 = c.inertia[1], J3 = c.inertia[2];
  if (J1 != J2) return false;
  if (c.torque_world[0] != 0 || c.torque_world[1] != 0 || c.torque_world[2] != 0) return false;
  // R(t) = exp(t L/J1) R0 exp(t psi e3), psi = w3 (1 - J3/J1), R0 = identity,
  // so L = J w0 (world = body at t = 0). Evaluated in long double (the
  // rotation angles reach ~500 rad, so double would lose ~1e-14 rad).
  const LD L[3] = {LD(J1) * c.w0_body[0], LD(J2) * c.w0_body[1], LD(J3) * c.w0_body[2]};
  const LD Ln = std::sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
  const LD a = LD(t) * Ln / LD(J1);   // precession angle about L
  const LD psi = LD(c.w0_body[2]) * (LD(1) - LD(J3) / LD(J1));
  const LD b = LD(t) * psi;           // body spin angle about e3
  const LD sa = std::sin(a / 2) / Ln, ca = std::cos(a / 2);
  const LD qa[4] = {ca, sa * L[0], sa * L[1], sa * L[2]};
  const LD qb[4] = {std::cos(b / 2), 0, 0, std::sin(b / 2)};
  // q = qa (x) qb
  const LD q[4] = {qa[0] * qb[0] - qa[3] * qb[3], qa[1] * qb[0] + qa[2] * qb[3],
                   qa[2] * qb[0] - qa[1] * qb[3], qa[0] * qb[3] + qa[3] * qb[0]};
  for (int i = 0; i < 4; ++i) out->q[i] = static_cast<double>(q[i]);
  // w_world = L/J1 + psi R e3
  const std::array<double, 3> e3 = rotate(out->q, {0.0, 0.0, 1.0});
  for (int i = 0; i < 3; ++i) out->w_world[i] = static_cast<double>(L[i] / LD(J1) + psi * LD(e3[i]));
  ballistic(c, t, out);
  return true;
}

double energyOf(const Case& c, const BodyState& s) {
  const std::array<double, 4> q = normalized(s.q);
  const std::array<double, 3> wb = rotate(conj(q), s.w_world);
  double e = 0.5 * c.mass * (s.v[0] * s.v[0] + s.v[1] * s.v[1] + s.v[2] * s.v[2]);
  for (int i = 0; i < 3; ++i) e += 0.5 * c.inertia[i] * wb[i] * wb[i] - c.mass * c.gravity[i] * s.x[i];
  return e;
}

std::array<double, 3> angularMomentumWorld(const Case& c, const BodyState& s) {
  const std::array<double, 4> q = normalized(s.q);
  const std::array<double, 3> wb = rotate(conj(q), s.w_world);
  return rotate(q, {c.inertia[0] * wb[0], c.inertia[1] * wb[1], c.inertia[2] * wb[2]});
}

double orientationError(const std::array<double, 4>& q, const std::array<double, 4>& q_ref) {
  const std::array<double, 4> e = qmul(conj(normalized(q_ref)), normalized(q));
  const double vn = std::sqrt(e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
  return 2.0 * std::atan2(vn, std::fabs(e[0]));
}

Errors computeErrors(const Case& c, const Reference& ref, const BodyState& s) {
  Errors e;
  e.orientation_rad = orientationError(s.q, ref.state.q);
  std::array<double, 3> dx = {s.x[0] - ref.state.x[0], s.x[1] - ref.state.x[1], s.x[2] - ref.state.x[2]};
  e.com_m = norm3(dx);
  e.energy_rel = std::fabs(energyOf(c, s) - ref.energy) / std::fabs(ref.energy);
  e.L_rel = std::fabs(norm3(angularMomentumWorld(c, s)) - ref.L_norm) / ref.L_norm;
  return e;
}

}  // namespace bench
