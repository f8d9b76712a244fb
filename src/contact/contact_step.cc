// The contacts stage (doc/contacts.md): detection at the step's start, then for every body that
// touches something a kick by its loads and the contact impulses, solved together; the
// integration then drifts those bodies torque-free and the trees by their own integrators,
// and the contact step ends in this folder: contact_drift.cc for a body (called by
// stage_integrate.cc), contact_tree_end.cc for a tree (correction, energy book and guards,
// called by stage_trees.cc). Bodies that touch nothing are left alone: they keep their exact or
// symplectic path. The sub-stages are in contact_step.h.
#include "contact/contact_step.h"

#include "cga_rigid_sim/sim/stages.h"

namespace cga_rigid_sim {
namespace sim {

bool detectContactsOfAwake(const Model& model, Data& data, ContactScratch& S) {
  S.found.clear();
  data.contact_sweeps = 0;
  detectContacts(model, data, *S.cache, S.found, &S.sleep.asleep);
  while (wakeTouched(model, data, S.sleep, S.found)) {  // their own contacts too
    S.found.clear();
    detectContacts(model, data, *S.cache, S.found, &S.sleep.asleep);
  }
  if (S.found.empty()) {
    data.contacts.clear();
    return false;
  }
  return true;
}

void reportContacts(Data& data, const ContactScratch& S) {
  // The contacts of this step, with their impulses, for reports and the next warm start.
  data.contacts.assign(S.found.begin(), S.found.end());
  for (std::size_t k = 0; k < S.found.size(); ++k) {
    const ContactRow& r = S.rows[k];
    data.contacts[k].normal_impulse = r.lambda_n;
    data.contacts[k].friction_impulse_W = r.lambda_t.x() * r.t1 + r.lambda_t.y() * r.t2;
    data.contacts[k].pyramid_share = r.pyramid_share;
  }
  data.contacts.insert(data.contacts.end(), S.landed.begin(), S.landed.end());
}

void solveContacts(const Model& model, Data& data) {
  if (!data.contact_scratch) data.contact_scratch = std::make_shared<ContactScratch>();
  ContactScratch& S = *data.contact_scratch;
  wakeChanged(model, data, S.sleep);
  [&] {  // the awake bodies' contact step; each sub-stage may end it
    if (!detectContactsOfAwake(model, data, S)) return;
    if (!kickContactBodies(model, data, S)) return;
    if (!keepClosingContacts(model, data, S)) return;
    const SolverSettings settings = contactSettings(model);
    if (!landBodies(model, data, S, settings)) return;
    makeRows(model, data, S);
    solveRows(model, data, S, settings);
    applyToBodies(model, data, S);
    reportContacts(data, S);
  }();
  fallAsleep(model, data, S.sleep);
}

}  // namespace sim
}  // namespace cga_rigid_sim
