// Disjoint sets (union-find) over 0..n-1 with path halving. Deterministic: a set's root is
// always its smallest member, so the result does not depend on the order of unions.
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

namespace vesselmesh::mesh {

class DisjointSets {
 public:
  explicit DisjointSets(int n) : parent_(static_cast<size_t>(n)) { std::iota(parent_.begin(), parent_.end(), 0); }

  int find(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  // Joins the sets of a and b; true if they were apart.
  bool unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (a < b) parent_[b] = a;
    else parent_[a] = b;
    return true;
  }

 private:
  std::vector<int> parent_;
};

}  // namespace vesselmesh::mesh
