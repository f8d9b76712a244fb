// Admission of inputs: a wrench or impulse is checked completely against the Model and the
// current Data (rules in world.h) and resolved to a QueuedInput — or refused with an Error
// naming input, field and rule, with nothing changed. enqueue() then queues it and makes the
// room its start will need, so the step never allocates. Internal to the sim layer.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/input/input_queue.h"
#include "cga_rigid_sim/sim/input/inputs.h"
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

/// The refusal of `n` more waiting inputs like `q` for its moving body (wrench, impulse) or its
/// tree (joint effort) past ~max_queued_inputs_per_body, or past ~max_queued_inputs in all, or
/// nothing. `field` names the body or joint in the refusal.
std::optional<Error> checkQueueRoom(const Model& model, const Data& data, const std::string& input,
                                    const std::string& field, const QueuedInput& q,
                                    std::size_t n = 1);
/// The same for ~max_queued_inputs alone.
std::optional<Error> checkQueueTotal(const Model& model, const Data& data, const std::string& input,
                                     std::size_t n);
/// "body 'box'", or for a joint effort "the tree of joint 'elbow'" (trees are named by their
/// root, often "world").
std::string targetName(const Model& model, const QueuedInput& q);

/// A capacity of at least `needed` for a list that never holds more than `bound`: the next
/// power of two (so growing one by one reallocates O(log n) times), capped at the bound.
std::size_t roomFor(std::size_t needed, int bound);

/// Queues an admitted input unless the queue is at a bound (then the refusal, nothing
/// changed); for a wrench, reserves room for it among its body's loads and among the active
/// wrenches, so that its start does not allocate.
Result<bool> enqueue(const Model& model, Data& data, const QueuedInput& q,
                     const std::string& input);

}  // namespace sim
}  // namespace cga_rigid_sim
