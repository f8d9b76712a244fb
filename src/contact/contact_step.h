// The contact step's sub-stages (doc/contacts.md#time-stepping), each over
// (const Model&, Data&, ContactScratch&), in the order contact_step.cc conducts them:
//
//   detect     → the awake bodies' contacts at the step's start (waking what they touch)
//   kick       → solver slots for every body and tree in a contact, the loads' kick
//   keep       → speculative contacts whose gap stays open over the step dropped
//   land       → bodies that land on the ground plane within the step stepped to the instant
//   rows       → the solver's rows, warm-started from last step's impulses of the same contacts
//   solve      → velocities and positions; trees take their impulses and their guards' references
//   apply      → free bodies take their impulses, their position correction and their book
//   report     → Data::contacts with the impulses
//
// A sub-stage that leaves no contact to go on with ends the step (returns false) with
// Data::contacts set.
#pragma once

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "contact/contact_scratch.h"
#include "contact/contact_solver.h"

namespace cga_rigid_sim {
namespace sim {

/// Gaps below this count as touching (the solver's residual lifts a resting body by ~1e-11 m).
constexpr double kTouching = 1e-9;

bool detectContactsOfAwake(const Model& model, Data& data, ContactScratch& S);
bool kickContactBodies(const Model& model, Data& data, ContactScratch& S);
bool keepClosingContacts(const Model& model, Data& data, ContactScratch& S);
/// The solver's settings for this model's step.
SolverSettings contactSettings(const Model& model);
bool landBodies(const Model& model, Data& data, ContactScratch& S, const SolverSettings& st);
void makeRows(const Model& model, Data& data, ContactScratch& S);
void solveRows(const Model& model, Data& data, ContactScratch& S, const SolverSettings& st);
void applyToBodies(const Model& model, Data& data, ContactScratch& S);
void reportContacts(Data& data, const ContactScratch& S);

}  // namespace sim
}  // namespace cga_rigid_sim
