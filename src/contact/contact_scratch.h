// What the contacts stage keeps between steps besides Data::contacts: the collision geometry
// and the solver's arrays (reused, so a step with contacts allocates only when they grow).
#pragma once

#include <memory>
#include <vector>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/moment.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/tree/articulated_body.h"
#include "contact/contact_detection.h"
#include "contact/contact_sleep.h"
#include "contact/contact_solver.h"

namespace cga_rigid_sim {
namespace sim {

struct ContactScratch {
  std::shared_ptr<CollisionCache> cache = makeCollisionCache();
  std::vector<Contact> found;             ///< this step's detection
  std::vector<int> slot_of_moving;        ///< per moving index: its solver slot, or −1
  std::vector<int> moving_of_slot;        ///< per slot: the moving index
  std::vector<cga::Bivelocity> kicked_B;  ///< per slot: Ω_B after the loads' kick
  std::vector<SolverBody> bodies;         ///< per slot
  std::vector<SolverTree> trees;          ///< per tree in a contact
  std::vector<int> solver_tree_of_tree;   ///< per Model tree: its index in `trees`, or −1
  std::vector<int> tree_of_solver_tree;   ///< per solver tree: the Model's tree index
  std::vector<char> tree_used;            ///< per solver tree: it has a contact in the solve
  std::vector<dynamics::TreeKinematics> tree_kicked;  ///< per solver tree: after the kick
  std::vector<int> slot_a, slot_b;                    ///< per contact
  std::vector<ContactRow> rows;                       ///< per contact
  SleepState sleep;                                   ///< the sleeping islands (contact_sleep.h)
  SolverWork work;  ///< the solver's working arrays (the landings' solves use them too)
  std::vector<std::size_t> previous;  ///< last step's contacts, sorted by their pair
  /// Per slot of a free body: its world-axes momentum (contact_momentum.h) after the kick and,
  /// once solved, the impulses; its centre's velocity before the kick.
  std::vector<MovingBodyData::ContactMomentum> momentum;
  std::vector<Eigen::Vector3d> v_start;
  /// Per slot: the sum of its contact impulses and of their moments about its centre, world.
  std::vector<Eigen::Vector3d> impulse_W, impulse_moment_W;
  std::vector<Eigen::Vector3d> common_normal;  ///< per slot: its contacts' one normal, or NaN
  std::vector<char> landing;                   ///< per slot: it lands within the step
  std::vector<Contact> landed;                 ///< the landings' contacts, with impulses
  // One landing's solve.
  std::vector<Contact> land_found;
  std::vector<SolverBody> land_bodies;
  std::vector<SolverTree> land_trees;  ///< always empty: trees do not land
  std::vector<int> land_slot_a, land_slot_b;
  std::vector<ContactRow> land_rows;
};

/// Moving body i as the solver sees it: state s with body bivelocity omega_B, world axes
/// (contact_kick.cc).
SolverBody solverBody(const Model& model, const dynamics::BodyState& s,
                      const cga::Bivelocity& omega_B, int i);

}  // namespace sim
}  // namespace cga_rigid_sim
