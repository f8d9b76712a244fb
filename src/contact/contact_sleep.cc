// Sleeping islands (contact_sleep.h, doc/contacts.md#sleeping): waking what was changed or
// touched before detection, and after the solve counting each body's still steps and putting
// the islands still long enough to sleep.
#include "contact/contact_sleep.h"

#include <algorithm>
#include <cmath>

#include "cga_rigid_sim/body/derived.h"
#include "contact/contact_trees.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// The moving index of scene body j, or −1 (the ground, a static body).
int movingOf(const Model& model, int j) { return j < 0 ? -1 : model.moving_of_body[j]; }

void wakeIsland(const Model& model, Data& data, SleepState& S, int label) {
  S.woken.assign(S.island.size(), 0);
  for (std::size_t i = 0; i < S.island.size(); ++i) {
    if (S.island[i] != label) continue;
    S.woken[i] = 1;
    S.island[i] = -1;
    S.asleep[i] = 0;
    S.still[i] = 0;
    --S.count;
    MovingBodyData& b = data.bodies[i];
    if (b.contact_step == MovingBodyData::ContactStep::kDone)
      b.contact_step = MovingBodyData::ContactStep::kNone;
    if (const int t = model.tree_of_moving[i]; t >= 0) {
      data.trees[t].asleep = false;
      data.trees[t].integrator->reset();
    }
  }
  // Its contacts are detected again from now on (last step's, in data.contacts, warm-start
  // them).
  const auto of_island = [&](const Contact& c) {
    const int a = movingOf(model, c.body_a), b = movingOf(model, c.body_b);
    return (a >= 0 && S.woken[a]) || (b >= 0 && S.woken[b]);
  };
  S.contacts.erase(std::remove_if(S.contacts.begin(), S.contacts.end(), of_island),
                   S.contacts.end());
}

// Whether sleeping tree link i's tree was changed from outside: a velocity (an impulse on a
// link), efforts other than those it fell asleep under, timed efforts, a pose set from outside.
bool treeChanged(const Model& model, const Data& data, int i) {
  const int t = model.tree_of_moving[i];
  if (t < 0) return false;
  const TreeData& td = data.trees[t];
  return !td.state.v.isZero(0.0) || !td.state.omega_0.rot.isZero(0.0) ||
         !td.state.omega_0.trans.isZero(0.0) || !td.timed.empty() ||
         td.held_effort != td.asleep_effort || td.state.q != td.asleep_q;
}

// The fastest point of tree link i within its own size, |v| + |ω| ℓ with ℓ twice its largest
// radius of gyration (a link's reach about its centre of mass, roughly).
double linkSpeed(const Model& model, const Data& data, int i) {
  const dynamics::Inertia& I = model.moving[i].inertia;
  const double reach = 2.0 * std::sqrt(I.principalMoments().maxCoeff() / I.mass());
  const dynamics::BodyState& s = data.bodies[i].state;
  return dynamics::comVelocity_W(s, model.lambda).norm() +
         dynamics::angularVelocity_W(s).norm() * reach;
}

// Tree t falls asleep: at rest where it is, not stepped. Its kinetic energy is booked as
// dissipated — from before its contact step's kick, which is dropped with its drift (the pose
// does not move, so the loads did no work).
void putTreeToSleep(const Model& model, Data& data, int t) {
  TreeData& td = data.trees[t];
  const dynamics::ArticulatedBody& tree = model.trees[t].body;
  dynamics::TreeKinematics& kin = data.tree_scratch.sleep_kin;
  dynamics::treeKinematics(tree, td.state, kin);
  const double E_now = treeEnergy(model, t, kin);
  const double T_now = dynamics::kineticEnergy(tree, kin);
  data.dissipated_energy += td.contact_kicked ? td.contact_energy_start - (E_now - T_now) : T_now;
  td.state.v.setZero();
  td.state.omega_0 = cga::Bivelocity();
  td.contact_kicked = false;
  td.asleep = true;
  td.asleep_effort = td.held_effort;
  td.asleep_q = td.state.q;
  td.integrator->reset();
  writeTreeBodies(model, data, t);
}

void reset(const Model& model, Data& data, SleepState& S) {
  const std::size_t n = data.bodies.size();
  for (std::size_t i = 0; i < S.asleep.size() && i < n; ++i)
    if (S.asleep[i] && data.bodies[i].contact_step == MovingBodyData::ContactStep::kDone)
      data.bodies[i].contact_step = MovingBodyData::ContactStep::kNone;
  for (TreeData& td : data.trees) td.asleep = false;
  S.topology = model.topology_version;
  S.still.assign(n, 0);
  S.island.assign(n, -1);
  S.asleep.assign(n, 0);
  S.rotation.resize(n);
  S.position.resize(n);
  S.contacts.clear();
  S.gravity = model.scene.gravity_W;
  S.count = 0;
  S.counting = false;
}

// The fastest contact point of each awake body in this step's contacts (−1: none), the
// landing bodies blocked, and the bodies joined by their contacts.
void contactSpeeds(const Model& model, const Data& data, SleepState& S) {
  const std::size_t n = data.bodies.size();
  const double lambda = model.lambda;
  S.speed.assign(n, -1.0);  // −1: no contact this step
  S.blocked.assign(n, 0);
  S.sets.reset(static_cast<int>(n));
  for (const Contact& c : data.contacts) {
    const int a = movingOf(model, c.body_a), b = movingOf(model, c.body_b);
    for (const int i : {a, b}) {
      if (i < 0 || S.asleep[i] || S.speed[i] >= kSleepSpeed) continue;  // known to move
      const MovingBodyData& body = data.bodies[i];
      // A landing body is mid-flight within the step.
      if (body.contact_step == MovingBodyData::ContactStep::kDone) {
        S.blocked[i] = 1;
        continue;
      }
      // A link moves with its tree: its speed is the tree's (joinTrees).
      if (model.tree_of_moving[i] >= 0) {
        S.speed[i] = std::max(S.speed[i], 0.0);
        continue;
      }
      // Not the contact point's own velocity (a rolling ball's is zero): the body's fastest
      // point within reach of its contacts, |v| + |ω| |p − x|.
      const double arm = (c.point_W - dynamics::comPosition_W(body.state, lambda)).norm();
      const double v = dynamics::comVelocity_W(body.state, lambda).norm() +
                       dynamics::angularVelocity_W(body.state).norm() * arm;
      S.speed[i] = std::max(S.speed[i], v);
    }
    if (a >= 0 && b >= 0) S.sets.join(a, b);
  }
}

// A tree with a link in contact: every link joins its island, and its speed is the tree's
// fastest link's (a swinging arm keeps a robot awake whose feet rest). Timed efforts keep it
// awake: they end by themselves; so do servos (their references move with their controllers).
void joinTrees(const Model& model, const Data& data, SleepState& S) {
  for (std::size_t t = 0; t < model.trees.size(); ++t) {
    const TreeModel& tm = model.trees[t];
    int in_contact = -1;
    for (int b = tm.body.floating() ? 0 : 1; b < tm.body.bodyCount() && in_contact < 0; ++b)
      if (S.speed[tm.movingOf(b)] >= 0 && !S.asleep[tm.movingOf(b)]) in_contact = tm.movingOf(b);
    if (in_contact < 0) continue;
    double speed = 0.0;
    for (int b = tm.body.floating() ? 0 : 1; b < tm.body.bodyCount(); ++b)
      speed = std::max(speed, linkSpeed(model, data, tm.movingOf(b)));
    const bool blocked = !data.trees[t].timed.empty() || data.trees[t].loads.servos.active();
    for (int b = tm.body.floating() ? 0 : 1; b < tm.body.bodyCount(); ++b) {
      const int i = tm.movingOf(b);
      S.speed[i] = speed;
      S.blocked[i] = S.blocked[i] || blocked;
      S.sets.join(i, in_contact);
    }
  }
}

// Still steps in a row; an island is blocked by any member that is not still for `steps`.
void countStillSteps(SleepState& S, std::size_t n, int steps) {
  S.counting = false;
  for (std::size_t i = 0; i < n; ++i) {
    if (S.asleep[i]) continue;
    S.still[i] = S.speed[i] >= 0 && S.speed[i] < kSleepSpeed ? S.still[i] + 1 : 0;
    S.counting = S.counting || S.still[i] > 0;
    if (S.blocked[i] || S.still[i] < steps) S.blocked[S.sets.find(static_cast<int>(i))] = 1;
  }
}

// Moving body i falls asleep in the island `root`: it stays where the contact stage left it (no
// drift), at rest. The energy book had it drift by h v + shift and keep its kinetic energy:
// both go to the dissipated energy instead, so the book still balances.
void putToSleep(const Model& model, Data& data, SleepState& S, int i, int root) {
  const double lambda = model.lambda, h = model.config.dt;
  const Eigen::Vector3d& g = model.scene.gravity_W;
  MovingBodyData& b = data.bodies[i];
  if (const int t = model.tree_of_moving[i]; t >= 0) {  // its tree sleeps as a whole
    if (!data.trees[t].asleep) putTreeToSleep(model, data, t);
  } else {
    const dynamics::Inertia& I = model.moving[i].inertia;
    const Eigen::Vector3d v = dynamics::comVelocity_W(b.state, lambda);
    data.dissipated_energy +=
        I.kineticEnergy(b.state.omega_B, lambda) - I.mass() * g.dot(h * v + b.contact_shift_W);
  }
  b.state.omega_B = cga::Bivelocity();
  b.contact_shift_W.setZero();
  b.contact_step = MovingBodyData::ContactStep::kDone;
  S.island[i] = root;
  S.asleep[i] = 1;
  S.rotation[i] = b.state.M_WB.rotation();
  S.position[i] = b.state.M_WB.translation(lambda);
  ++S.count;
}

}  // namespace

void wakeChanged(const Model& model, Data& data, SleepState& S) {
  if (!model.config.contact_sleeping || S.topology != model.topology_version ||
      S.still.size() != data.bodies.size() || S.gravity != model.scene.gravity_W) {
    if (S.count > 0 || S.topology != model.topology_version ||
        S.still.size() != data.bodies.size() || S.gravity != model.scene.gravity_W)
      reset(model, data, S);
    return;
  }
  if (S.count == 0) return;
  const double lambda = model.lambda;
  for (std::size_t i = 0; i < data.bodies.size(); ++i) {
    if (!S.asleep[i]) continue;
    const MovingBodyData& b = data.bodies[i];
    // Set from outside: any velocity (an impulse, a state set), a moved pose, a wrench.
    const bool changed = !b.state.omega_B.rot.isZero(0.0) || !b.state.omega_B.trans.isZero(0.0) ||
                         b.loads.hasApplied() || b.loads_dirty ||
                         b.state.M_WB.rotation().coeffs() != S.rotation[i].coeffs() ||
                         b.state.M_WB.translation(lambda) != S.position[i];
    if (changed || treeChanged(model, data, i)) wakeIsland(model, data, S, S.island[i]);
  }
  for (std::size_t i = 0; i < data.bodies.size(); ++i)
    if (S.asleep[i]) data.bodies[i].contact_step = MovingBodyData::ContactStep::kDone;
}

bool wakeTouched(const Model& model, Data& data, SleepState& S, const std::vector<Contact>& found) {
  if (S.count == 0) return false;
  bool woke = false;
  for (const Contact& c : found)
    for (const int j : {c.body_a, c.body_b}) {
      const int i = movingOf(model, j);
      if (i >= 0 && S.asleep[i]) {
        wakeIsland(model, data, S, S.island[i]);
        woke = true;
      }
    }
  return woke;
}

void fallAsleep(const Model& model, Data& data, SleepState& S) {
  if (!model.config.contact_sleeping) return;
  // Nothing touches anything and no still steps are counted: nothing can fall asleep, and the
  // per-body passes below would cost every free body a pass each step (doc/decisions.md).
  if (data.contacts.empty() && S.contacts.empty() && !S.counting) return;
  const std::size_t n = data.bodies.size();
  const double h = model.config.dt;
  const int steps = std::max(1, static_cast<int>(std::ceil(kSleepTime / h - 1e-9)));
  contactSpeeds(model, data, S);
  joinTrees(model, data, S);
  countStillSteps(S, n, steps);
  bool fell = false;
  for (std::size_t i = 0; i < n; ++i) {
    if (S.asleep[i] || S.speed[i] < 0) continue;
    const int root = S.sets.find(static_cast<int>(i));
    if (S.blocked[root]) continue;
    putToSleep(model, data, S, static_cast<int>(i), root);
    fell = true;
  }
  if (fell) {
    // The new sleepers' contacts (data.contacts holds the awake bodies' only, and an island
    // sleeps whole): every contact of a sleeper.
    for (const Contact& c : data.contacts) {
      const int a = movingOf(model, c.body_a), b = movingOf(model, c.body_b);
      if ((a >= 0 && S.asleep[a]) || (b >= 0 && S.asleep[b])) S.contacts.push_back(c);
    }
  }
  data.contacts.insert(data.contacts.end(), S.contacts.begin(), S.contacts.end());
}

}  // namespace sim
}  // namespace cga_rigid_sim
