// Markers: the core's reports (sim/reports.h) drawn as a visualization_msgs/MarkerArray for
// rviz (the node's ~markers topic; doc/node.md "Seeing the simulation").
//
// Per moving body, at its centre of mass, in the world frame:
//   namespace "body/<name>", id 0: the angular momentum L about the CoM (arrow),
//                            id 1: the angular velocity ω (arrow).
// Per contact of the last step:
//   namespace "contacts", id 0: every contact point (one sphere list),
//                         id 1: every normal, a segment ℓ/2 long from the point along n (one
//                               line list),
//   namespace "contact_impulses", id k: contact k's impulse on body a (normal + friction), drawn
//                                       as its mean force over the step, J/dt (arrow).
// Every array starts with a DELETEALL, so markers of a deleted body or an ended contact vanish at
// the next tick; the ids above are the same at every tick.
//
// Scaling rule (one for every arrow): a quantity of magnitude x is drawn
//   length = ℓ · min(x / x_ref, kMaxRelativeLength)   metres,
// with ℓ = MarkerScale::length and x_ref = L_ref, ω_ref or F_ref. L_ref and ω_ref are parameters;
// when not given (0) each is the largest |L| (|ω|) any body has had at a tick so far, but at
// least kMinAngularMomentumRef (kMinAngularVelocityRef): the fastest body's arrow is ℓ long,
// the others compare with it, and round-off spin on a body at rest draws nothing. F_ref defaults
// to 10 N (the weight of about 1 kg): a 1 kg body resting on one contact gets an ℓ-long arrow.
// The cap keeps an impact (a large impulse in one step) on screen.
#pragma once

#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

#include "cga_rigid_sim/sim/reports.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace node {

/// Arrows longer than this many ℓ are clipped to it.
constexpr double kMaxRelativeLength = 4.0;
/// Least chosen references: below them a body counts as not turning (kg m²/s, rad/s).
constexpr double kMinAngularMomentumRef = 1e-4;
constexpr double kMinAngularVelocityRef = 0.1;

/// The node's parameters ~marker_length, ~marker_angular_momentum_ref, ... (doc/node.md).
struct MarkerScale {
  double length = 0.25;               ///< ℓ, m: the length of an arrow at its reference magnitude
  double angular_momentum_ref = 0.0;  ///< L_ref, kg m²/s; 0 = chosen (the rule above)
  double angular_velocity_ref = 0.0;  ///< ω_ref, rad/s; 0 = chosen (the rule above)
  double force_ref = 10.0;            ///< F_ref, N: a contact's impulse J is drawn as J/dt
};

/// The references in use (the node keeps them from tick to tick).
struct MarkerReferences {
  double angular_momentum = 0.0;  ///< L_ref, kg m²/s
  double angular_velocity = 0.0;  ///< ω_ref, rad/s
  double force = 0.0;             ///< F_ref, N
};

/// What one tick's markers are built from: the World's reports at that tick.
struct MarkerInputs {
  std::vector<sim::BodyStateReport> bodies;   ///< moving bodies (CoM, ω)
  std::vector<sim::MomentumReport> momentum;  ///< per moving body (by name) and "total" (unused)
  std::vector<sim::ContactReport> contacts;   ///< the last step's contacts
  double dt = 0.0;                            ///< s, the step the contact impulses act over
};

/// The references for this tick: given ones as they are, chosen ones by the rule above from
/// `previous` (all 0 at the first tick) and the bodies in `in` (the "total" entry is no body).
MarkerReferences updateMarkerReferences(const MarkerInputs& in, const MarkerScale& scale,
                                        const MarkerReferences& previous);

/// The arrow length of a magnitude x against its reference by the rule above (0 if x_ref ≤ 0).
double arrowLength(double x, double x_ref, double length);

/// One tick's MarkerArray (DELETEALL first), every marker in `frame` at `stamp`. Arrows shorter
/// than 1 µm (a body at rest, a zero reference) are left out.
visualization_msgs::MarkerArray toMarkerArray(const MarkerInputs& in, double length,
                                              const MarkerReferences& refs,
                                              const ::ros::Time& stamp, const std::string& frame);

/// The node's ~markers at the World's current step: its reports, `refs` updated, toMarkerArray.
visualization_msgs::MarkerArray markersOf(const sim::World& world, const MarkerScale& scale,
                                          MarkerReferences* refs, const ::ros::Time& stamp);

}  // namespace node
}  // namespace cga_rigid_sim
