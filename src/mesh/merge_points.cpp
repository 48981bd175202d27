#include "mesh/merge_points.h"

#include "mesh/error.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace vesselmesh::mesh {
namespace {

uint64_t mix(uint64_t h) {  // splitmix64 finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  return h ^ (h >> 31);
}

uint64_t bits(double x) { return std::bit_cast<uint64_t>(x == 0.0 ? 0.0 : x); }

uint64_t hash_point(const Vec3& p) {
  return mix(bits(p.x()) ^ mix(bits(p.y()) ^ mix(bits(p.z()))));
}

bool identical(const Vec3& a, const Vec3& b) {
  return bits(a.x()) == bits(b.x()) && bits(a.y()) == bits(b.y()) && bits(a.z()) == bits(b.z());
}

// Keeps the representatives, in order, and turns `representative` into the final remap.
std::vector<int> compact(std::vector<Vec3>& points, const std::vector<int>& representative) {
  std::vector<int> remap(points.size());
  int kept = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (representative[i] == static_cast<int>(i)) {
      points[kept] = points[i];
      remap[i] = kept++;
    } else {
      remap[i] = remap[representative[i]];  // representative[i] < i: already numbered
    }
  }
  points.resize(kept);
  return remap;
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

IdenticalPointSet::IdenticalPointSet(size_t expected_points) {
  size_t capacity = 16;
  while (capacity < 2 * expected_points) capacity *= 2;
  table_.assign(capacity, -1);
  mask_ = capacity - 1;
  points_.reserve(expected_points);
}

int IdenticalPointSet::insert(const Vec3& p) {
  size_t slot = hash_point(p) & mask_;
  while (table_[slot] != -1) {
    if (identical(points_[table_[slot]], p)) return table_[slot];
    slot = (slot + 1) & mask_;
  }
  const int index = static_cast<int>(points_.size());
  table_[slot] = index;
  points_.push_back(p);
  if (2 * points_.size() > table_.size()) grow();
  return index;
}

void IdenticalPointSet::grow() {
  table_.assign(table_.size() * 2, -1);
  mask_ = table_.size() - 1;
  for (size_t i = 0; i < points_.size(); ++i) {
    size_t slot = hash_point(points_[i]) & mask_;
    while (table_[slot] != -1) slot = (slot + 1) & mask_;
    table_[slot] = static_cast<int>(i);
  }
}

std::vector<int> merge_identical_points(std::vector<Vec3>& points) {
  IdenticalPointSet set(points.size());
  std::vector<int> remap(points.size());
  for (size_t i = 0; i < points.size(); ++i) remap[i] = set.insert(points[i]);
  points = set.release();
  return remap;
}

std::vector<int> merge_close_points(std::vector<Vec3>& points, std::span<const double> tolerance) {
  const size_t n = points.size();
  VM_CHECK(tolerance.size() == n, "one tolerance per point");
  const double cell = *std::max_element(tolerance.begin(), tolerance.end());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  if (n == 0 || !(cell > 0.0)) return compact(points, parent);

  // Bucket points in a grid of cell size max(tol): close pairs lie in neighbouring cells.
  auto cell_of = [&](const Vec3& p) {  // clamped: far points share the edge cells, still correct
    auto index = [&](double x) { return static_cast<int64_t>(std::clamp(std::floor(x / cell), -4e18, 4e18)); };
    return std::array<int64_t, 3>{index(p.x()), index(p.y()), index(p.z())};
  };
  auto key_of = [](const std::array<int64_t, 3>& c) {
    return mix(static_cast<uint64_t>(c[0]) ^
               mix(static_cast<uint64_t>(c[1]) ^ mix(static_cast<uint64_t>(c[2]))));
  };
  std::vector<std::pair<uint64_t, int>> sorted(n);
  for (size_t i = 0; i < n; ++i) sorted[i] = {key_of(cell_of(points[i])), static_cast<int>(i)};
  std::sort(sorted.begin(), sorted.end());

  for (size_t i = 0; i < n; ++i) {
    const auto c = cell_of(points[i]);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const uint64_t key = key_of({c[0] + dx, c[1] + dy, c[2] + dz});
          auto it = std::lower_bound(sorted.begin(), sorted.end(), std::pair<uint64_t, int>{key, 0});
          for (; it != sorted.end() && it->first == key; ++it) {
            const int j = it->second;
            if (j <= static_cast<int>(i)) continue;
            if ((points[i] - points[j]).norm() <= std::min(tolerance[i], tolerance[j])) {
              const int ri = find_root(parent, static_cast<int>(i));
              const int rj = find_root(parent, j);
              if (ri != rj) parent[std::max(ri, rj)] = std::min(ri, rj);
            }
          }
        }
  }
  std::vector<int> representative(n);
  for (size_t i = 0; i < n; ++i) representative[i] = find_root(parent, static_cast<int>(i));
  return compact(points, representative);
}

void remap_triangles(std::vector<Triangle>& triangles, const std::vector<int>& remap) {
  for (Triangle& f : triangles)
    for (int& v : f) v = remap[v];
}

}  // namespace vesselmesh::mesh
