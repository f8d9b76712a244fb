// Joint-effort inputs (sim/input/inputs.h JointEffortInput, TimedJointEffortInput): checked
// completely and queued as one QueuedInput per joint, or refused with nothing queued; and the joint
// states users see. Internal to the sim layer (World's façade calls them).
#pragma once

#include <vector>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/input/inputs.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/reports.h"

namespace cga_rigid_sim {
namespace sim {

Result<bool> queueJointEfforts(const Model& model, Data& data, const JointEffortInput& in);
Result<bool> queueTimedJointEffort(const Model& model, Data& data, const TimedJointEffortInput& in);
/// Joint states set from outside (joint_state_edit.cc; JointStateInput: the rules there).
Result<bool> queueJointState(const Model& model, Data& data, const JointStateInput& in);
/// Every joint of every tree, trees in model order, joints parent first.
std::vector<JointStateReport> jointStateReports(const Model& model, const Data& data);

}  // namespace sim
}  // namespace cga_rigid_sim
