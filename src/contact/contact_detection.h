// Contact detection (doc/contacts.md#detection): the contacts of the bodies at the poses of the
// step's start, in a deterministic order.
//
//   broad phase   every shape's bounding sphere, swept along the world x axis (sort and sweep):
//                 only pairs whose boxes overlap reach the narrow phase, so a pile of n bodies
//                 costs O(n log n) plus its real neighbours, not n² tests;
//   narrow phase  the ground plane against each shape's vertices (exact for boxes and meshes,
//                 the lowest point of a sphere, the rims of a cylinder), with a speculative
//                 margin so that a body about to land is caught in the step it lands; every
//                 other pair through FCL (its box–box gives the full face manifold, up to 4
//                 points; meshes collide as their convex hulls).
// Pairs inside one body never collide; two static bodies are never tested; two bodies of one
// robot only when its self-collision table allows them (Model::self_collision).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cga_rigid_sim/contact/contact.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

/// The geometry of every shape, made once per topology (opaque: it holds FCL objects).
class CollisionCache;

/// A cache for `model` (rebuilt by detectContacts when the topology changed).
std::shared_ptr<CollisionCache> makeCollisionCache();

/// Appends to `out` the contacts at the current poses. Plane contacts come with a speculative
/// margin of each body's travel over the step (depth ≤ 0: a gap that may close). `asleep`
/// (per moving index, optional): bodies that do not move (contact_sleep.h): their poses are
/// those of the last detection, and only their pairs with awake moving bodies are tested.
void detectContacts(const Model& model, const Data& data, CollisionCache& cache,
                    std::vector<Contact>& out, const std::vector<char>* asleep = nullptr);

/// The pairs of bodies that overlap by more than `depth` m at the current poses (each at its
/// deepest point), naming the bodies and links: one line each for up to five pairs, else a line
/// with their count and the five deepest. Reported once, when a World is created.
std::vector<std::string> overlapWarnings(const Model& model, const Data& data,
                                         CollisionCache& cache, double depth);

/// Appends the ground-plane contacts of body j alone at its current pose, with a speculative
/// margin of `margin` m (used after a body has been moved to the instant it lands).
void detectPlaneContactsOf(const Model& model, const Data& data, CollisionCache& cache, int j,
                           double margin, std::vector<Contact>& out);

}  // namespace sim
}  // namespace cga_rigid_sim
