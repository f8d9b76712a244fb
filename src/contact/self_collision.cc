// The self-collision table of a World (contact/self_collision.h): which pairs of one robot's bodies
// contact detection tests, from the scene's rules and the mode (doc/contacts.md#self-collision).
#include <algorithm>
#include <map>
#include <set>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/math/union_find.h"
#include "contact/contact_detection.h"
#include "contact/self_collision_rules.h"

namespace cga_rigid_sim {
namespace sim {

void SelfCollision::indexAllowed() {
  const std::size_t n = robot_of_body.size();
  pair_row_.assign(n, 0);
  place_in_robot_.assign(n, -1);
  // Each robot's bodies, in body order (labels are only compared with each other).
  std::map<int, std::vector<int>> bodies_of_robot;
  for (std::size_t j = 0; j < n; ++j)
    if (robot_of_body[j] >= 0) bodies_of_robot[robot_of_body[j]].push_back(static_cast<int>(j));
  std::size_t bits = 0;
  for (const auto& [robot, bodies] : bodies_of_robot) {
    const std::size_t k = bodies.size();
    for (std::size_t p = 0; p < k; ++p) {
      place_in_robot_[bodies[p]] = static_cast<int>(p);
      pair_row_[bodies[p]] = bits + p * k;
    }
    bits += k * k;
  }
  pair_bits_.assign((bits + 63) / 64, 0u);
  const auto set = [this](int a, int b) {
    const std::size_t bit = pair_row_[a] + static_cast<std::size_t>(place_in_robot_[b]);
    pair_bits_[bit >> 6] |= std::uint64_t{1} << (bit & 63);
  };
  for (const auto& [a, b] : allowed_) {
    set(a, b);
    set(b, a);
  }
}

void SelfCollision::setAllowed(std::vector<std::pair<int, int>> pairs) {
  std::sort(pairs.begin(), pairs.end());
  allowed_ = std::move(pairs);
  indexAllowed();
}

void SelfCollision::eraseBodies(int first, int count) {
  robot_of_body.erase(robot_of_body.begin() + first, robot_of_body.begin() + first + count);
  const auto gone = [first, count](int x) { return x >= first && x < first + count; };
  const auto shift = [first, count](int x) { return x >= first + count ? x - count : x; };
  allowed_.erase(
      std::remove_if(allowed_.begin(), allowed_.end(),
                     [&](const std::pair<int, int>& p) { return gone(p.first) || gone(p.second); }),
      allowed_.end());
  excluded.erase(std::remove_if(excluded.begin(), excluded.end(),
                                [&](const Excluded& e) { return gone(e.a) || gone(e.b); }),
                 excluded.end());
  for (auto& p : allowed_) p = {shift(p.first), shift(p.second)};
  for (auto& e : excluded) e.a = shift(e.a), e.b = shift(e.b);
  indexAllowed();
}

void SelfCollision::appendRobot(const SelfCollision& robot, int first_body) {
  // Labels are only compared with each other: the robot's start past every label in use.
  int label = static_cast<int>(robot_of_body.size());
  for (int r : robot_of_body) label = std::max(label, r + 1);
  for (std::size_t k = 0; k < robot.robot_of_body.size(); ++k)
    if (robot.robot_of_body[k] >= 0) robot_of_body[first_body + k] = label + robot.robot_of_body[k];
  // Its pairs come after every pair here (their bodies do): allowed_ stays sorted.
  for (const auto& [a, b] : robot.allowed_) allowed_.emplace_back(a + first_body, b + first_body);
  for (Excluded e : robot.excluded) {
    e.a += first_body;
    e.b += first_body;
    excluded.push_back(e);
  }
  indexAllowed();
}

const char* toString(SelfCollision::Reason reason) {
  switch (reason) {
    case SelfCollision::Reason::kJoint:
      return "joined by a joint";
    case SelfCollision::Reason::kMode:
      return "~self_collision none";
    case SelfCollision::Reason::kGazebo:
      return "<self_collide> false for both";
    case SelfCollision::Reason::kSrdf:
      return "disabled by the SRDF";
    case SelfCollision::Reason::kOverlap:
      return "overlapping at the initial configuration";
  }
  return "";
}

namespace {

using Pair = std::pair<int, int>;
Pair ordered(int a, int b) { return a < b ? Pair(a, b) : Pair(b, a); }

// Per body: its robot, the union of the bodies joints join (−1: no joint touches it).
std::vector<int> robots(const Model& model) {
  const int n = static_cast<int>(model.scene.bodies.size());
  math::UnionFind sets;
  sets.reset(n);
  std::vector<int> robot(n, -1);
  std::vector<char> jointed(n, 0);
  for (const scene::JointModel& j : model.scene.joints) {
    jointed[j.child_body] = 1;
    if (j.parent_body < 0) continue;
    jointed[j.parent_body] = 1;
    sets.join(j.parent_body, j.child_body);
  }
  for (int j = 0; j < n; ++j)
    if (jointed[j]) robot[j] = sets.find(j);
  return robot;
}

// The body pairs an SRDF's rules name (links mapped to their bodies; a pair inside one body is
// no pair). A pair of bodies is left out when the SRDF disables any pair of their links.
struct SrdfPairs {
  std::set<Pair> disabled, enabled;
  std::set<int> disabled_bodies;
};
SrdfPairs srdfPairs(const Model& model) {
  const scene::SelfCollisionRules& r = model.scene.self_collision;
  SrdfPairs out;
  const auto body = [&model](const std::string& link) { return model.scene.findLink(link); };
  for (const scene::LinkPair& p : r.srdf_disabled) {
    const int a = body(p.link1), b = body(p.link2);
    if (a >= 0 && b >= 0 && a != b) out.disabled.insert(ordered(a, b));
  }
  for (const scene::LinkPair& p : r.srdf_enabled) {
    const int a = body(p.link1), b = body(p.link2);
    if (a >= 0 && b >= 0 && a != b) out.enabled.insert(ordered(a, b));
  }
  for (const std::string& l : r.srdf_disabled_links)
    if (body(l) >= 0) out.disabled_bodies.insert(body(l));
  return out;
}

// Gazebo's rule for a body: <self_collide> of any of its links (links merged by fixed joints are
// one body, as Gazebo lumps them), else the model's, else false.
bool gazeboSelfCollides(const Model& model, int j) {
  const scene::SelfCollisionRules& r = model.scene.self_collision;
  bool any_given = false, value = false;
  for (const scene::LinkFrame& l : model.scene.bodies[j].links) {
    const auto it = r.gazebo_links.find(l.link);
    if (it == r.gazebo_links.end()) continue;
    any_given = true;
    value = value || it->second;
  }
  return any_given ? value : r.gazebo_model.value_or(false);
}

}  // namespace

void compileSelfCollision(Model& model) {
  SelfCollision& sc = model.self_collision;
  sc = SelfCollision();
  sc.mode = model.config.self_collision;
  sc.robot_of_body = robots(model);
  const auto& bodies = model.scene.bodies;
  const int n = static_cast<int>(bodies.size());
  std::set<Pair> joined;
  for (const scene::JointModel& j : model.scene.joints)
    if (j.parent_body >= 0) joined.insert(ordered(j.parent_body, j.child_body));
  const SrdfPairs srdf = srdfPairs(model);
  const bool gazebo = model.scene.self_collision.hasGazebo();
  std::vector<Pair> allowed;
  using Reason = SelfCollision::Reason;
  using Mode = scene::SelfCollisionMode;
  for (int a = 0; a < n; ++a) {
    if (sc.robot_of_body[a] < 0 || bodies[a].shapes.empty()) continue;
    for (int b = a + 1; b < n; ++b) {
      if (sc.robot_of_body[b] != sc.robot_of_body[a] || bodies[b].shapes.empty()) continue;
      const Pair p(a, b);
      std::optional<Reason> out;
      if (joined.count(p))
        out = Reason::kJoint;
      else if (sc.mode == Mode::kNone)
        out = Reason::kMode;
      else if (sc.mode == Mode::kAuto) {
        const bool srdf_off = srdf.disabled.count(p) ||
                              ((srdf.disabled_bodies.count(a) || srdf.disabled_bodies.count(b)) &&
                               !srdf.enabled.count(p));
        if (srdf_off)
          out = Reason::kSrdf;
        else if (gazebo && !gazeboSelfCollides(model, a) && !gazeboSelfCollides(model, b))
          out = Reason::kGazebo;
      }
      if (out)
        sc.excluded.push_back({a, b, *out, 0.0});
      else
        allowed.push_back(p);
    }
  }
  sc.setAllowed(std::move(allowed));
}

void leaveOutInitialOverlaps(Model& model, const Data& data, CollisionCache& cache) {
  SelfCollision& sc = model.self_collision;
  using Pair = std::pair<int, int>;
  if (sc.mode != scene::SelfCollisionMode::kAuto || sc.allowed().empty()) return;
  // auto: the allowed pairs that overlap at the initial configuration are left out (the rule
  // of MoveIt's setup assistant: their authors never meant them to touch).
  std::vector<Contact> found;
  detectContacts(model, data, cache, found);
  std::map<Pair, double> overlap;
  for (const Contact& c : found) {
    if (c.body_b < 0 || c.depth <= 0) continue;
    const int ra = sc.robot_of_body[c.body_a];
    if (ra < 0 || ra != sc.robot_of_body[c.body_b]) continue;
    double& d = overlap[ordered(c.body_a, c.body_b)];
    d = std::max(d, c.depth);
  }
  if (overlap.empty()) return;
  std::vector<Pair> kept;
  for (const Pair& p : sc.allowed()) {
    const auto it = overlap.find(p);
    if (it == overlap.end())
      kept.push_back(p);
    else
      sc.excluded.push_back({p.first, p.second, SelfCollision::Reason::kOverlap, it->second});
  }
  sc.setAllowed(std::move(kept));
  std::sort(sc.excluded.begin(), sc.excluded.end(),
            [](const SelfCollision::Excluded& x, const SelfCollision::Excluded& y) {
              return std::make_pair(x.a, x.b) < std::make_pair(y.a, y.b);
            });
}

std::vector<std::string> selfCollisionSummary(const Model& model) {
  const SelfCollision& sc = model.self_collision;
  std::vector<std::string> out;
  std::map<int, std::vector<Pair>> allowed_of;
  std::map<int, std::map<SelfCollision::Reason, std::vector<const SelfCollision::Excluded*>>>
      excluded_of;
  for (const Pair& p : sc.allowed()) allowed_of[sc.robot_of_body[p.first]].push_back(p);
  for (const SelfCollision::Excluded& e : sc.excluded)
    excluded_of[sc.robot_of_body[e.a]][e.reason].push_back(&e);
  std::set<int> robots_seen;
  for (int r : sc.robot_of_body)
    if (r >= 0) robots_seen.insert(r);
  const auto name = [&model](int j) { return model.scene.bodies[j].name; };
  // At most this many pairs are named per line; the rest are counted (the whole lists are the
  // node's ~self_collision_pairs parameter).
  constexpr std::size_t kNamed = 12;
  for (int r : robots_seen) {
    const auto& allowed = allowed_of[r];
    auto& excluded = excluded_of[r];
    std::size_t total = allowed.size();
    for (const auto& kv : excluded) total += kv.second.size();
    if (total == 0) continue;  // a robot with at most one body with shapes
    // The robot is named by its first body (the tree's root or the body it hangs on).
    int first = -1;
    for (int j = 0; j < static_cast<int>(sc.robot_of_body.size()) && first < 0; ++j)
      if (sc.robot_of_body[j] == r) first = j;
    std::string head = "self-collision (" + std::string(scene::toString(sc.mode)) +
                       ") of the robot of '" + name(first) +
                       "': " + std::to_string(allowed.size()) + " of " + std::to_string(total) +
                       " pairs of its links collide";
    out.push_back(head);
    const auto pairs = [&](auto begin, auto end, auto text) {
      std::string line;
      std::size_t k = 0, count = static_cast<std::size_t>(std::distance(begin, end));
      for (auto it = begin; it != end && k < kNamed; ++it, ++k) line += (k ? ", " : "") + text(*it);
      if (count > kNamed) line += ", … " + std::to_string(count - kNamed) + " more";
      return line;
    };
    if (!allowed.empty())
      out.push_back("  colliding: " + pairs(allowed.begin(), allowed.end(), [&](const Pair& p) {
                      return name(p.first) + "–" + name(p.second);
                    }));
    for (const auto& [reason, list] : excluded) {
      // Overlaps, deepest first: the pairs a user most wants to see.
      auto sorted = list;
      if (reason == SelfCollision::Reason::kOverlap)
        std::stable_sort(sorted.begin(), sorted.end(),
                         [](const auto* x, const auto* y) { return x->depth > y->depth; });
      out.push_back(
          "  left out, " + std::string(toString(reason)) + " (" + std::to_string(sorted.size()) +
          "): " + pairs(sorted.begin(), sorted.end(), [&](const SelfCollision::Excluded* e) {
            std::string s = name(e->a) + "–" + name(e->b);
            if (e->reason == SelfCollision::Reason::kOverlap)
              s += " " + formatNumber(e->depth * 1e3, 3) + " mm";
            return s;
          }));
    }
  }
  return out;
}

}  // namespace sim
}  // namespace cga_rigid_sim
