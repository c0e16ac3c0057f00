// Disjoint sets over 0 .. n-1 with path halving; the smaller id becomes the
// root, so the roots (and everything built on them) do not depend on the
// order of the unions. Shared by skeleton.cpp and unfold.cpp.
#pragma once

#include <algorithm>
#include <numeric>
#include <vector>

namespace developable {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  // Joins the sets of a and b; false when they were one already.
  bool unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent[std::max(a, b)] = std::min(a, b);
    return true;
  }
};

}  // namespace developable
