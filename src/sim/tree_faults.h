// Recording a fault of a tree step (TreeFaults, doc/articulated.md#faults): the tree stage's
// guards and the contact step's (contact/contact_tree_end.cc) count and describe it the same way.
// Internal to the sim layer.
#pragma once

#include "cga_rigid_sim/sim/data.h"

namespace cga_rigid_sim {
namespace sim {

// Counts a fault of tree t and describes it (TreeFaults); the step then undoes it.
inline TreeFaults& recordTreeFault(Data& data, int t, TreeFaults::Rule rule) {
  TreeFaults& f = data.tree_faults;
  ++f.count;
  f.tree = t;
  f.step = data.step_count + 1;
  f.rule = rule;
  f.joint = f.body_a = f.body_b = -1;
  f.value = f.bound = 0.0;
  return f;
}

}  // namespace sim
}  // namespace cga_rigid_sim
