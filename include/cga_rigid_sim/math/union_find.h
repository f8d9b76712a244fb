// Disjoint sets over 0 … n−1 (union–find with path halving), once: the islands of contacts, of
// sleeping bodies, of joints on the ground and of robots in a scene are all its sets. It keeps
// its array from one reset to the next, so a step that resets it to no more elements than before
// does not allocate.
#pragma once

#include <vector>

namespace cga_rigid_sim {
namespace math {

class UnionFind {
 public:
  /// n elements, each a set of its own.
  void reset(int n) {
    parent_.resize(n);
    for (int x = 0; x < n; ++x) parent_[x] = x;
  }
  int size() const { return static_cast<int>(parent_.size()); }
  /// The representative of x's set (halving the path on the way).
  int find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  /// Joins a's set to b's: b's representative stays the representative of the union.
  void join(int a, int b) {
    const int rb = find(b);
    parent_[find(a)] = rb;
  }

 private:
  std::vector<int> parent_;
};

}  // namespace math
}  // namespace cga_rigid_sim
