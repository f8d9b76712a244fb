// math::UnionFind against a second method: the connected components of a random graph found by
// breadth-first search over its edge list.
#include "cga_rigid_sim/math/union_find.h"

#include <gtest/gtest.h>

#include <queue>
#include <random>
#include <utility>
#include <vector>

namespace cga_rigid_sim {
namespace math {
namespace union_find_test {

// Component labels by BFS: label[x] = the smallest element of x's component.
std::vector<int> componentsByBfs(int n, const std::vector<std::pair<int, int>>& edges) {
  std::vector<std::vector<int>> adjacent(n);
  for (const auto& [a, b] : edges) {
    adjacent[a].push_back(b);
    adjacent[b].push_back(a);
  }
  std::vector<int> label(n, -1);
  for (int s = 0; s < n; ++s) {
    if (label[s] >= 0) continue;
    std::queue<int> q;
    q.push(s);
    label[s] = s;
    while (!q.empty()) {
      const int x = q.front();
      q.pop();
      for (int y : adjacent[x])
        if (label[y] < 0) {
          label[y] = s;
          q.push(y);
        }
    }
  }
  return label;
}

TEST(UnionFind, SetsAreTheComponentsOfTheJoinedPairs) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 1 + trial * 7;
    std::uniform_int_distribution<int> pick(0, n - 1);
    std::vector<std::pair<int, int>> edges;
    for (int e = 0; e < n * 2 / 3; ++e) edges.emplace_back(pick(rng), pick(rng));
    UnionFind sets;
    sets.reset(n);
    for (const auto& [a, b] : edges) sets.join(a, b);
    const std::vector<int> label = componentsByBfs(n, edges);
    for (int x = 0; x < n; ++x)
      for (int y = 0; y < n; ++y)
        ASSERT_EQ(sets.find(x) == sets.find(y), label[x] == label[y]) << x << " " << y;
  }
}

TEST(UnionFind, JoinKeepsTheSecondSetsRepresentative) {
  UnionFind sets;
  sets.reset(4);
  sets.join(0, 1);
  EXPECT_EQ(sets.find(0), 1);
  sets.join(1, 3);
  EXPECT_EQ(sets.find(0), 3);
  EXPECT_EQ(sets.find(2), 2);
  sets.reset(2);  // fresh sets again
  EXPECT_EQ(sets.find(0), 0);
  EXPECT_EQ(sets.size(), 2);
}

}  // namespace union_find_test
}  // namespace math
}  // namespace cga_rigid_sim
