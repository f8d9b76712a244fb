// The sensors of a World at run time (sensors.h, doc/sensors.md).
#include "cga_rigid_sim/sensor/sensors.h"

#include <algorithm>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/math/rpy.h"

namespace cga_rigid_sim {
namespace sensor {
namespace {

// Noise streams per sensor: the SDF channels of each axis, then the plugin's gaussianNoise.
constexpr std::uint64_t kStreamsPerSensor = 16;
constexpr std::uint64_t kAngularStream = 0, kLinearStream = 3, kPluginStream = 6;

}  // namespace

Sensors::Sensors(const sim::World& world, std::uint64_t seed) : seed_(seed) {
  const sim::Model& model = world.model();
  const double lambda = model.lambda;
  std::uint64_t k = 0;
  for (const scene::SensorModel& s : world.scene().sensors.sensors) {
    Entry e;
    e.model = s;
    e.stream = k++ * kStreamsPerSensor;
    const auto owner = model.link_owner.find(s.link);
    if (owner == model.link_owner.end()) {
      // Its link is in no body (not expected: a delete takes its sensors out): it reads nothing.
      entries_.push_back(std::move(e));
      continue;
    }
    e.body = owner->second.first;
    e.moving = model.moving_of_body[e.body];
    e.X_BL = model.scene.bodies[e.body].links[owner->second.second].M_BL.toIsometry(lambda);
    e.X_BS = e.X_BL * s.X_LS;
    if (s.kind == scene::SensorKind::kContact) resolveCollisions(world, owner->second.second, &e);
    if ((s.kind == scene::SensorKind::kGroundTruth || s.kind == scene::SensorKind::kContact) &&
        !s.reference_link.empty() && s.reference_link != "world") {
      const auto ref = model.link_owner.find(s.reference_link);
      if (ref != model.link_owner.end()) {
        e.reference_body = ref->second.first;
        e.X_RB_L =
            model.scene.bodies[e.reference_body].links[ref->second.second].M_BL.toIsometry(lambda);
      }
    }
    if (s.kind == scene::SensorKind::kForceTorque) resolveJoint(world, &e);
    for (int a = 0; a < 3; ++a) {
      e.angular_velocity[a] =
          NoisyChannel(s.angular_velocity_noise[a], seed, e.stream + kAngularStream + a);
      e.linear_acceleration[a] =
          NoisyChannel(s.linear_acceleration_noise[a], seed, e.stream + kLinearStream + a);
    }
    const dynamics::BodyState now = stateOf(e.moving, e.body, world);
    e.initial_orientation = now.M_WB.rotation() * Eigen::Quaterniond(e.X_BS.linear());
    entries_.push_back(std::move(e));
  }
}

// A bumper's collision shapes: the link's (its k-th alone when the sensor names one).
void Sensors::resolveCollisions(const sim::World& world, int link, Entry* e) {
  const std::vector<scene::CollisionShape>& shapes = world.model().scene.bodies[e->body].shapes;
  int k = 0;
  for (std::size_t j = 0; j < shapes.size(); ++j) {
    if (shapes[j].link_index != link) continue;
    if (e->model.collision < 0 || e->model.collision == k) e->shapes.push_back(static_cast<int>(j));
    ++k;
  }
}

// The subtree below a force-torque sensor's joint, and its parent link's place.
void Sensors::resolveJoint(const sim::World& world, Entry* e) {
  const sim::Model& model = world.model();
  const auto joint = model.joint_by_name.find(e->model.joint);
  if (joint == model.joint_by_name.end()) return;  // a fixed joint, merged: not measured
  const auto [t, k] = joint->second;
  const sim::TreeModel& tree = model.trees[t];
  const int child = k + 1;
  std::vector<bool> below(tree.body.bodyCount(), false);
  below[child] = true;
  e->subtree.push_back(tree.movingOf(child));
  for (int b = child + 1; b < tree.body.bodyCount(); ++b)
    if (below[tree.body.parentOf(b)]) {
      below[b] = true;
      e->subtree.push_back(tree.movingOf(b));
    }
  e->subtree_before.resize(e->subtree.size());
  e->in_subtree.assign(model.moving.size(), false);
  for (int i : e->subtree) e->in_subtree[i] = true;
  const scene::JointModel& jm = model.scene.joints[tree.scene_joint[k]];
  e->parent_body = jm.parent_body;
  const auto parent = model.link_owner.find(jm.parent_link);
  if (parent != model.link_owner.end())
    e->X_PL = model.scene.bodies[parent->second.first].links[parent->second.second].M_BL.toIsometry(
        model.lambda);
}

dynamics::BodyState Sensors::stateOf(int moving, int body, const sim::World& world) const {
  if (moving >= 0) return world.movingState(moving);
  dynamics::BodyState s;
  s.M_WB = world.model().scene.bodies[body].M_WB0;
  return s;
}

dynamics::BodyState Sensors::bodyState(std::size_t k, const sim::World& world) const {
  return stateOf(entries_[k].moving, entries_[k].body, world);
}

void Sensors::remember(std::size_t k, const sim::World& world) {
  Entry& e = entries_[k];
  if (e.body < 0) return;
  e.before = stateOf(e.moving, e.body, world);
  for (std::size_t b = 0; b < e.subtree.size(); ++b)
    e.subtree_before[b] = world.movingState(e.subtree[b]);
  e.before_step = world.stepCount();
}

bool Sensors::ready(std::size_t k, const sim::World& world) const {
  return entries_[k].body >= 0 && entries_[k].before_step + 1 == world.stepCount();
}

ImuSample Sensors::imu(std::size_t k, const sim::World& world, std::uint64_t n) const {
  const Entry& e = entries_[k];
  const sim::Model& model = world.model();
  ImuSample s = imuSample(e.before, stateOf(e.moving, e.body, world), model.config.dt, e.X_BS,
                          model.scene.gravity_W, model.lambda);
  if (e.model.initial_orientation_as_reference)
    s.orientation_WS = e.initial_orientation.conjugate() * s.orientation_WS;
  for (int a = 0; a < 3; ++a) {
    s.angular_velocity_S[a] = e.angular_velocity[a].apply(s.angular_velocity_S[a], n);
    s.linear_acceleration_S[a] = e.linear_acceleration[a].apply(s.linear_acceleration_S[a], n);
  }
  if (const double sigma = e.model.gaussian_noise; sigma > 0) {
    // gazebo_ros's <gaussianNoise>: on each component of the three, the quaternion's included
    // (renormalised here, so that it stays a rotation).
    const std::uint64_t stream = e.stream + kPluginStream;
    for (int a = 0; a < 3; ++a) {
      s.angular_velocity_S[a] += sigma * standardNormal(seed_, stream + a, n);
      s.linear_acceleration_S[a] += sigma * standardNormal(seed_, stream + 3 + a, n);
    }
    Eigen::Vector4d q = s.orientation_WS.coeffs();
    for (int a = 0; a < 4; ++a) q[a] += sigma * standardNormal(seed_, stream + 6 + a, n);
    s.orientation_WS = Eigen::Quaterniond(q).normalized();
  }
  return s;
}

OdometrySample Sensors::odometry(std::size_t k, const sim::World& world, std::uint64_t n) const {
  const Entry& e = entries_[k];
  const double lambda = world.model().lambda;
  // The link's origin L: pose and world velocity (v_c + ω × (x_L − x_c)).
  auto originOf = [&](int moving, int body, const Eigen::Isometry3d& X_BL, Eigen::Isometry3d* X_WL,
                      Eigen::Vector3d* v_W, Eigen::Vector3d* w_W) {
    const dynamics::BodyState s = stateOf(moving, body, world);
    const Eigen::Isometry3d X_WB = s.M_WB.toIsometry(lambda);
    *X_WL = X_WB * X_BL;
    *w_W = dynamics::angularVelocity_W(s);
    *v_W =
        dynamics::comVelocity_W(s, lambda) + w_W->cross(X_WL->translation() - X_WB.translation());
  };
  Eigen::Isometry3d X_WL;
  Eigen::Vector3d v_W, w_W;
  originOf(e.moving, e.body, e.X_BL, &X_WL, &v_W, &w_W);
  OdometrySample o;
  if (e.reference_body < 0) {
    o.X_RL = X_WL;
    o.linear_R = v_W;
    o.angular_R = w_W;
  } else {
    Eigen::Isometry3d X_WR;
    Eigen::Vector3d v_R, w_R;
    originOf(world.model().moving_of_body[e.reference_body], e.reference_body, e.X_RB_L, &X_WR,
             &v_R, &w_R);
    const Eigen::Matrix3d R_RW = X_WR.linear().transpose();
    o.X_RL = X_WR.inverse() * X_WL;
    o.linear_R = R_RW * (v_W - v_R);
    o.angular_R = R_RW * (w_W - w_R);
  }
  // gazebo_ros_p3d's offsets: xyzOffsets added to the position, rpyOffsets turning the attitude.
  o.X_RL.translation() += e.model.xyz_offset;
  o.X_RL.linear() = math::rotationFromRpy(e.model.rpy_offset) * o.X_RL.linear();
  if (const double sigma = e.model.gaussian_noise; sigma > 0) {
    // As gazebo_ros_p3d: on the position and both velocities (not the attitude).
    const std::uint64_t stream = e.stream + kPluginStream;
    for (int a = 0; a < 3; ++a) {
      o.X_RL.translation()[a] += sigma * standardNormal(seed_, stream + a, n);
      o.linear_R[a] += sigma * standardNormal(seed_, stream + 3 + a, n);
      o.angular_R[a] += sigma * standardNormal(seed_, stream + 6 + a, n);
    }
  }
  return o;
}

WrenchSample Sensors::wrench(std::size_t k, const sim::World& world, std::uint64_t n) const {
  const Entry& e = entries_[k];
  WrenchSample w;
  if (e.subtree.empty()) return w;
  const sim::Model& model = world.model();
  const double lambda = model.lambda, h = model.config.dt;
  const Eigen::Vector3d& g_W = model.scene.gravity_W;
  // The child link's frame now: the point the angular momenta are taken about (fixed in the
  // world over the step) and the default frame of the reading.
  const Eigen::Isometry3d X_WC = stateOf(e.moving, e.body, world).M_WB.toIsometry(lambda) * e.X_BL;
  const Eigen::Vector3d p = X_WC.translation();
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  const std::vector<bool>& in_subtree = e.in_subtree;
  for (std::size_t b = 0; b < e.subtree.size(); ++b) {
    const int i = e.subtree[b];
    const dynamics::Inertia& I = model.moving[i].inertia;
    const dynamics::BodyState& s0 = e.subtree_before[b];
    const dynamics::BodyState& s1 = world.movingState(i);
    const Eigen::Vector3d P0 = dynamics::linearMomentum_W(I, s0, lambda);
    const Eigen::Vector3d P1 = dynamics::linearMomentum_W(I, s1, lambda);
    const Eigen::Vector3d L0 =
        (dynamics::comPosition_W(s0, lambda) - p).cross(P0) + dynamics::angularMomentumCom_W(I, s0);
    const Eigen::Vector3d L1 =
        (dynamics::comPosition_W(s1, lambda) - p).cross(P1) + dynamics::angularMomentumCom_W(I, s1);
    // Rate of momentum less gravity (at the step's mean centre, as the flow moves it).
    const Eigen::Vector3d x_mid =
        0.5 * (dynamics::comPosition_W(s0, lambda) + dynamics::comPosition_W(s1, lambda));
    const Eigen::Vector3d weight = I.mass() * g_W;
    force += (P1 - P0) / h - weight;
    torque += (L1 - L0) / h - (x_mid - p).cross(weight);
  }
  // Wrenches applied to the subtree's links (~apply_wrench), at the step's mean pose (the mean
  // of its ends, as for gravity).
  for (std::size_t b = 0; b < e.subtree.size(); ++b) {
    const dynamics::Loads& loads = world.lastLoads(e.subtree[b]);
    for (const dynamics::AppliedLoad& l : loads.applied())
      for (const dynamics::BodyState* s :
           {&e.subtree_before[b], &world.movingState(e.subtree[b])}) {
        const Eigen::Isometry3d X_WB = s->M_WB.toIsometry(lambda);
        const bool world_axes = l.axes == dynamics::Axes::kWorld;
        const Eigen::Vector3d f_W = world_axes ? l.F.f : Eigen::Vector3d(X_WB.linear() * l.F.f);
        const Eigen::Vector3d c_W =
            world_axes ? l.couple : Eigen::Vector3d(X_WB.linear() * l.couple);
        force -= 0.5 * f_W;
        torque -= 0.5 * ((X_WB * l.point_B - p).cross(f_W) + c_W);
      }
  }
  // Contact impulses of the step on the subtree's links, as their mean force.
  for (const sim::Contact& c : world.lastContacts()) {
    const auto inSubtree = [&](int j) {
      if (j == sim::kGroundPlane) return false;
      const int i = model.moving_of_body[j];
      return i >= 0 && in_subtree[i];
    };
    const bool on_a = inSubtree(c.body_a), on_b = inSubtree(c.body_b);
    if (on_a == on_b) continue;  // outside, or inside on both sides
    const Eigen::Vector3d f = (c.normal_impulse * c.normal_W + c.friction_impulse_W) / h;
    const Eigen::Vector3d f_sub = on_a ? f : Eigen::Vector3d(-f);
    force -= f_sub;
    torque -= (c.point_W - p).cross(f_sub);
  }
  // The wrench on the child from the parent, about p in world axes. Its frame: the child link,
  // the parent link or the sensor (its <pose> in the child link).
  Eigen::Isometry3d X_WF = X_WC;
  if (e.model.wrench_frame == scene::WrenchFrame::kParent)
    X_WF = (e.parent_body < 0 ? Eigen::Isometry3d::Identity()
                              : stateOf(model.moving_of_body[e.parent_body], e.parent_body, world)
                                        .M_WB.toIsometry(lambda) *
                                    e.X_PL);
  else if (e.model.wrench_frame == scene::WrenchFrame::kSensor)
    X_WF = X_WC * e.model.X_LS;
  const Eigen::Vector3d torque_F = torque - (X_WF.translation() - p).cross(force);
  const double sign =
      e.model.measure_direction == scene::MeasureDirection::kParentToChild ? 1.0 : -1.0;
  w.force = sign * (X_WF.linear().transpose() * force);
  w.torque = sign * (X_WF.linear().transpose() * torque_F);
  if (const double sigma = e.model.gaussian_noise; sigma > 0) {
    const std::uint64_t stream = e.stream + kPluginStream;
    for (int a = 0; a < 3; ++a) {
      w.force[a] += sigma * standardNormal(seed_, stream + a, n);
      w.torque[a] += sigma * standardNormal(seed_, stream + 3 + a, n);
    }
  }
  return w;
}

std::vector<sim::ContactReport> Sensors::contacts(std::size_t k, const sim::World& world) const {
  const Entry& e = entries_[k];
  const sim::Model& model = world.model();
  const auto mine = [&e](int body, int shape) {
    return body == e.body && std::find(e.shapes.begin(), e.shapes.end(), shape) != e.shapes.end();
  };
  // The frame the contacts are expressed in: the world, or frameName's link now.
  Eigen::Isometry3d X_FW = Eigen::Isometry3d::Identity();
  if (e.reference_body >= 0)
    X_FW = (stateOf(model.moving_of_body[e.reference_body], e.reference_body, world)
                .M_WB.toIsometry(model.lambda) *
            e.X_RB_L)
               .inverse();
  std::vector<sim::ContactReport> out;
  for (const sim::Contact& c : world.lastContacts()) {
    const bool on_a = mine(c.body_a, c.shape_a), on_b = mine(c.body_b, c.shape_b);
    if (!on_a && !on_b) continue;
    sim::ContactReport r = sim::contactReport(model, c);
    if (!on_a) {
      std::swap(r.body_a, r.body_b);
      std::swap(r.link_a, r.link_b);
      // b's view: the normal turned to point towards the link; the normal impulse along it on
      // the link keeps its value, the friction impulse on the link is the opposite of a's.
      r.normal = -r.normal;
      r.friction_impulse = -r.friction_impulse;
    }
    r.point = X_FW * r.point;
    r.normal = X_FW.linear() * r.normal;
    r.friction_impulse = X_FW.linear() * r.friction_impulse;
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace sensor
}  // namespace cga_rigid_sim
