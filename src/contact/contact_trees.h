// Articulated trees in the contacts stage (doc/contacts.md#trees): a tree with a link in a
// contact is kicked by its loads like a free body, ν ← ν + h M(q)⁻¹ (τ + Q), takes the contact
// impulses through its links' Jacobians (contact_solver.h) and then drifts over the step with
// its own integrator and no loads (stage_trees.cc); then the contact step ends here
// (contact_tree_end.cc): correction, energy book, guards.
#pragma once

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/tree/articulated_body.h"
#include "contact/contact_solver.h"

namespace cga_rigid_sim {
namespace sim {

/// Kicks tree t by its loads over the step (its loads must be this step's: loadTrees), fills
/// the solver's view of it (ν after the kick, M(q), the coordinates' world twists) and `kicked`
/// with the bodies' poses and velocities after the kick, and keeps in the tree's data its
/// energy and the power of its inputs at the step's start (for the energy book).
void kickTree(const Model& model, Data& data, int t, SolverTree& out,
              dynamics::TreeKinematics& kicked);

/// Takes tree t's contact impulses: ν from the solver (`solved`), the position correction kept
/// for after the drift, the world momentum a floating tree has now (against which the contact
/// step's momentum guard measures the drift), and the drift's integrator started from the new
/// state with its kinematics (the kick's poses, `kicked`, with the new velocities) and M(q).
void takeTreeImpulses(const Model& model, Data& data, int t, const SolverTree& solved,
                      const dynamics::TreeKinematics& kicked);

/// Ends the contact step of tree t after its drift (contact_tree_end.cc): the position
/// correction, paid from the kinetic energy when it raises the energy and keeping a floating
/// tree's momentum; the step's energy booked (what the tree had plus the inputs' work minus what
/// it has); the guards: the energy may not rise beyond the inputs' work, a floating tree's
/// momentum must be the one its impulses give. Returns false, the fault recorded, when a guard
/// is broken; else adds the booked energy to Data::dissipated_energy. Either way leaves the
/// kinematics of the tree's state in data.tree_scratch.end_kin.
bool finishTreeContactStep(const Model& model, Data& data, int t);

/// Kinetic plus potential energy of tree t (uniform gravity), J, at the poses and velocities of
/// `kin`.
double treeEnergy(const Model& model, int t, const dynamics::TreeKinematics& kin);

/// The power of tree t's inputs, W: its joints' efforts times their `rates` plus its links'
/// applied loads paired with their velocities in `kin`.
double treeInputPower(const Model& model, const Data& data, int t,
                      const dynamics::TreeKinematics& kin, const Eigen::VectorXd& rates);

}  // namespace sim
}  // namespace cga_rigid_sim
