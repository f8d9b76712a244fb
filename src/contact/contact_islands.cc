// The islands (doc/contacts.md#solver): the bodies joined by their contacts, found by
// union-find over the face blocks each step (SolverWork::Island). Each island is solved on its
// own, so its impulses depend on nothing it does not touch.
#include <vector>

#include "contact/contact_solver_internals.h"

namespace cga_rigid_sim {
namespace sim {
namespace detail {
namespace {

// A single face or contact (on no tree): one island, without union-find.
void makeOneIsland(int n, SolverWork& work) {
  const int a = work.a[work.groups[0].first], b = work.b[work.groups[0].first];
  work.island_group.assign(1, 0);
  work.island_body.clear();
  if (a < n) work.island_body.push_back(a);
  if (b < n) work.island_body.push_back(b);
  work.island_tree.clear();
  work.islands.assign(1, SolverWork::Island());
  work.islands[0].groups = 1;
  work.islands[0].bodies = static_cast<int>(work.island_body.size());
}

// The union-find nodes of row k's group (any row of it: a group's rows share their bodies):
// its movable slots (0 … n−1) and its trees (n + t); returns how many.
int groupNodes(const std::vector<ContactRow>& rows, const SolverWork& work, int n, int k,
               int out[4]) {
  int m = 0;
  if (work.a[k] < n) out[m++] = work.a[k];
  if (work.b[k] < n) out[m++] = work.b[k];
  if (rows[k].ta >= 0) out[m++] = n + rows[k].ta;
  if (rows[k].tb >= 0) out[m++] = n + rows[k].tb;
  return m;
}

// Numbers the islands by their first group: work.group_island per group, work.node_island per
// union-find root (−1 for none). Returns how many islands there are.
int numberIslands(const std::vector<ContactRow>& rows, int n, int n_trees, SolverWork& work) {
  math::UnionFind& sets = work.island_sets;
  std::vector<int>& id = work.node_island;
  id.assign(n + n_trees, -1);
  std::vector<int>& island_of_group = work.group_island;
  island_of_group.resize(work.groups.size());
  int islands = 0;
  for (std::size_t q = 0; q < work.groups.size(); ++q) {
    int nd[4];
    if (groupNodes(rows, work, n, work.groups[q].first, nd) == 0) {  // nothing movable: alone
      island_of_group[q] = islands++;
      continue;
    }
    int& i = id[sets.find(nd[0])];
    if (i < 0) i = islands++;
    island_of_group[q] = i;
  }
  return islands;
}

// Each island's runs of groups, slots and trees in island_group, island_body and island_tree.
void collectIslands(int n, int n_trees, int islands, SolverWork& work) {
  math::UnionFind& sets = work.island_sets;
  const std::vector<int>& id = work.node_island;
  const std::vector<int>& island_of_group = work.group_island;
  work.islands.assign(islands, SolverWork::Island());
  for (const int i : island_of_group) ++work.islands[i].groups;
  for (int x = 0; x < n + n_trees; ++x) {
    const int i = id[sets.find(x)];
    if (i < 0) continue;
    if (x < n)
      ++work.islands[i].bodies;
    else
      ++work.islands[i].trees;
  }
  int g0 = 0, b0 = 0, t0 = 0;
  for (SolverWork::Island& I : work.islands) {
    I.first_group = g0;
    I.first_body = b0;
    I.first_tree = t0;
    g0 += I.groups;
    b0 += I.bodies;
    t0 += I.trees;
    I.groups = I.bodies = I.trees = 0;
  }
  work.island_group.resize(g0);
  work.island_body.resize(b0);
  work.island_tree.resize(t0);
  for (std::size_t q = 0; q < work.groups.size(); ++q) {
    SolverWork::Island& I = work.islands[island_of_group[q]];
    work.island_group[I.first_group + I.groups++] = static_cast<int>(q);
  }
  for (int x = 0; x < n + n_trees; ++x) {
    const int i = id[sets.find(x)];
    if (i < 0) continue;
    SolverWork::Island& I = work.islands[i];
    if (x < n)
      work.island_body[I.first_body + I.bodies++] = x;
    else
      work.island_tree[I.first_tree + I.trees++] = x - n;
  }
}

}  // namespace

// Union-find over the slots (0 … n−1) and the trees (n + t); the dummy joins nothing. Islands
// are numbered by their first group, and each keeps its groups in their order, so Gauss–Seidel
// visits an island's contacts as a sweep over all of them would.
void makeIslands(const std::vector<ContactRow>& rows, int n_trees, SolverWork& work) {
  const int n = static_cast<int>(work.response.size()) - 1;
  if (work.groups.size() == 1 && !onTree(rows[work.groups[0].first])) {
    makeOneIsland(n, work);
    return;
  }
  work.island_sets.reset(n + n_trees);
  for (const SolverWork::Group& g : work.groups) {
    int nd[4];
    const int m = groupNodes(rows, work, n, g.first, nd);
    for (int i = 1; i < m; ++i) work.island_sets.join(nd[i], nd[0]);
  }
  collectIslands(n, n_trees, numberIslands(rows, n, n_trees, work), work);
}

}  // namespace detail
}  // namespace sim
}  // namespace cga_rigid_sim
