#include "analysis/normals.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

namespace vesselmesh::analysis {
namespace {

constexpr int kGrain = 2048;

// Max's term for a face with edges e1, e2 from the point and e1 x e2 = cross (not degenerate).
inline Vec3 max_term(const Vec3& cross, const Vec3& e1, const Vec3& e2) {
  return cross * (1.0 / (e1.squaredNorm() * e2.squaredNorm()));
}

// The weighted sum of the face normals around v (`corners` lists 3 t + c), not normalized.
Vec3 weighted_sum(const TriMesh& mesh, const mesh::VertexTriangles& corners, int v, NormalMethod weighting) {
  Vec3 sum = Vec3::Zero();
  for (int corner : corners.of(v)) {
    const Triangle& f = mesh.triangles[corner / 3];
    const int c = corner % 3;
    const Vec3 e1 = mesh.points[f[(c + 1) % 3]] - mesh.points[v];
    const Vec3 e2 = mesh.points[f[(c + 2) % 3]] - mesh.points[v];
    const Vec3 cross = e1.cross(e2);
    const double a2 = cross.squaredNorm();
    if (!(a2 > 0.0)) continue;  // degenerate triangle: no direction
    switch (weighting) {
      case NormalMethod::angle: {
        const double a = std::sqrt(a2);
        sum += (cross / a) * std::atan2(a, e1.dot(e2));
        break;
      }
      case NormalMethod::area: sum += cross; break;
      default: sum += max_term(cross, e1, e2); break;
    }
  }
  return sum;
}

Vec3 unit_or_zero(const Vec3& v) {
  const double n = v.norm();
  return n > 0.0 ? Vec3(v / n) : Vec3::Zero();
}

// The quadric fits of kBatch points are solved together, each step of the factorization a loop
// over the batch: the solves run side by side instead of one long chain of dependent divisions
// per point. Lanes do exactly the arithmetic a single solve would, so the result does not depend
// on a point's neighbours in the batch.
constexpr int kBatch = 8;
// Triangles per point and neighbours handled on the stack; larger fans take the general path.
constexpr int kMaxFan = 24;
constexpr int kMaxRing = 64;
constexpr int kMinRing = 5;  // fewer neighbours than the fit's unknowns: the 2-ring

// A point's neighbours as offsets from it, each once, and the sum of their squared lengths.
struct Ring {
  int n = 0;
  double length2 = 0.0;
  int id[kMaxRing];
  double q[kMaxRing][3];

  // Adds neighbour w at offset (x, y, z) unless present; false when full.
  bool add(int w, double x, double y, double z) {
    for (int j = 0; j < n; ++j)
      if (id[j] == w) return true;
    if (n == kMaxRing) return false;
    id[n] = w, q[n][0] = x, q[n][1] = y, q[n][2] = z;
    length2 += x * x + y * y + z * z;
    ++n;
    return true;
  }
};

// The fits of up to kBatch points: per lane the normal equations of the height fit (lower
// triangle packed by rows: (0,0), (1,0), (1,1), (2,0), ...) and the frame they are written in.
struct FitBatch {
  double a[15][kBatch];
  double b[5][kBatch];
  double frame[9][kBatch];  // start normal, t1, t2
  bool active[kBatch];
};

constexpr int packed(int i, int j) {
  return i * (i + 1) / 2 + j;
}

// Writes the height fit of one point into lane `lane`: in the frame (t1, t2, start), the normal
// equations of z = a x^2 + b xy + c y^2 + d x + e y over its n neighbours, `offset(i)` the
// i-th's offset from the point, coordinates in units of the rms neighbour distance.
template <typename Offset>
void write_fit(const Vec3& start, int n, double length2, Offset offset, FitBatch& batch, int lane) {
  const Vec3 t1 = start.unitOrthogonal(), t2 = start.cross(t1);
  const double scale = std::sqrt(static_cast<double>(n) / length2);
  const Vec3 s1 = scale * t1, s2 = scale * t2, s3 = scale * start;
  // The matrix sum r r^T, r = (x^2, xy, y^2, x, y), has 12 distinct monomials: their sums.
  double x4 = 0, x3y = 0, x2y2 = 0, xy3 = 0, y4 = 0, x3 = 0, x2y = 0, xy2 = 0, y3 = 0, x2 = 0,
         xy = 0, y2 = 0;
  double b[5] = {};
  for (int i = 0; i < n; ++i) {
    const Vec3 q = offset(i);
    const double x = q.dot(s1), y = q.dot(s2), z = q.dot(s3);
    const double xx = x * x, xyi = x * y, yy = y * y;
    x4 += xx * xx, x3y += xx * xyi, x2y2 += xx * yy, xy3 += xyi * yy, y4 += yy * yy;
    x3 += xx * x, x2y += xx * y, xy2 += x * yy, y3 += yy * y;
    x2 += xx, xy += xyi, y2 += yy;
    b[0] += z * xx, b[1] += z * xyi, b[2] += z * yy, b[3] += z * x, b[4] += z * y;
  }
  const double a[15] = {x4, x3y, x2y2, x2y2, xy3, y4, x3, x2y, xy2, x2, x2y, xy2, y3, xy, y2};
  for (int k = 0; k < 15; ++k) batch.a[k][lane] = a[k];
  for (int k = 0; k < 5; ++k) batch.b[k][lane] = b[k];
  for (int d = 0; d < 3; ++d)
    batch.frame[d][lane] = start[d], batch.frame[3 + d][lane] = t1[d],
    batch.frame[6 + d][lane] = t2[d];
  batch.active[lane] = true;
}

// Solves every active lane's system by an LDL^T factorization in place (no square roots); a lane
// whose pivot is not clearly positive is turned off.
void solve_batch(FitBatch& batch) {
  double inv_d[5][kBatch], largest[kBatch];
  for (int s = 0; s < kBatch; ++s) {
    largest[s] = 0.0;
    for (int i = 0; i < 5; ++i) largest[s] = std::max(largest[s], batch.a[packed(i, i)][s]);
  }
  for (int j = 0; j < 5; ++j) {
    for (int s = 0; s < kBatch; ++s) {
      double d = batch.a[packed(j, j)][s];
      for (int k = 0; k < j; ++k)
        d -= batch.a[packed(j, k)][s] * batch.a[packed(j, k)][s] * batch.a[packed(k, k)][s];
      const bool positive = d > 1e-10 * largest[s];
      batch.active[s] = batch.active[s] && positive;
      batch.a[packed(j, j)][s] = d;
      inv_d[j][s] = 1.0 / (positive ? d : 1.0);
    }
    for (int i = j + 1; i < 5; ++i)
      for (int s = 0; s < kBatch; ++s) {
        double x = batch.a[packed(i, j)][s];
        for (int k = 0; k < j; ++k)
          x -= batch.a[packed(i, k)][s] * batch.a[packed(j, k)][s] * batch.a[packed(k, k)][s];
        batch.a[packed(i, j)][s] = x * inv_d[j][s];
      }
  }
  for (int i = 0; i < 5; ++i)  // L y = b
    for (int k = 0; k < i; ++k)
      for (int s = 0; s < kBatch; ++s) batch.b[i][s] -= batch.a[packed(i, k)][s] * batch.b[k][s];
  for (int i = 4; i >= 0; --i) {  // D L^T x = y
    for (int s = 0; s < kBatch; ++s) batch.b[i][s] *= inv_d[i][s];
    for (int k = i + 1; k < 5; ++k)
      for (int s = 0; s < kBatch; ++s) batch.b[i][s] -= batch.a[packed(k, i)][s] * batch.b[k][s];
  }
}

// The fitted patch's normal in lane `lane` where the fit succeeded and turns the start normal by
// less than 30 degrees; the start normal otherwise.
Vec3 fitted_normal(const FitBatch& batch, int lane) {
  constexpr double kMinCos = 0.8660254037844386;  // 30 degrees
  const Vec3 start(batch.frame[0][lane], batch.frame[1][lane], batch.frame[2][lane]);
  if (!batch.active[lane]) return start;
  const Vec3 t1(batch.frame[3][lane], batch.frame[4][lane], batch.frame[5][lane]);
  const Vec3 t2(batch.frame[6][lane], batch.frame[7][lane], batch.frame[8][lane]);
  const Vec3 fitted = (start - batch.b[3][lane] * t1 - batch.b[4][lane] * t2).normalized();
  return fitted.allFinite() && fitted.dot(start) > kMinCos ? fitted : start;
}

// The fast path for a point with at most kMaxFan triangles: one sweep of its fan gives the Max
// normal (its sum, not normalized) and the neighbours. A closed fan's next corners are its ring;
// otherwise the previous corners not seen are added; under kMinRing neighbours, those of the
// neighbours' fans (the 2-ring). False where the stack arrays are too small.
bool fan_ring(const TriMesh& mesh, const mesh::VertexTriangles& corners, int v, Ring& ring,
              Vec3& max_sum) {
  const std::span<const int> fan = corners.of(v);
  const int k = static_cast<int>(fan.size());
  if (k > kMaxFan) return false;
  const Vec3 o = mesh.points[v];
  int prev[kMaxFan];
  Vec3 prev_offset[kMaxFan];
  max_sum = Vec3::Zero();
  ring.n = 0, ring.length2 = 0.0;
  uint64_t sum_next = 0, sum_prev = 0, square_next = 0,
           square_prev = 0;  // wrap around: compared only
  bool touches_itself = false;
  for (int i = 0; i < k; ++i) {
    const Triangle& f = mesh.triangles[fan[i] / 3];
    const int c = fan[i] % 3;
    const int a = f[c == 2 ? 0 : c + 1], b = f[c == 0 ? 2 : c - 1];
    const Vec3 e1 = mesh.points[a] - o, e2 = mesh.points[b] - o;
    const Vec3 cross = e1.cross(e2);
    if (cross.squaredNorm() > 0.0) max_sum += max_term(cross, e1, e2);
    ring.id[i] = a, ring.q[i][0] = e1.x(), ring.q[i][1] = e1.y(), ring.q[i][2] = e1.z();
    ring.length2 += e1.squaredNorm();
    prev[i] = b, prev_offset[i] = e2;
    sum_next += static_cast<uint64_t>(a), sum_prev += static_cast<uint64_t>(b);
    square_next += static_cast<uint64_t>(a) * static_cast<uint64_t>(a);
    square_prev += static_cast<uint64_t>(b) * static_cast<uint64_t>(b);
    touches_itself |= a == v || b == v;
  }
  ring.n = k;
  // Closed: the previous corners are the next ones. Compared by the sums of the indices and of
  // their squares, which tells apart any two multisets differing in at most two elements: every
  // open fan, and a point where two open fans meet. (Where more meet, a match would leave the
  // fit a subset of the ring: still a fit, never a wrong index.)
  bool closed = !touches_itself;
  closed &= sum_next == sum_prev && square_next == square_prev;
  if (!closed) {
    const Ring next = ring;
    ring.n = 0, ring.length2 = 0.0;
    for (int i = 0; i < k; ++i)
      if (next.id[i] != v) ring.add(next.id[i], next.q[i][0], next.q[i][1], next.q[i][2]);
    for (int i = 0; i < k; ++i)
      if (prev[i] != v)
        ring.add(prev[i], prev_offset[i].x(), prev_offset[i].y(), prev_offset[i].z());
  }
  if (ring.n >= kMinRing) return true;
  const int first = ring.n;
  for (int i = 0; i < first; ++i)
    for (int corner : corners.of(ring.id[i])) {
      const Triangle& f = mesh.triangles[corner / 3];
      for (int w : f) {
        if (w == v) continue;
        const Vec3 q = mesh.points[w] - o;
        if (!ring.add(w, q.x(), q.y(), q.z())) return false;
      }
    }
  return true;
}

// Quadric-fit normals of points [begin, end), kBatch at a time.
void fit_normals(const TriMesh& mesh, const mesh::VertexTriangles& corners, int begin, int end,
                 tbb::enumerable_thread_specific<std::vector<int>>& stamps,
                 std::vector<Vec3>& normals) {
  FitBatch batch;
  Ring ring;
  std::vector<int> large_ring;
  for (int first = begin; first < end; first += kBatch) {
    const int count = std::min(kBatch, end - first);
    for (int lane = 0; lane < kBatch; ++lane) {
      batch.active[lane] = false;
      for (int i = 0; i < 5; ++i)  // idle lanes solve the identity
        for (int j = 0; j <= i; ++j) batch.a[packed(i, j)][lane] = i == j ? 1.0 : 0.0;
      for (int k = 0; k < 5; ++k) batch.b[k][lane] = 0.0;
      for (int k = 0; k < 9; ++k) batch.frame[k][lane] = 0.0;
      if (lane >= count) continue;
      const int v = first + lane;
      Vec3 max_sum;
      if (fan_ring(mesh, corners, v, ring, max_sum)) {
        const Vec3 start = unit_or_zero(max_sum);
        for (int d = 0; d < 3; ++d) batch.frame[d][lane] = start[d];
        if (ring.n >= kMinRing && start.squaredNorm() > 0.0)
          write_fit(
              start, ring.n, ring.length2,
              [&](int i) { return Vec3(ring.q[i][0], ring.q[i][1], ring.q[i][2]); }, batch, lane);
        continue;
      }
      // A large fan: the general path.
      const Vec3 start = unit_or_zero(weighted_sum(mesh, corners, v, NormalMethod::max));
      for (int d = 0; d < 3; ++d) batch.frame[d][lane] = start[d];
      mesh::gather_ring(mesh, corners, v, kMinRing, stamps.local(), large_ring);
      if (static_cast<int>(large_ring.size()) < kMinRing || start.squaredNorm() == 0.0) continue;
      double length2 = 0.0;
      for (int w : large_ring) length2 += (mesh.points[w] - mesh.points[v]).squaredNorm();
      write_fit(
          start, static_cast<int>(large_ring.size()), length2,
          [&](int i) { return Vec3(mesh.points[large_ring[i]] - mesh.points[v]); }, batch, lane);
    }
    solve_batch(batch);
    for (int lane = 0; lane < count; ++lane) normals[first + lane] = fitted_normal(batch, lane);
  }
}

}  // namespace

std::vector<Vec3> vertex_normals(const TriMesh& mesh, const mesh::VertexTriangles& corners, NormalMethod method) {
  std::vector<Vec3> normals(mesh.points.size());
  if (method != NormalMethod::quadric_fit) {
    tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_points(), kGrain), [&](const tbb::blocked_range<int>& range) {
      for (int v = range.begin(); v < range.end(); ++v) normals[v] = unit_or_zero(weighted_sum(mesh, corners, v, method));
    });
    return normals;
  }
  // Stamp arrays only for the threads that meet a large fan.
  tbb::enumerable_thread_specific<std::vector<int>> stamps(
      [&] { return std::vector<int>(mesh.points.size(), 0); });
  tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_points(), kGrain),
                    [&](const tbb::blocked_range<int>& range) {
                      fit_normals(mesh, corners, range.begin(), range.end(), stamps, normals);
                    });
  return normals;
}

std::vector<Vec3> vertex_normals(const TriMesh& mesh, NormalMethod method) {
  return vertex_normals(mesh, mesh::build_vertex_corners(mesh), method);
}

}  // namespace vesselmesh::analysis
