// Analytic contact benchmark cases, their exact answers and the error
// metrics every engine reports against them.
//
// Header-only on purpose: the peer runners (bench/peers/contact_*.cc) use it
// now, cga_rigid_sim's own contact benchmark can include it later without a
// link dependency. An engine runner builds the scene described by a
// ContactCase, then feeds a ContactMonitor the state of the dynamic bodies
// (world frame) after every step; the monitor turns the trajectory into
// error rows.
//
// Conventions (all cases): SI units, world z up, g = 9.81 m/s^2, the ground
// is the static plane z = 0 (contact height 0), friction is Coulomb with the
// one coefficient `mu` between every pair of surfaces (body-ground and
// body-body), `e` is the coefficient of (normal) restitution for every pair.
// Bodies start with identity orientation (box edges along the world axes).
//
// The inclined plane is modelled by tilting gravity instead of the plane:
// g_world = g (-sin(theta), 0, -cos(theta)), plane z = 0. In the frame of a
// plane tilted by theta this is exactly the same problem (same normal and
// tangential load, same contact geometry); it keeps every engine's ground a
// plain z-plane and the slope direction along -x.
//
// Truths (derivations):
//  * bounce: free fall from apex height h (height of the centre above the
//    contact height r) reaches the ground with v = sqrt(2 g h); restitution
//    sends it up with e v, which reaches h' = (e v)^2 / (2 g) = e^2 h. So the
//    k-th apex after the k-th impact is h_k = e^{2k} h0. Flight time of the
//    first fall sqrt(2 h0 / g); each later arc (up and down) takes
//    2 e^k v0 / g = 2 e^k sqrt(2 h0 / g). Summing the geometric series,
//    t_rest = sqrt(2h0/g) (1 + 2 sum_{k>=1} e^k) = sqrt(2h0/g)(1+e)/(1-e)
//    (= 4.0640 s for h0 = 1, e = 0.8): infinitely many bounces in finite time.
//  * incline (box on a slope theta, Coulomb mu): along the slope the
//    driving force is m g sin(theta), the normal force m g cos(theta), the
//    largest static friction mu m g cos(theta). tan(theta) <= mu: the box
//    sticks (a = 0, displacement 0). Otherwise it slides with
//    a = g (sin(theta) - mu cos(theta)), d(t) = a t^2 / 2
//    (theta = 30 deg, mu = 0.3: a = 2.3562 m/s^2, d(1 s) = 1.1781 m).
//  * slide_stop: kinetic friction decelerates at mu g, so
//    v(t) = v0 - mu g t stops at t* = v0/(mu g) after d = v0^2/(2 mu g)
//    (v0 = 2, mu = 0.5: t* = 0.4077 s, d = 0.4077 m).
//  * rolling_sphere: while it slides, friction mu m g opposes the slip:
//    v' = -mu g, and about the centre the torque mu m g r spins it up,
//    w' = mu m g r / J = (5/2) mu g / r (J = 2/5 m r^2). Slip velocity
//    s = v - w r: s' = -(7/2) mu g, s(0) = v0, so rolling starts at
//    t_r = 2 v0 / (7 mu g) with v = v0 - mu g t_r = 5 v0 / 7. Afterwards
//    (no rolling resistance) it rolls at 5 v0/7 forever.
//    The slip crosses the detection threshold s_tol (below) at
//    t = (v0 - s_tol)/((7/2) mu g): that is the truth of the measured
//    rolling-start time (no approximation, the threshold is part of the
//    metric's definition).
//  * stack10: a column of equal boxes resting face on face is in static
//    equilibrium (only normal forces, each balancing the weight above it):
//    drift 0, kinetic energy 0 for all time.
//  * pile1000: no closed form; a stress test (speed, stability, containment).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "cga_rigid_sim/math/constants.h"

namespace bench {
namespace contacts {

constexpr double kG = 9.81;
using cga_rigid_sim::math::kPi;

enum class Shape { Sphere, Box };

struct BodySpec {
  Shape shape;
  double size;  // sphere: radius; box: half edge (cube)
  double mass;
  std::array<double, 3> x0;  // centre, world
  std::array<double, 3> v0;  // linear velocity, world
  // Principal moment of inertia (all three equal for a solid sphere or a
  // solid cube: 2/5 m r^2, m a^2/6 with a = 2 * half edge).
  double inertia() const {
    return shape == Shape::Sphere ? 0.4 * mass * size * size : mass * (2 * size) * (2 * size) / 6.0;
  }
};

// Static open bin: floor = ground plane, four walls (boxes) whose inner faces
// are at |x| = half_width, |y| = half_width, from z = 0 to wall_height.
struct Bin {
  bool present = false;
  double half_width = 1.0;
  double wall_height = 0.5;
  double wall_thickness = 0.1;
};

struct ContactCase {
  std::string name;
  double mu;
  double e;
  std::array<double, 3> gravity;
  double T;  // simulated time, s
  std::vector<BodySpec> bodies;
  Bin bin;
  // Only observe the state at the end (pile1000: cheap, no per-step reads).
  bool observe_end_only = false;
};

// ---- case parameters -------------------------------------------------------

struct BounceParams {
  double r = 0.1, m = 1.0, h0 = 1.0, e = 0.8, T = 6.0;
  int n_apex = 5;
  double v_rest = 0.01;  // "at rest": |v| below this for the rest of the run
  double tRest() const { return std::sqrt(2 * h0 / kG) * (1 + e) / (1 - e); }
  double apex(int k) const { return std::pow(e, 2 * k) * h0; }
};
struct InclineParams {
  double half = 0.1, m = 1.0, theta = 30.0 * kPi / 180.0;
  double accel(double mu) const {
    const double a = kG * (std::sin(theta) - mu * std::cos(theta));
    return a > 0 ? a : 0.0;
  }
};
struct SlideParams {
  double half = 0.1, m = 1.0, v0 = 2.0, mu = 0.5, T = 1.0;
  double distance() const { return v0 * v0 / (2 * mu * kG); }
  double tStop() const { return v0 / (mu * kG); }
};
struct RollParams {
  double r = 0.1, m = 1.0, v0 = 3.0, mu = 0.2, T = 1.5;
  double s_tol_rel = 0.01;  // rolling detected when slip < 1% of v0
  double vRoll() const { return 5.0 * v0 / 7.0; }
  double tRoll() const { return 2.0 * v0 / (7.0 * mu * kG); }
  double tDetect() const { return (v0 - s_tol_rel * v0) / (3.5 * mu * kG); }
};
struct StackParams {
  int n = 10;
  double half = 0.1, m = 1.0, mu = 0.8, T = 10.0;
};
struct PileParams {
  int nx = 10, ny = 10, nz = 10;
  double half = 0.05, m = 1.0, spacing = 0.15, z_bottom = 0.5, mu = 0.5, e = 0.2, T = 5.0;
};

inline ContactCase bounceCase() {
  BounceParams p;
  return {"bounce", 0.0, p.e, {0, 0, -kG}, p.T,
          {{Shape::Sphere, p.r, p.m, {0, 0, p.r + p.h0}, {0, 0, 0}}}, Bin{}, false};
}
inline ContactCase inclineCase(const std::string& name, double mu, double T) {
  InclineParams p;
  return {name, mu, 0.0, {-kG * std::sin(p.theta), 0, -kG * std::cos(p.theta)}, T,
          {{Shape::Box, p.half, p.m, {0, 0, p.half}, {0, 0, 0}}}, Bin{}, false};
}
inline ContactCase slideCase() {
  SlideParams p;
  return {"slide_stop", p.mu, 0.0, {0, 0, -kG}, p.T,
          {{Shape::Box, p.half, p.m, {0, 0, p.half}, {p.v0, 0, 0}}}, Bin{}, false};
}
inline ContactCase rollCase() {
  RollParams p;
  return {"rolling_sphere", p.mu, 0.0, {0, 0, -kG}, p.T,
          {{Shape::Sphere, p.r, p.m, {0, 0, p.r}, {p.v0, 0, 0}}}, Bin{}, false};
}
inline ContactCase stackCase() {
  StackParams p;
  ContactCase c{"stack10", p.mu, 0.0, {0, 0, -kG}, p.T, {}, Bin{}, false};
  for (int i = 0; i < p.n; ++i)
    c.bodies.push_back({Shape::Box, p.half, p.m, {0, 0, p.half + 2 * p.half * i}, {0, 0, 0}});
  return c;
}
inline ContactCase pileCase() {
  PileParams p;
  ContactCase c{"pile1000", p.mu, p.e, {0, 0, -kG}, p.T, {}, Bin{}, true};
  c.bin.present = true;
  const double x0 = -0.5 * p.spacing * (p.nx - 1), y0 = -0.5 * p.spacing * (p.ny - 1);
  for (int k = 0; k < p.nz; ++k)
    for (int j = 0; j < p.ny; ++j)
      for (int i = 0; i < p.nx; ++i)
        c.bodies.push_back({Shape::Box, p.half, p.m,
                            {x0 + p.spacing * i, y0 + p.spacing * j, p.z_bottom + p.half + p.spacing * k},
                            {0, 0, 0}});
  return c;
}

inline std::vector<ContactCase> allContactCases() {
  return {bounceCase(),
          inclineCase("incline_stick", 0.7, 2.0),
          inclineCase("incline_slide", 0.3, 1.0),
          slideCase(),
          rollCase(),
          stackCase(),
          pileCase()};
}

// ---- observation and metrics -------------------------------------------------

struct BodyObs {
  std::array<double, 3> x;  // centre, world
  std::array<double, 3> v;  // linear velocity, world
  std::array<double, 3> w;  // angular velocity, world
};

// One output row: error with the name of its metric, and a free-text note
// (measured value, truth, engine events). No commas in notes (CSV).
struct MetricRow {
  double error;
  std::string metric;
  std::string note;
};

inline double norm3(const std::array<double, 3>& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
inline std::string fmtG(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.5g", v);
  return b;
}

// Collects what a case's metrics need from the trajectory. Feed it
// observe(t, bodies) after every step (t = time after the step), or only at
// the end when the case says observe_end_only; then call finish().
class ContactMonitor {
 public:
  explicit ContactMonitor(const ContactCase& c) : c_(c) {}

  void observe(double t, const std::vector<BodyObs>& b) {
    if (!finiteAll(b)) nonfinite_ = true;
    if (c_.name == "bounce") {
      const BodyObs& s = b[0];
      const double z = s.x[2] - c_.bodies[0].size;  // height above contact height
      // Apex: vertical velocity changes sign from up to down; the apex height
      // is the largest height seen while rising/at the turn.
      if (prev_vz_ > 0 && s.v[2] <= 0) apexes_.push_back(std::max(z, prev_z_));
      if (norm3(s.v) >= BounceParams().v_rest) last_moving_ = t;
      prev_vz_ = s.v[2];
      prev_z_ = z;
    } else if (c_.name == "rolling_sphere") {
      const BodyObs& s = b[0];
      const double r = c_.bodies[0].size;
      // Contact-point velocity: v + w x (-r z) = (vx - r wy, vy + r wx, .).
      const double sx = s.v[0] - r * s.w[1], sy = s.v[1] + r * s.w[0];
      const double slip = std::hypot(sx, sy);
      const RollParams p;
      const double tol = p.s_tol_rel * p.v0;
      if (t_roll_ < 0 && slip < tol) {
        // Linear interpolation of the crossing between the two samples.
        t_roll_ = (prev_slip_ > tol && prev_t_ >= 0) ? prev_t_ + (t - prev_t_) * (prev_slip_ - tol) / (prev_slip_ - slip)
                                                     : t;
      }
      prev_slip_ = slip;
      prev_t_ = t;
    }
    last_ = b;
    t_ = t;
  }

  std::vector<MetricRow> finish() const {
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<MetricRow> rows;
    if (nonfinite_ || last_.empty()) {
      rows.push_back({inf, "blew_up", "non-finite state"});
      return rows;
    }
    const BodyObs& s0 = last_[0];
    if (c_.name == "bounce") {
      const BounceParams p;
      double worst = 0;
      std::string note = "apexes";
      for (int k = 1; k <= p.n_apex; ++k) {
        if (int(apexes_.size()) < k) {
          worst = inf;
          note += " missing";
          break;
        }
        const double rel = std::fabs(apexes_[k - 1] - p.apex(k)) / p.apex(k);
        worst = std::max(worst, rel);
        note += " " + fmtG(apexes_[k - 1]);
      }
      note += " truth " + fmtG(p.apex(1)) + ".." + fmtG(p.apex(p.n_apex));
      rows.push_back({worst, "apex_rel_max", note});
      // At rest if |v| < v_rest from some time on until the end of the run.
      // Quiet for at least the last 0.25 s of the run.
      if (norm3(s0.v) < p.v_rest && last_moving_ < t_ - 0.25) {
        rows.push_back({std::fabs(last_moving_ - p.tRest()) / p.tRest(), "t_rest_rel",
                        "t_rest " + fmtG(last_moving_) + " truth " + fmtG(p.tRest()) + " bounces " +
                            std::to_string(apexes_.size())});
      } else {
        rows.push_back({inf, "t_rest_rel", "not at rest by T (|v| " + fmtG(norm3(s0.v)) + ") bounces " +
                                               std::to_string(apexes_.size())});
      }
    } else if (c_.name == "incline_stick") {
      const double d = std::hypot(s0.x[0] - c_.bodies[0].x0[0], s0.x[1] - c_.bodies[0].x0[1]);
      rows.push_back({d, "displacement_m", "truth 0 after " + fmtG(c_.T) + " s"});
    } else if (c_.name == "incline_slide") {
      const InclineParams p;
      const double truth = 0.5 * p.accel(c_.mu) * c_.T * c_.T;
      const double d = -(s0.x[0] - c_.bodies[0].x0[0]);  // down the slope = -x
      rows.push_back({std::fabs(d - truth) / truth, "displacement_rel", "d " + fmtG(d) + " truth " + fmtG(truth)});
    } else if (c_.name == "slide_stop") {
      const SlideParams p;
      const double d = s0.x[0] - c_.bodies[0].x0[0];
      rows.push_back({std::fabs(d - p.distance()) / p.distance(), "stop_distance_rel",
                      "d " + fmtG(d) + " truth " + fmtG(p.distance()) + " |v(T)| " + fmtG(norm3(s0.v))});
    } else if (c_.name == "rolling_sphere") {
      const RollParams p;
      const double v = std::hypot(s0.v[0], s0.v[1]);
      rows.push_back({std::fabs(v - p.vRoll()) / p.vRoll(), "v_final_rel", "v " + fmtG(v) + " truth " + fmtG(p.vRoll())});
      if (t_roll_ >= 0)
        rows.push_back({std::fabs(t_roll_ - p.tDetect()) / p.tDetect(), "t_roll_rel",
                        "t " + fmtG(t_roll_) + " truth " + fmtG(p.tDetect()) + " (slip<1% v0; ideal " +
                            fmtG(p.tRoll()) + ")"});
      else
        rows.push_back({inf, "t_roll_rel", "slip never below 1% of v0"});
    } else if (c_.name == "stack10") {
      const BodyObs& top = last_.back();
      const BodySpec& ts = c_.bodies.back();
      rows.push_back({std::hypot(top.x[0] - ts.x0[0], top.x[1] - ts.x0[1]), "top_drift_m",
                      "top z " + fmtG(top.x[2]) + " (start " + fmtG(ts.x0[2]) + ")"});
      double ke = 0;
      for (size_t i = 0; i < last_.size(); ++i) {
        const BodySpec& bs = c_.bodies[i];
        const double v = norm3(last_[i].v), w = norm3(last_[i].w);
        ke += 0.5 * bs.mass * v * v + 0.5 * bs.inertia() * w * w;  // isotropic inertia
      }
      rows.push_back({ke, "kinetic_energy_J", "truth 0"});
    } else if (c_.name == "pile1000") {
      double vmax = 0;
      int below = 0, escaped = 0;
      for (size_t i = 0; i < last_.size(); ++i) {
        const BodyObs& s = last_[i];
        vmax = std::max(vmax, norm3(s.v));
        if (s.x[2] < 0) ++below;
        if (std::fabs(s.x[0]) > c_.bin.half_width || std::fabs(s.x[1]) > c_.bin.half_width) ++escaped;
      }
      rows.push_back({vmax, "max_speed_mps", "at T = " + fmtG(c_.T) + " s"});
      rows.push_back({double(escaped), "n_escaped", "centres outside the bin walls"});
      rows.push_back({double(below), "n_below_floor", "centres below z = 0"});
    }
    return rows;
  }

 private:
  static bool finiteAll(const std::vector<BodyObs>& b) {
    for (const BodyObs& s : b)
      for (int i = 0; i < 3; ++i)
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.v[i]) || !std::isfinite(s.w[i])) return false;
    return true;
  }
  ContactCase c_;
  std::vector<BodyObs> last_;
  double t_ = 0;
  bool nonfinite_ = false;
  // bounce
  std::vector<double> apexes_;
  double prev_vz_ = 0, prev_z_ = 0, last_moving_ = 0;
  // rolling
  double t_roll_ = -1, prev_slip_ = -1, prev_t_ = -1;
};

}  // namespace contacts
}  // namespace bench
