// The solver's working arrays (contact_solver.h): the bodies' velocities side by side and their
// responses, the rows' slots, the face blocks (contact_face_blocks.cc), the islands
// (contact_islands.cc) and the matrices of a resting island's direct solve (contact_resting.h).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "cga_rigid_sim/math/union_find.h"
#include "contact/contact_tree_factor.h"
#include "contact/contact_tree_newton.h"

namespace cga_rigid_sim {
namespace sim {

/// The solver's working arrays, kept between steps so that a step allocates only when the
/// problem grows. The sweeps read and write the bodies' velocities here, side by side, rather
/// than in SolverBody (large: a pile's bodies would not stay in the cache); slot n (one past
/// the last body) is an immovable dummy with zero velocity and response, which the rows'
/// immovable and tree sides point to, so that a contact update has no branch per side.
struct SolverWork {
  struct Twist {
    Eigen::Vector3d v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  };
  struct Response {
    double inv_mass = 0.0;
    Eigen::Matrix3d inv_inertia = Eigen::Matrix3d::Zero();
    /// The longest lever arm of its contacts, m: a change of w moves a contact point by up to
    /// reach·|Δw|.
    double reach = 0.0;
  };
  /// Per slot + the dummy: the (pseudo-)velocities; before the current sweep (the convergence
  /// test); before any contact impulse (the energy guard starts again from them).
  std::vector<Twist> vel, vel_sweep, vel_start;
  std::vector<Response> response;  ///< per slot + the dummy
  std::vector<int> a, b;           ///< per row: its slots, the dummy for none
  /// A run of consecutive rows between the same two bodies with one normal (a face's corners,
  /// at most four; a single row otherwise): their normal impulses are solved as one block.
  struct Group {
    int first = 0, size = 1;
    /// The pseudo-inverse of the block's normal Delassus matrix (size × size, top left): four
    /// coplanar corners leave one combination of impulses that moves nothing.
    Eigen::Matrix4d pinv = Eigen::Matrix4d::Zero();
  };
  std::vector<Group> groups;
  /// The islands: the bodies joined by their contacts (static bodies and the ground join
  /// nothing; a tree joins every contact on any of its links), each a run of `groups` in
  /// island_group and of slots in island_body, trees in island_tree. They are solved one
  /// after the other, each until its own sweeps converge: an island's impulses do not depend
  /// on bodies it does not touch, and a settled island stops sweeping while another lands.
  struct Island {
    int first_group = 0, groups = 0;
    int first_body = 0, bodies = 0;
    int first_tree = 0, trees = 0;
  };
  std::vector<Island> islands;
  std::vector<int> island_group, island_body, island_tree;
  math::UnionFind island_sets;                 ///< makeIslands: the islands as sets
  std::vector<int> node_island, group_island;  ///< scratch of makeIslands
  /// The direct solve of a resting island (contact_resting.h): at most 16 faces, so its
  /// matrices have a fixed largest size and a step allocates nothing.
  struct Resting {
    static constexpr int kMax = 6 * 16;
    using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMax, kMax>;
    using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMax, 1>;
    struct Face {
      Eigen::Vector3d c;     ///< the corners' centre, world
      Eigen::Vector3d p[4];  ///< the corners from c
      Eigen::Vector3d impulse[4];
      Eigen::Matrix3d S_inv;   ///< (Σ |ρ|² 1 − ρ ρᵀ)⁻¹
      int side[2] = {-1, -1};  ///< its bodies' places in the island (−1: immovable)
      Eigen::Matrix<double, 6, 6> phi[2];
    };
    Face faces[16];
    Matrix A;
    Vector rhs, W;
    Eigen::LDLT<Matrix> ldlt;
  };
  Resting resting;
  /// The Newton solve of a resting tree's island (contact_resting_tree.h): its workspace, the
  /// island's rows in order, the warm-started ν (restored when the solve fails).
  struct RestingTree {
    TreeNewton newton;
    std::vector<int> contacts;
    Eigen::VectorXd nu_warm, dnu, nu_f, held_friction;
  };
  RestingTree resting_tree;
  /// The sweeps of an island with trees (doc/contacts.md#trees) move each tree's ν as
  /// ν₀ + L⁻¹ z, L the factor of M(q) (M = Lᵀ L, contact_tree_factor.h) and z = 0 at ν₀: a
  /// contact's impulse P adds Y P to z and its point's velocity is J ν₀ + Yᵀ z, Y = L⁻ᵀ Jᵀ the
  /// first half of its response (nonzero only on the coordinates from its link to the base),
  /// where ν itself would take the dense M⁻¹ Jᵀ P and J ν over every coordinate. A joint stop's
  /// rate is ν₀_k + sᵀ z, s = L⁻ᵀ e_k, on the coordinates from its joint to the base.
  /// (With mimic joints the factor is dense and so are Y and s.) ν is made from z once, after
  /// the sweeps. The position correction's sweeps take the same coordinates for pν = L⁻¹ z.
  struct TreeSweeps {
    /// A run of `coordinate` and `y` (a row side's nonzeros) or of `stop_coordinate` and `s`
    /// (a stop's).
    struct Run {
      int first = 0, size = 0;
    };
    std::vector<Run> side_a, side_b;  ///< per row: its tree sides' runs (size 0: none)
    std::vector<Eigen::Vector3d> u0;  ///< per row: J ν₀ of its tree sides (a's minus b's)
    std::vector<int> coordinate, stop_coordinate;
    std::vector<Eigen::Vector3d> y;  ///< per coordinate of a side's run: its row of Y
    /// Per coordinate of a side's run: Y n, its row's normal (negated on side b): the position
    /// correction's sweeps push along the normal alone (contact_positions.cc).
    std::vector<double> yn;
    std::vector<double> s;  ///< per coordinate of a stop's run: its entry of s
    /// Per tree: z, and z before the current sweep; its limit rows' runs, sᵀ s = (M⁻¹)_kk and
    /// |s|.
    std::vector<Eigen::VectorXd> z, z_sweep;
    std::vector<std::vector<Run>> stop;
    std::vector<std::vector<double>> stop_a, stop_norm;
    /// Per tree: a half solve's columns (kept per tree: trees of other sizes would reallocate).
    std::vector<TreeFactor::Columns> scratch;
    /// Per tree: L⁻¹ z, the sweeps' change of ν (sweptChange).
    std::vector<Eigen::VectorXd> change;
    /// The island and rows whose runs these are once its velocity sweeps have run (cleared at
    /// the start of solveVelocities and by loadSweptLimits, set by sweepIsland, taken by the
    /// solvePositions that follows on the same rows and islands, which then uses the runs as
    /// they are).
    const Island* swept_island = nullptr;
    const void* swept_rows = nullptr;
  };
  TreeSweeps tree_sweeps;
};

}  // namespace sim
}  // namespace cga_rigid_sim
