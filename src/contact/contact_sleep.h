// Sleeping (doc/contacts.md#sleeping): an island of bodies in contact (bodies joined by
// contacts between them; the ground and static bodies join nothing) whose contact points all
// move slower than kSleepSpeed for kSleepTime (|v| + |ω| |p − x| at each contact point p: a
// rolling ball's contact point rests, the ball does not) falls asleep: its velocities are set to
// zero (the kinetic energy left is booked as dissipated), it is neither detected, solved nor
// integrated, and its last contacts are reported as they were. It wakes, as a whole, when a
// body of it is changed from outside (its state set, an impulse, a wrench), when gravity or
// the scene's topology changes, or when an awake body (or a tree's link) touches it.
// WorldConfig::contact_sleeping = false turns it off.
#pragma once

#include <cstdint>
#include <vector>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/contact/contact.h"
#include "cga_rigid_sim/math/union_find.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

/// Contact points slower than this, m/s, count as still: 1e-4 of the kick g h at 1 ms, five
/// orders below any motion a step resolves, far above a settled stack's round-off (1e-16).
constexpr double kSleepSpeed = 1e-6;
/// … for this long, s (at least one step).
constexpr double kSleepTime = 0.2;

struct SleepState {
  std::uint64_t topology = ~std::uint64_t{0};  ///< the topology the arrays below are for
  std::vector<int> still;    ///< per moving index: steps in contact and still, in a row
  std::vector<int> island;   ///< per moving index: −1 awake, else its island's label
  std::vector<char> asleep;  ///< per moving index: the detection's mask
  std::vector<Eigen::Quaterniond> rotation;  ///< per sleeper: the pose it fell asleep in
  std::vector<Eigen::Vector3d> position;
  std::vector<Contact> contacts;  ///< the sleepers' contacts, as they were
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  int count = 0;          ///< sleepers
  bool counting = false;  ///< some awake body has still steps counted
  // Scratch of fallAsleep, per moving index.
  math::UnionFind sets;  ///< bodies joined by contacts and trees
  std::vector<double> speed;
  std::vector<char> blocked;
  std::vector<char> woken;  ///< wakeIsland's
};

/// Before detection: wakes the islands changed from outside (all of them when gravity or the
/// topology changed, or sleeping is off), and marks the remaining sleepers as stepped (the
/// integration leaves them alone).
void wakeChanged(const Model& model, Data& data, SleepState& sleep);
/// After detection: wakes the islands of sleepers in `found` (an awake body touches them).
/// True when any woke: their own contacts are then to be detected.
bool wakeTouched(const Model& model, Data& data, SleepState& sleep,
                 const std::vector<Contact>& found);
/// After the solve (data.contacts: this step's): counts each awake body's still steps, puts
/// the islands still long enough to sleep, and appends the sleepers' contacts to
/// data.contacts.
void fallAsleep(const Model& model, Data& data, SleepState& sleep);

}  // namespace sim
}  // namespace cga_rigid_sim
