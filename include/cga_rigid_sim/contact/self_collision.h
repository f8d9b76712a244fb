// SelfCollision: the pairs of one robot's bodies that contact detection tests, decided once when
// a World is made from the scene's rules and the mode (scene/self_collision.h,
// doc/contacts.md#self-collision), and why each other pair is left out (the start-up summary).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cga_rigid_sim/scene/self_collision.h"

namespace cga_rigid_sim {
namespace sim {

struct SelfCollision {
  /// Why a pair of one robot's bodies never collides.
  enum class Reason {
    kJoint,    ///< a link and its parent (always)
    kMode,     ///< ~self_collision none
    kGazebo,   ///< the URDF's <self_collide> (neither link self-collides)
    kSrdf,     ///< the SRDF disables it
    kOverlap,  ///< it overlaps at the initial configuration (auto)
  };
  struct Excluded {
    int a = -1, b = -1;  ///< body indices, a < b
    Reason reason = Reason::kJoint;
    double depth = 0.0;  ///< kOverlap: how deep, m
  };

  scene::SelfCollisionMode mode = scene::SelfCollisionMode::kAuto;
  /// Per body j: its robot (bodies joined by joints, with the static body a fixed-base tree
  /// hangs on), −1 for a body no joint touches.
  std::vector<int> robot_of_body;
  /// The other pairs of one robot's bodies with shapes, and why (in order of a, then b).
  std::vector<Excluded> excluded;

  /// Whether contact detection tests bodies a and b (a ≠ b): always for bodies of different
  /// robots or of none, else only an allowed pair (read from the pair matrix: the broad phase
  /// asks for every pair whose bounding spheres overlap).
  bool collides(int a, int b) const {
    const int ra = robot_of_body[a];
    if (ra < 0 || ra != robot_of_body[b]) return true;
    const std::size_t bit = pair_row_[a] + static_cast<std::size_t>(place_in_robot_[b]);
    return (pair_bits_[bit >> 6] >> (bit & 63)) & 1u;
  }
  /// Pairs (a < b) of bodies of one robot, both with collision shapes, that are tested. Sorted.
  const std::vector<std::pair<int, int>>& allowed() const { return allowed_; }
  /// Sets them (sorted here) and makes the pair matrix that collides() reads.
  void setAllowed(std::vector<std::pair<int, int>> pairs);
  /// Makes the pair matrix that collides() reads from robot_of_body and allowed(); called by
  /// whatever changes them (setAllowed, the mutators below; after robot_of_body changes).
  void indexAllowed();
  /// Body j removed (World::deleteBody): indices after it shift down. j is in no robot.
  void eraseBody(int j) { eraseBodies(j, 1); }
  /// Bodies [first, first + count) removed (a spawned robot deleted): their pairs go, indices
  /// after them shift down.
  void eraseBodies(int first, int count);
  /// A body appended (spawned free body): in no robot.
  void appendBody() {
    robot_of_body.push_back(-1);
    pair_row_.push_back(0);  // (in no robot: collides() never reads its place)
    place_in_robot_.push_back(-1);
  }
  /// The table of a robot compiled on its own (a spawned robot) for its bodies, appended at
  /// body indices first_body… (where appendBody already put them, in no robot): its robots get
  /// labels no robot here has, its pairs are shifted by first_body.
  void appendRobot(const SelfCollision& robot, int first_body);

 private:
  std::vector<std::pair<int, int>> allowed_;  // kept with the pair matrix it is indexed into
  // The pair matrix: per robot a square matrix of bits over its bodies (in body order), set
  // where a pair is allowed (both ways round). Body a's row starts at bit pair_row_[a]; body
  // b's column is its place among its robot's bodies.
  std::vector<std::size_t> pair_row_;
  std::vector<int> place_in_robot_;
  std::vector<std::uint64_t> pair_bits_;
};

const char* toString(SelfCollision::Reason reason);

}  // namespace sim
}  // namespace cga_rigid_sim
