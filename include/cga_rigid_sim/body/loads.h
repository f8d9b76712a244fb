// Loads on one body during one step: uniform gravity and applied CGA forces and couples.
//
// An applied load is a force F = f + αn applied at a material point of the body, plus a pure
// couple. Its directions are fixed either in the world (a push whose direction does not turn)
// or in the body (a thruster that turns with it). The point is always a material point, given
// in B (centre-of-mass principal frame). Moments are formed as λ X∧F, back-rotated into the
// body and wedged with n (doc/conventions.md (E13)): T_B = (x_B × f_B, λ f_B) + (τ_B, 0); α
// drops out.
//
// Gravity is kept apart: a uniform field acts at the centre of mass, produces no torque, and the
// integrators treat it exactly (the centre of mass follows the parabola to round-off).
// Loads accumulate: add() sums; clearApplied() empties the list for the next step.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "cga_rigid_sim/cga/force.h"
#include "cga_rigid_sim/cga/moment.h"
#include "cga_rigid_sim/cga/motor.h"

namespace cga_rigid_sim {
namespace dynamics {

/// The axes a load's force and couple directions are fixed in.
enum class Axes { kWorld, kBody };

struct AppliedLoad {
  Axes axes = Axes::kWorld;
  cga::Force F;                                       ///< force (in `axes`), N
  Eigen::Vector3d point_B = Eigen::Vector3d::Zero();  ///< material point, B frame, m
  Eigen::Vector3d couple = Eigen::Vector3d::Zero();   ///< pure couple (in `axes`), N m
};

class Loads {
 public:
  void setGravity(const Eigen::Vector3d& g_W) { g_W_ = g_W; }
  /// Uniform gravitational acceleration, world axes, m/s².
  const Eigen::Vector3d& gravity() const { return g_W_; }
  bool hasGravity() const { return !g_W_.isZero(0.0); }

  void add(const AppliedLoad& load) {
    applied_.push_back(load);
    // The world sums of worldSums(), kept as loads arrive so that a step reads them in O(1).
    if (load.axes != Axes::kWorld || !load.point_B.isZero(0.0)) world_at_centre_ = false;
    f_sum_W_ += load.F.f;
    couple_sum_W_ += load.couple;
  }
  /// Room for n applied loads, so that add() does not allocate until there are more.
  void reserveApplied(std::size_t n) { applied_.reserve(n); }
  void clearApplied() {
    applied_.clear();
    world_at_centre_ = true;
    f_sum_W_.setZero();
    couple_sum_W_.setZero();
  }
  const std::vector<AppliedLoad>& applied() const { return applied_; }
  bool hasApplied() const { return !applied_.empty(); }
  /// No gravity and no applied load: a free body.
  bool empty() const { return !hasGravity() && !hasApplied(); }
  /// Whether any applied load can exert a torque about the centre of mass.
  bool hasTorque() const {
    for (const auto& l : applied_)
      if (!l.couple.isZero(0.0) || (!l.F.f.isZero(0.0) && !l.point_B.isZero(0.0))) return true;
    return false;
  }

  /// Sum of the applied loads' body moments at the pose M_WB (gravity excluded).
  cga::Moment appliedMoment_B(const cga::Motor& M_WB, double lambda) const {
    cga::Moment T;
    for (const auto& l : applied_) {
      Eigen::Vector3d f = l.F.f, tau = l.couple;
      if (l.axes == Axes::kWorld) {
        const Eigen::Quaterniond R_BW = M_WB.rotation().conjugate();
        f = R_BW * f;
        tau = R_BW * tau;
      }
      T += cga::Moment::ofForceAt(f, l.point_B, lambda) + cga::Moment::couple(tau);
    }
    return T;
  }
  /// Gravity's and the applied loads' body moment at the pose M_WB, T = (τ_B, λ f_B): the same
  /// as gravityMoment_B + appliedMoment_B, with the world-axes parts (m g, world forces and
  /// couples, and the moments (R x_B) × f_W of world forces at body points) summed in world axes
  /// and rotated into the body once, instead of once per vector of every load.
  __attribute__((always_inline)) cga::Moment moment_B(double mass, const cga::Motor& M_WB,
                                                      double lambda) const {
    const Eigen::Quaterniond& r = M_WB.rotation();
    Eigen::Vector3d f_W = mass * g_W_, couple_W = Eigen::Vector3d::Zero();
    Eigen::Vector3d f_B = Eigen::Vector3d::Zero(), couple_B = Eigen::Vector3d::Zero();
    bool world_couple = false;
    for (const auto& l : applied_) {
      if (l.axes == Axes::kWorld) {
        f_W += l.F.f;
        if (!l.point_B.isZero(0.0)) {
          couple_W += (r * l.point_B).cross(l.F.f);
          world_couple = true;
        }
        if (!l.couple.isZero(0.0)) {
          couple_W += l.couple;
          world_couple = true;
        }
      } else {
        f_B += l.F.f;
        couple_B += l.couple + l.point_B.cross(l.F.f);
      }
    }
    if (!f_W.isZero(0.0)) f_B += toBody(r, f_W);
    if (world_couple) couple_B += toBody(r, couple_W);
    return {couple_B, lambda * f_B};
  }
  /// When every applied load is fixed in the world and acts at the centre of mass (or is a pure
  /// couple), the loads' world-axes sums, which then do not depend on the pose: the force
  /// m g + Σ f and the couple Σ τ (N, N m). moment_B at a pose is then (R̃ couple_W, λ R̃ f_W), so
  /// a splitting can form the sums once per step instead of once per kick. False otherwise.
  bool worldSums(double mass, Eigen::Vector3d& f_W, Eigen::Vector3d& couple_W) const {
    if (!world_at_centre_) return false;
    f_W = mass * g_W_ + f_sum_W_;
    couple_W = couple_sum_W_;
    return true;
  }
  /// R̃ x: a world vector in the axes of the body with rotor r = (w, a), written out
  /// (t = 2 x × a, R̃ x = x + w t + t × a) so that it inlines.
  __attribute__((always_inline)) static Eigen::Vector3d toBody(const Eigen::Quaterniond& r,
                                                               const Eigen::Vector3d& x) {
    const Eigen::Vector3d a = r.vec();
    const Eigen::Vector3d t = 2.0 * x.cross(a);
    return x + r.w() * t + t.cross(a);
  }
  /// Gravity's moment on a body of mass m at the pose M_WB: (0, λ m R̃ g).
  cga::Moment gravityMoment_B(double mass, const cga::Motor& M_WB, double lambda) const {
    return {Eigen::Vector3d::Zero(), (lambda * mass) * (M_WB.rotation().conjugate() * g_W_)};
  }

 private:
  Eigen::Vector3d g_W_ = Eigen::Vector3d::Zero();
  std::vector<AppliedLoad> applied_;
  // Running sums of the applied loads (add order), and whether all of them are world-axes loads
  // at the centre of mass (worldSums()).
  bool world_at_centre_ = true;
  Eigen::Vector3d f_sum_W_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d couple_sum_W_ = Eigen::Vector3d::Zero();
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
