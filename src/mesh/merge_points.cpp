#include "mesh/merge_points.h"

#include "mesh/disjoint_sets.h"
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
  DisjointSets sets(static_cast<int>(n));
  const double largest = n == 0 ? 0.0 : *std::max_element(tolerance.begin(), tolerance.end());
  if (!(largest > 0.0)) {
    std::vector<int> identity(n);
    std::iota(identity.begin(), identity.end(), 0);
    return compact(points, identity);
  }

  // Bucket points in a grid of cells much larger than any tolerance: a point looks only in
  // the cells its own tolerance box touches, one cell in most cases.
  const double cell = 16.0 * largest;
  auto index = [&](double x) {  // clamped: far points share the outermost cells, still correct
    return static_cast<int64_t>(std::clamp(std::floor(x / cell), -4e18, 4e18));
  };
  auto key_of = [](int64_t i, int64_t j, int64_t k) {
    return mix(static_cast<uint64_t>(i) ^ mix(static_cast<uint64_t>(j) ^ mix(static_cast<uint64_t>(k))));
  };
  std::vector<std::pair<uint64_t, int>> sorted(n);
  for (size_t i = 0; i < n; ++i)
    sorted[i] = {key_of(index(points[i].x()), index(points[i].y()), index(points[i].z())), static_cast<int>(i)};
  std::sort(sorted.begin(), sorted.end());

  for (size_t i = 0; i < n; ++i) {
    const Vec3& p = points[i];
    const double t = tolerance[i];
    if (!(t > 0.0)) continue;
    const int64_t x0 = index(p.x() - t), x1 = index(p.x() + t), y0 = index(p.y() - t), y1 = index(p.y() + t),
                  z0 = index(p.z() - t), z1 = index(p.z() + t);
    for (int64_t cx = x0; cx <= x1; ++cx)
      for (int64_t cy = y0; cy <= y1; ++cy)
        for (int64_t cz = z0; cz <= z1; ++cz) {
          const uint64_t key = key_of(cx, cy, cz);
          auto it = std::lower_bound(sorted.begin(), sorted.end(), std::pair<uint64_t, int>{key, 0});
          for (; it != sorted.end() && it->first == key; ++it) {
            const int j = it->second;
            if (j <= static_cast<int>(i) || (p - points[j]).norm() > std::min(t, tolerance[j])) continue;
            sets.unite(static_cast<int>(i), j);
          }
        }
  }
  std::vector<int> representative(n);
  for (size_t i = 0; i < n; ++i) representative[i] = sets.find(static_cast<int>(i));
  return compact(points, representative);
}

void remap_triangles(std::vector<Triangle>& triangles, const std::vector<int>& remap) {
  for (Triangle& f : triangles)
    for (int& v : f) v = remap[v];
}

}  // namespace vesselmesh::mesh
