// Admission of inputs: a wrench or impulse is checked completely against the Model and the
// current Data (rules in world.h) and resolved to a QueuedInput — or refused with an Error
// naming input, field and rule, with nothing changed. enqueue() then queues it and makes the
// room its start will need, so the step never allocates. Internal to the sim layer.
#pragma once

#include <string>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/input_queue.h"
#include "cga_rigid_sim/sim/inputs.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

/// The moving index of an input's target body (its name or any of its links), or the refusal
/// "<input>.body: unknown body '…'" / "… is static (static bodies never move)".
Result<int> movingTarget(const Model& model, const std::string& input, const std::string& name);

/// The step an input stamped s belongs to, k = floor(s/dt + kStepTolerance) (0 = the next
/// step), or the refusal "<input>.start_time: …" (too far ahead, already past).
Result<std::uint64_t> stepOf(const Model& model, const Data& data, const std::string& input,
                             double s);
Result<QueuedInput> admitWrench(const Model& model, const Data& data, const WrenchInput& in);
Result<QueuedInput> admitImpulse(const Model& model, const Data& data, const ImpulseInput& in);

/// Queues an admitted input; for a wrench, reserves room for it among its body's loads and
/// among the active wrenches.
void enqueue(Data& data, const QueuedInput& q);

}  // namespace sim
}  // namespace cga_rigid_sim
