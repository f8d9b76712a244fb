// World: the façade over the Model (what is simulated) and the Data (what changes). Each
// concern lives in its own file: model.cc (compiling and look-ups), data.cc, the stages
// (stage_*.cc), input_admission.cc (validation and queueing), wrench_schedule.cc,
// state_edit.cc (set state, reset), topology.cc (spawn, delete), reports.cc.
#include "cga_rigid_sim/sim/world.h"

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/stages.h"
#include "cga_rigid_sim/sim/worker_pool.h"
#include "contact/contact_detection.h"
#include "contact/contact_scratch.h"
#include "contact/self_collision_rules.h"
#include "sim/coasting.h"
#include "sim/controllers/controllers.h"
#include "sim/curved_bodies.h"
#include "sim/input/input_admission.h"
#include "sim/input/joint_efforts.h"
#include "sim/input/wrench_schedule.h"
#include "sim/state_edit.h"
#include "sim/topology.h"

namespace cga_rigid_sim {
namespace sim {

struct World::Impl {
  Model model;
  Data data;
  std::unique_ptr<WorkerPool> pool;  ///< null with one thread

  /// The data with every coasting body's state evaluated (coasting.h). Readers call this: a
  /// coasting body's state is a function of the step count alone, so evaluating it in a const
  /// reader changes nothing a caller can observe except the time it takes.
  const Data& current() {
    syncBodies(model, data, pool.get());
    return data;
  }
};

World::World() = default;
World::~World() = default;

Result<std::unique_ptr<World>> World::create(scene::Scene scene, const WorldConfig& config) {
  auto model = compileModel(std::move(scene), config);
  if (!model) return model.failure();
  auto data = makeData(*model);
  if (!data) return data.failure();
  // The contacts stage's scratch, made now: its collision geometry (meshes' convex hulls) serves
  // the start's checks too.
  data->contact_scratch = std::make_shared<ContactScratch>();
  CollisionCache& cache = *data->contact_scratch->cache;
  leaveOutInitialOverlaps(*model, *data, cache);
  // Bodies that start overlapping are said once (doc/contacts.md#energy).
  for (auto& w : overlapWarnings(*model, *data, cache, 1e-4))
    model->scene.warnings.push_back(std::move(w));
  std::unique_ptr<World> world(new World());
  const int threads = model->config.threads;
  world->impl_.reset(new Impl{std::move(model.value()), std::move(data.value()), nullptr});
  if (threads > 1) world->impl_->pool = std::make_unique<WorkerPool>(threads);
  return world;
}

void World::step() {
  const Model& m = impl_->model;
  Data& d = impl_->data;
  applyDueInputs(m, d);
  controlJoints(m, d);
  updateLoads(m, d);
  loadTrees(m, d);
  if (!m.curved_space) solveContacts(m, d);  // no contacts in curved space (curved_bodies.h)
  integrateTrees(m, d);
  integrateBodies(m, d, impl_->pool.get());
  expireInputs(m, d);
}

void World::step(std::uint64_t n) {
  for (std::uint64_t i = 0; i < n; ++i) step();
}

Result<bool> World::applyWrench(const WrenchInput& in) {
  auto q = admitWrench(impl_->model, impl_->data, in);
  if (!q) return q.failure();
  return enqueue(impl_->model, impl_->data, *q, "apply_wrench");
}

Result<bool> World::applyImpulse(const ImpulseInput& in) {
  auto q = admitImpulse(impl_->model, impl_->data, in);
  if (!q) return q.failure();
  return enqueue(impl_->model, impl_->data, *q, "apply_impulse");
}

void World::clearWrenches() {
  dropActiveWrenches(impl_->data);
  for (TreeData& t : impl_->data.trees) t.timed.clear();
  impl_->data.queue.clearWrenches();
}

void World::reset() {
  resetBodies(impl_->model, impl_->data);
  resetControllers(impl_->model, impl_->data);
}

const dynamics::BodyState& World::movingState(int i) const {
  syncBody(impl_->model, impl_->data, i);
  return impl_->data.bodies[i].state;
}

Result<BodyStateReport> World::getBodyState(const std::string& body) const {
  const int j = impl_->model.resolveBody(body);
  if (j < 0) return Error("get_body_state", "body", "unknown body '" + body + "'");
  if (const int i = impl_->model.moving_of_body[j]; i >= 0) syncBody(impl_->model, impl_->data, i);
  return bodyStateReport(impl_->model, impl_->data, j);
}

Result<bool> World::setBodyState(const std::string& body, const Eigen::Isometry3d& pose_root,
                                 const Eigen::Vector3d& linear_velocity_W,
                                 const Eigen::Vector3d& angular_velocity_W) {
  if (auto e = refuseInCurvedSpace(impl_->model, "set_body_state")) return *e;
  return sim::setBodyState(impl_->model, impl_->data, body, pose_root, linear_velocity_W,
                           angular_velocity_W);
}

Result<bool> World::spawnUrdf(const std::string& name, const std::string& urdf,
                              const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& linear_W,
                              const Eigen::Vector3d& angular_W, const SpawnOptions& options) {
  if (auto e = refuseInCurvedSpace(impl_->model, "spawn_urdf")) return *e;
  return sim::spawnUrdf(impl_->model, impl_->data, name, urdf, pose_root, linear_W, angular_W,
                        options);
}

Result<bool> World::deleteBody(const std::string& body) {
  return sim::deleteBody(impl_->model, impl_->data, body);
}

const WorldConfig& World::config() const { return impl_->model.config; }
const scene::Scene& World::scene() const { return impl_->model.scene; }
const Model& World::model() const { return impl_->model; }
const Data& World::data() const { return impl_->current(); }
std::uint64_t World::stepCount() const { return impl_->data.step_count; }
double World::time() const {
  return static_cast<double>(impl_->data.step_count) * impl_->model.config.dt;
}
std::uint64_t World::topologyVersion() const { return impl_->model.topology_version; }
std::size_t World::activeWrenchCount() const { return impl_->data.active_wrenches; }
std::size_t World::queuedInputCount() const { return impl_->data.queue.size(); }
std::uint64_t World::startRefusalCount() const { return impl_->data.start_refusals.count; }
std::optional<Error> World::lastStartRefusal() const {
  const Model& m = impl_->model;
  const StartRefusals& r = impl_->data.start_refusals;
  if (r.count == 0) return std::nullopt;
  const bool wrench = r.input.kind == QueuedInput::Kind::kWrench;
  const bool known = wrench ? r.input.body < static_cast<int>(m.moving.size())
                            : r.input.tree < static_cast<int>(m.trees.size());
  const std::string who = known ? targetName(m, r.input) : "its body";  // deleted since
  const std::string at = " at step " + std::to_string(r.step);
  const std::string rule =
      r.per_body
          ? who + " already has " + std::to_string(r.active) + " active " +
                (wrench ? "wrenches" : "timed joint efforts") + at +
                " (max_active_wrenches_per_body = " +
                std::to_string(m.config.max_active_wrenches_per_body) + ")"
          : std::to_string(r.active) + " wrenches and timed joint efforts already act" + at +
                " (max_active_wrenches = " + std::to_string(m.config.max_active_wrenches) + ")";
  return Error(wrench ? "apply_wrench" : "apply_joint_effort", wrench ? "body" : "joint", rule);
}

std::uint64_t World::treeFaultCount() const { return impl_->data.tree_faults.count; }
std::optional<Error> World::lastTreeFault() const {
  const TreeFaults& f = impl_->data.tree_faults;
  if (f.count == 0) return std::nullopt;
  return treeFaultError(impl_->model, f);
}

Result<bool> World::setJointEfforts(const JointEffortInput& in) {
  return queueJointEfforts(impl_->model, impl_->data, in);
}
Result<bool> World::setJointState(const JointStateInput& in) {
  return queueJointState(impl_->model, impl_->data, in);
}
Result<bool> World::applyJointEffort(const TimedJointEffortInput& in) {
  return queueTimedJointEffort(impl_->model, impl_->data, in);
}
Result<std::vector<std::string>> World::loadControllers(const scene::ParamValue& controllers,
                                                        const std::vector<std::string>& names,
                                                        const scene::ParamValue& pid_gains) {
  return sim::loadControllers(impl_->model, impl_->data, controllers, names, pid_gains);
}
Result<bool> World::commandTrajectory(const std::string& controller,
                                      const control::JointTrajectory& trajectory) {
  return queueTrajectory(impl_->model, impl_->data, controller, trajectory);
}
Result<bool> World::commandGroup(const std::string& controller, const std::vector<double>& values) {
  return queueGroupCommand(impl_->model, impl_->data, controller, values);
}
std::vector<JointStateReport> World::jointStates() const {
  return jointStateReports(impl_->model, impl_->data);
}

std::vector<MomentumReport> World::momentum() const {
  return momentumReports(impl_->model, impl_->current());
}
std::vector<ContactReport> World::contacts() const {
  return contactReports(impl_->model, impl_->data);
}
const std::vector<Contact>& World::lastContacts() const { return impl_->data.contacts; }
const dynamics::Loads& World::lastLoads(int i) const { return impl_->data.bodies[i].loads; }

std::vector<BodyStateReport> World::bodyStates() const {
  return bodyStateReports(impl_->model, impl_->current());
}
std::vector<FramePose> World::movingFrames() const {
  return sim::movingFrames(impl_->model, impl_->current());
}
std::vector<FramePose> World::staticFrames() const { return sim::staticFrames(impl_->model); }
std::vector<std::string> World::selfCollisionSummary() const {
  return sim::selfCollisionSummary(impl_->model);
}

std::vector<std::pair<std::string, std::string>> World::selfCollisionPairs() const {
  std::vector<std::pair<std::string, std::string>> out;
  const Model& m = impl_->model;
  for (const auto& [a, b] : m.self_collision.allowed())
    out.emplace_back(m.scene.bodies[a].name, m.scene.bodies[b].name);
  return out;
}

std::string World::summary() const { return worldSummary(impl_->model, impl_->current()); }

std::vector<CurvedMomentumReport> World::curvedMomentum() const {
  return curvedMomentumReports(impl_->model, impl_->data);
}

}  // namespace sim
}  // namespace cga_rigid_sim
