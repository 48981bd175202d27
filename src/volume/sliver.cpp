#include "volume/sliver.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <utility>

namespace vesselmesh::volume {
namespace {

constexpr double kFlat = -1.0;  // the quality of a flat or inverted tetrahedron

// The face opposite corner c of a positive tetrahedron t, ordered so that (face, t[c]) is positive.
constexpr int kFaceOpposite[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};

// The corners of t's face opposite corner c, in increasing order (a key for that face).
std::array<int, 3> sorted_face(const Tet& t, int c) {
  std::array<int, 3> f = {t[kFaceOpposite[c][0]], t[kFaceOpposite[c][1]], t[kFaceOpposite[c][2]]};
  std::sort(f.begin(), f.end());
  return f;
}

// What an operation must raise: the least dihedral angle (degrees), capped by 60 x the
// volume-length measure 6 sqrt(2) V / l_rms^3 (1 for the regular tetrahedron, 0 for a flat
// one), so that a sliver is never traded for a needle or a cap: those keep fair dihedral angles
// but not their volume.
double work_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double angle = least_dihedral_deg(a, b, c, d);
  if (angle <= 0.0) return angle;
  const double squares = ((b - a).squaredNorm() + (c - a).squaredNorm() + (d - a).squaredNorm() +
                          (c - b).squaredNorm() + (d - b).squaredNorm() + (d - c).squaredNorm()) / 6.0;
  const double shape = std::sqrt(2.0) * mesh::tet_volume6(a, b, c, d) / (squares * std::sqrt(squares));
  return std::min(angle, 60.0 * shape);
}

// The tetrahedra, the tetrahedra around each point, and which are still in the mesh.
class Mesh {
 public:
  Mesh(std::vector<Vec3>& points, std::vector<Tet>& tets) : points_(points), tets_(tets), ball_(points.size()) {
    alive_.assign(tets.size(), 1);
    for (int t = 0; t < static_cast<int>(tets.size()); ++t)
      for (int v : tets[t]) ball_[v].push_back(t);
  }

  const Vec3& point(int v) const { return points_[v]; }
  const Tet& tet(int t) const { return tets_[t]; }
  bool alive(int t) const { return alive_[t] != 0; }
  int num_tets() const { return static_cast<int>(tets_.size()); }
  const std::vector<int>& ball(int v) const { return ball_[v]; }

  double quality(const Tet& t) const {
    return work_quality(points_[t[0]], points_[t[1]], points_[t[2]], points_[t[3]]);
  }
  double quality(int t) const { return quality(tets_[t]); }
  double dihedral(int t) const {
    const Tet& c = tets_[t];
    return least_dihedral_deg(points_[c[0]], points_[c[1]], points_[c[2]], points_[c[3]]);
  }

  // The live tetrahedra holding all of `corners` (2 or 3 points).
  std::vector<int> holding(std::initializer_list<int> corners) const {
    const int first = *corners.begin();
    std::vector<int> out;
    for (int t : ball_[first]) {
      bool all = true;
      for (int v : corners) all = all && std::find(tets_[t].begin(), tets_[t].end(), v) != tets_[t].end();
      if (all) out.push_back(t);
    }
    return out;
  }

  // The live tetrahedra other than t holding t's face opposite corner c: one inside, none on
  // the boundary.
  std::vector<int> across(int t, int c) const {
    const Tet& tt = tets_[t];
    std::vector<int> out = holding({tt[kFaceOpposite[c][0]], tt[kFaceOpposite[c][1]], tt[kFaceOpposite[c][2]]});
    std::erase(out, t);
    return out;
  }

  // Replaces tetrahedra `old` by `fresh` (slots of the old ones reused first, in order).
  void replace(const std::vector<int>& old, const std::vector<Tet>& fresh) {
    for (int t : old) {
      for (int v : tets_[t]) std::erase(ball_[v], t);
      alive_[t] = 0;
    }
    for (size_t i = 0; i < fresh.size(); ++i) {
      int t;
      if (i < old.size()) {
        t = old[i];
        tets_[t] = fresh[i];
        alive_[t] = 1;
      } else {
        t = static_cast<int>(tets_.size());
        tets_.push_back(fresh[i]);
        alive_.push_back(1);
      }
      for (int v : fresh[i]) ball_[v].push_back(t);
      touched_.push_back(t);
    }
  }

  size_t ball_count() const { return ball_.size(); }
  int add_point(const Vec3& p) {
    points_.push_back(p);
    ball_.emplace_back();
    return static_cast<int>(points_.size()) - 1;
  }
  void remove_last_point() {
    points_.pop_back();
    ball_.pop_back();
  }
  void move(int v, const Vec3& p) {
    points_[v] = p;
    touched_.insert(touched_.end(), ball_[v].begin(), ball_[v].end());
  }
  // The tetrahedra made or moved since the last call.
  std::vector<int> take_touched() { return std::exchange(touched_, {}); }

  // Drops the dead tetrahedra, keeping the order of the others.
  void compact() {
    size_t kept = 0;
    for (size_t t = 0; t < tets_.size(); ++t)
      if (alive_[t]) tets_[kept++] = tets_[t];
    tets_.resize(kept);
    alive_.assign(kept, 1);
    ball_.clear();  // not kept up to date past this point
  }

 private:
  std::vector<Vec3>& points_;
  std::vector<Tet>& tets_;
  std::vector<std::vector<int>> ball_;
  std::vector<char> alive_;
  std::vector<int> touched_;
};

double least_of(const Mesh& m, const std::vector<Tet>& tets) {
  double least = std::numeric_limits<double>::infinity();
  for (const Tet& t : tets) least = std::min(least, m.quality(t));
  return least;
}
double least_of(const Mesh& m, const std::vector<int>& tets) {
  double least = std::numeric_limits<double>::infinity();
  for (int t : tets) least = std::min(least, m.quality(t));
  return least;
}

// 2-3 flip of the face of t opposite its corner `c`, if it is shared and the flip raises the
// least angle.
bool try_flip23(Mesh& m, int t, int c) {
  const Tet& tt = m.tet(t);
  const int d = tt[c];
  // (a, b, c) with d on its positive side: a positive tetrahedron (a, b, c, d) is tt with d last.
  int face[3], k = 0;
  for (int i : kFaceOpposite[c]) face[k++] = tt[i];
  const std::vector<int> other = m.across(t, c);
  if (other.size() != 1) return false;  // a boundary face
  const int u = other[0];
  int e = -1;
  for (int v : m.tet(u))
    if (v != face[0] && v != face[1] && v != face[2]) e = v;
  const std::vector<Tet> fresh = {{face[0], face[1], e, d}, {face[1], face[2], e, d}, {face[2], face[0], e, d}};
  const std::vector<int> old = {t, u};
  if (least_of(m, fresh) <= least_of(m, old)) return false;
  m.replace(old, fresh);
  return true;
}

// The corners around edge (c, d) in cyclic order, oriented so that (c, d, x_i, x_i+1) is
// positive, when the tetrahedra holding the edge close a ring around it (an edge inside the
// mesh); empty for an edge on the boundary.
std::vector<int> edge_ring(const Mesh& m, int c, int d, const std::vector<int>& ring) {
  std::vector<std::pair<int, int>> links;  // (x, y) with (c, d, x, y) positive
  for (int t : ring) {
    int xy[2], k = 0;
    for (int v : m.tet(t))
      if (v != c && v != d) xy[k++] = v;
    if (mesh::tet_volume6(m.point(c), m.point(d), m.point(xy[0]), m.point(xy[1])) < 0.0) std::swap(xy[0], xy[1]);
    links.emplace_back(xy[0], xy[1]);
  }
  std::vector<int> order = {links[0].first};
  for (size_t step = 0; step < links.size(); ++step) {
    const auto next = std::find_if(links.begin(), links.end(), [&](const auto& l) { return l.first == order.back(); });
    if (next == links.end()) return {};
    if (next->second == order.front()) return order.size() == links.size() ? order : std::vector<int>{};
    order.push_back(next->second);
  }
  return {};
}

// Edge removal (Shewchuk, "Two discrete optimization algorithms for the topological improvement
// of tetrahedral meshes", 2002): the n tetrahedra around an inside edge (c, d) replaced by the
// 2 (n - 2) joining c and d to a triangulation of the ring of their other corners, the
// triangulation that makes the least angle largest (dynamic programming over the ring), if it
// raises the least angle. n = 3 is the 3-2 flip, n = 4 the 4-4 flip.
bool try_edge_removal(Mesh& m, int c, int d) {
  constexpr int kMaxRing = 8;
  const std::vector<int> ring = m.holding({c, d});
  if (ring.size() < 3 || ring.size() > kMaxRing) return false;
  const std::vector<int> x = edge_ring(m, c, d, ring);
  const int n = static_cast<int>(x.size());
  if (n < 3) return false;
  // A triangle (x_i, x_j, x_k), i < j < k, gives (x_i, x_j, x_k, d) and (x_k, x_j, x_i, c).
  auto pair_quality = [&](int i, int j, int k) {
    return std::min(m.quality(Tet{x[i], x[j], x[k], d}), m.quality(Tet{x[k], x[j], x[i], c}));
  };
  double best[kMaxRing][kMaxRing];
  int split[kMaxRing][kMaxRing];
  for (int gap = 2; gap < n; ++gap)
    for (int i = 0; i + gap < n; ++i) {
      const int j = i + gap;
      best[i][j] = -std::numeric_limits<double>::infinity();
      for (int k = i + 1; k < j; ++k) {
        double q = pair_quality(i, k, j);
        if (k - i > 1) q = std::min(q, best[i][k]);
        if (j - k > 1) q = std::min(q, best[k][j]);
        if (q > best[i][j]) best[i][j] = q, split[i][j] = k;
      }
    }
  if (best[0][n - 1] <= least_of(m, ring)) return false;
  std::vector<Tet> fresh;
  std::vector<std::pair<int, int>> todo = {{0, n - 1}};
  while (!todo.empty()) {
    const auto [i, j] = todo.back();
    todo.pop_back();
    const int k = split[i][j];
    fresh.push_back({x[i], x[k], x[j], d});
    fresh.push_back({x[j], x[k], x[i], c});
    if (k - i > 1) todo.emplace_back(i, k);
    if (j - k > 1) todo.emplace_back(k, j);
  }
  m.replace(ring, fresh);
  return true;
}

// The least angle around v with v at p.
double ball_quality(const Mesh& m, int v, const Vec3& p) {
  double least = std::numeric_limits<double>::infinity();
  for (int t : m.ball(v)) {
    Vec3 c[4];
    for (int i = 0; i < 4; ++i) c[i] = m.tet(t)[i] == v ? p : m.point(m.tet(t)[i]);
    least = std::min(least, work_quality(c[0], c[1], c[2], c[3]));
  }
  return least;
}

// Moves free point v by compass search to raise the least angle around it; true if it moved.
bool try_smooth(Mesh& m, int v) {
  const Vec3 start = m.point(v);
  double step = 0.0;
  int count = 0;
  for (int t : m.ball(v))
    for (int w : m.tet(t))
      if (w != v) step += (m.point(w) - start).norm(), ++count;
  if (count == 0) return false;
  step *= 0.1 / count;
  const double stop = 1e-3 * step;
  Vec3 p = start;
  const double before = ball_quality(m, v, p);
  double best = before;
  static const Vec3 kDirections[6] = {Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(),
                                      -Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitZ()};
  for (int iteration = 0; iteration < 60 && step > stop; ++iteration) {
    Vec3 next = p;
    double next_quality = best;
    for (const Vec3& direction : kDirections) {
      const Vec3 q = p + step * direction;
      const double quality = ball_quality(m, v, q);
      if (quality > next_quality) next_quality = quality, next = q;
    }
    if (next_quality > best) p = next, best = next_quality;
    else step *= 0.5;
  }
  if (!(best > before)) return false;
  m.move(v, p);
  return true;
}

// Replaces the tetrahedra `cavity` by `fresh`, which join its boundary to the last point added,
// then smooths that point; keeps the result if the least angle rose, else undoes both (the
// point removed).
bool try_star(Mesh& m, const std::vector<int>& cavity, const std::vector<Tet>& fresh) {
  const int p = static_cast<int>(m.ball_count()) - 1;
  const double before = least_of(m, cavity);
  if (least_of(m, fresh) <= kFlat + 0.5) {  // the point does not see every face
    m.remove_last_point();
    return false;
  }
  std::vector<Tet> original;
  for (int u : cavity) original.push_back(m.tet(u));
  m.replace(cavity, fresh);
  try_smooth(m, p);
  if (ball_quality(m, p, m.point(p)) > before) return true;
  // Undo: every tetrahedron of the cavity back in its own slot (the cavity's slots first, in its
  // order), the slots added for the new ones freed.
  std::vector<int> slots = cavity;
  for (int u : m.ball(p))
    if (std::find(cavity.begin(), cavity.end(), u) == cavity.end()) slots.push_back(u);
  m.replace(slots, original);
  m.remove_last_point();
  return false;
}

// Splits the inside edge (c, d) of a sliver at its midpoint (each tetrahedron around it cut in
// two), the new point then smoothed: what frees a sliver whose corners are all on the
// boundary and whose edge removals all fail.
bool try_edge_split(Mesh& m, int c, int d) {
  const std::vector<int> ring = m.holding({c, d});
  if (ring.size() < 3 || edge_ring(m, c, d, ring).empty()) return false;
  const int p = m.add_point(0.5 * (m.point(c) + m.point(d)));
  std::vector<Tet> fresh;
  for (int t : ring)
    for (int end : {c, d}) {
      Tet half = m.tet(t);
      for (int& v : half)
        if (v == end) v = p;
      fresh.push_back(half);
    }
  return try_star(m, ring, fresh);
}

// Removes free point v by moving it onto a neighbour w (edge collapse): the tetrahedra around
// v become those joining w to the faces of v's ball away from w, the neighbour that makes the
// least angle largest; kept if it rises. The ball must be closed (v inside the mesh) and
// every new tetrahedron positive, so that they fill the ball exactly. v is left out of every
// tetrahedron (remove_slivers drops such points at the end).
bool try_collapse(Mesh& m, int v) {
  const std::vector<int> ball = m.ball(v);
  // Closed: each face through v is shared by two tetrahedra of the ball.
  std::vector<std::array<int, 3>> faces;
  std::vector<int> neighbours;
  for (int t : ball) {
    const Tet& tt = m.tet(t);
    for (int c = 0; c < 4; ++c) {
      if (tt[c] == v) continue;
      neighbours.push_back(tt[c]);
      faces.push_back(sorted_face(tt, c));
    }
  }
  std::sort(faces.begin(), faces.end());
  for (size_t i = 0; i < faces.size(); i += 2)
    if (i + 1 >= faces.size() || faces[i] != faces[i + 1]) return false;
  std::sort(neighbours.begin(), neighbours.end());
  neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
  const double before = least_of(m, ball);
  double best = before;
  std::vector<Tet> chosen;
  for (int w : neighbours) {
    std::vector<Tet> fresh;
    for (int t : ball) {
      Tet n = m.tet(t);
      if (std::find(n.begin(), n.end(), w) != n.end()) continue;
      std::replace(n.begin(), n.end(), v, w);
      fresh.push_back(n);
    }
    const double q = least_of(m, fresh);
    if (q > best) best = q, chosen = std::move(fresh);
  }
  if (chosen.empty()) return false;
  m.replace(ball, chosen);
  return true;
}

// Inserts a point at `at`, joined to the faces of `cavity` used once (each becomes a tetrahedron
// with the new point in place of the corner across it), then smoothed; kept if the least angle
// rises (try_star). Refused when a corner of the cavity is on none of those faces: it would be
// left out of the mesh.
bool try_insert(Mesh& m, const std::vector<int>& cavity, const Vec3& at) {
  struct Face {
    std::array<int, 3> sorted;
    int tet, corner;
  };
  std::vector<Face> faces;
  for (int u : cavity)
    for (int c = 0; c < 4; ++c) faces.push_back({sorted_face(m.tet(u), c), u, c});
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.sorted < b.sorted; });
  const int p = m.add_point(at);
  std::vector<Tet> fresh;
  for (size_t i = 0; i < faces.size(); ++i) {
    const bool twice = (i + 1 < faces.size() && faces[i + 1].sorted == faces[i].sorted) ||
                       (i > 0 && faces[i - 1].sorted == faces[i].sorted);
    if (twice) continue;
    Tet n = m.tet(faces[i].tet);
    n[faces[i].corner] = p;
    fresh.push_back(n);
  }
  std::vector<int> kept, corners;
  for (const Tet& n : fresh) kept.insert(kept.end(), n.begin(), n.end());
  for (int u : cavity) corners.insert(corners.end(), m.tet(u).begin(), m.tet(u).end());
  std::sort(kept.begin(), kept.end());
  for (int v : corners)
    if (!std::binary_search(kept.begin(), kept.end(), v)) {
      m.remove_last_point();
      return false;
    }
  return try_star(m, cavity, fresh);
}

// A point at the centroid of t, in the cavity of t and its face neighbours.
bool try_insert_centroid(Mesh& m, int t) {
  const Tet tt = m.tet(t);
  std::vector<int> cavity = {t};
  for (int c = 0; c < 4; ++c)
    for (int u : m.across(t, c)) cavity.push_back(u);
  Vec3 centroid = Vec3::Zero();
  for (int v : tt) centroid += 0.25 * m.point(v);
  return try_insert(m, cavity, centroid);
}

// True if p is inside the circumsphere of tetrahedron t.
bool in_circumsphere(const Mesh& m, int t, const Vec3& p) {
  const Vec3& a = m.point(m.tet(t)[0]);
  const Vec3 b = m.point(m.tet(t)[1]) - a, c = m.point(m.tet(t)[2]) - a, d = m.point(m.tet(t)[3]) - a;
  const double det = 2.0 * b.dot(c.cross(d));
  if (!(std::abs(det) > 0.0)) return false;
  const Vec3 centre = (b.squaredNorm() * c.cross(d) + c.squaredNorm() * d.cross(b) + d.squaredNorm() * b.cross(c)) / det;
  return (p - a - centre).squaredNorm() < centre.squaredNorm();
}

// A sliver standing on the boundary (a face of it used once) whose far corner cannot move away
// from that face: a point where a fair tetrahedron on the face would have its apex (over the
// face's centroid, at 1, 0.7 or 0.45 of a regular one's height), in the cavity of the
// tetrahedra whose circumspheres hold it, grown from t across faces (Bowyer and Watson).
bool try_insert_over_boundary(Mesh& m, int t) {
  for (int c = 0; c < 4; ++c) {
    const Tet tt = m.tet(t);
    if (!m.across(t, c).empty()) continue;
    const int f[3] = {tt[kFaceOpposite[c][0]], tt[kFaceOpposite[c][1]], tt[kFaceOpposite[c][2]]};
    const Vec3 &a = m.point(f[0]), &b = m.point(f[1]), &d = m.point(f[2]);
    const Vec3 normal = (b - a).cross(d - a).normalized();  // toward t[c]: (face, t[c]) is positive
    const double edge = ((b - a).norm() + (d - b).norm() + (a - d).norm()) / 3.0;
    for (double height : {1.0, 0.7, 0.45}) {
      const Vec3 apex = (a + b + d) / 3.0 + height * std::sqrt(2.0 / 3.0) * edge * normal;
      std::vector<int> cavity = {t};
      for (size_t i = 0; i < cavity.size() && cavity.size() < 64; ++i) {
        for (int k = 0; k < 4; ++k)
          for (int w : m.across(cavity[i], k))
            if (std::find(cavity.begin(), cavity.end(), w) == cavity.end() && in_circumsphere(m, w, apex))
              cavity.push_back(w);
      }
      if (try_insert(m, cavity, apex)) return true;
    }
  }
  return false;
}

}  // namespace

double least_dihedral_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  if (!(mesh::tet_volume6(a, b, c, d) > 0.0)) return kFlat;  // positive: no face is degenerate
  return mesh::least_dihedral_angle(a, b, c, d) * 180.0 / std::numbers::pi;
}

SliverReport remove_slivers(std::vector<Vec3>& points, std::vector<Tet>& tets, int first_free,
                            const SliverOptions& options) {
  SliverReport report;
  Mesh m(points, tets);
  // Counts the tetrahedra under the goal (listing them in `bad_ones` when given) and finds the worst.
  auto census = [&](int& below, double& least, std::vector<int>* bad_ones) {
    below = 0;
    least = std::numeric_limits<double>::infinity();
    for (int t = 0; t < m.num_tets(); ++t) {
      if (!m.alive(t)) continue;
      const double q = m.dihedral(t);
      if (q < options.min_dihedral_deg) {
        ++below;
        if (bad_ones) bad_ones->push_back(t);
      }
      if (q < least) {
        least = q;
        report.worst_at = Vec3::Zero();
        for (int v : m.tet(t)) report.worst_at += 0.25 * m.point(v);
      }
    }
  };
  std::vector<int> candidates;
  census(report.below_before, report.least_before, &candidates);
  auto bad = [&](int t) { return m.alive(t) && m.dihedral(t) < options.min_dihedral_deg; };
  static const int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  auto operations = [&] { return report.flips + report.moves + report.insertions + report.collapses; };
  // Flips that raise the least angle of u's neighbourhood: 2-3 across its faces, edge removal
  // around its edges. Moves of u's free corners.
  auto flip = [&](int u) {
    for (int c = 0; c < 4; ++c)
      if (try_flip23(m, u, c)) return ++report.flips, true;
    for (int e = 0; e < 6; ++e)
      if (try_edge_removal(m, m.tet(u)[kEdges[e][0]], m.tet(u)[kEdges[e][1]])) return ++report.flips, true;
    return false;
  };
  auto smooth_corners = [&](int u) {
    const Tet corners = m.tet(u);
    for (int v : corners)
      if (v >= first_free && try_smooth(m, v)) ++report.moves;
  };
  for (int pass = 0; pass < options.passes && !candidates.empty(); ++pass) {
    m.take_touched();
    const int done_before = operations();
    for (int t : candidates) {
      if (!bad(t)) continue;
      bool done = flip(t);
      if (!done) {
        smooth_corners(t);
        done = !bad(t);
      }
      if (!done) {
        const Tet corners = m.tet(t);
        for (int c = 0; c < 4 && !done; ++c)
          if (corners[c] >= first_free && try_collapse(m, corners[c])) ++report.collapses, done = true;
      }
      for (int e = 0; e < 6 && !done; ++e)
        if (try_edge_split(m, m.tet(t)[kEdges[e][0]], m.tet(t)[kEdges[e][1]])) ++report.insertions, done = true;
      if (!done && try_insert_centroid(m, t)) ++report.insertions, done = true;
      if (!done && try_insert_over_boundary(m, t)) ++report.insertions, done = true;
      // Stuck: flips and moves on the tetrahedra across its faces (each kept only if it raises
      // their own least angle) change what t's operations see in the next pass.
      if (!done) {
        std::vector<int> around;
        for (int c = 0; c < 4; ++c)
          for (int u : m.across(t, c)) around.push_back(u);
        for (int u : around)
          if (m.alive(u) && !flip(u)) smooth_corners(u);  // alive: not gone with an earlier one's flip
      }
    }
    // Next pass: what is still under the goal among the tetrahedra worked on or touched.
    std::vector<int> next = m.take_touched();
    next.insert(next.end(), candidates.begin(), candidates.end());
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    candidates.clear();
    for (int t : next)
      if (bad(t)) candidates.push_back(t);
    if (operations() == done_before) break;  // nothing more changes
  }
  m.compact();
  // Points removed by collapses: dropped, the others renumbered (those below first_free keep
  // their indices).
  std::vector<char> used(points.size(), 0);
  for (const Tet& t : tets)
    for (int v : t) used[v] = 1;
  std::vector<int> index(points.size(), -1);
  int next_index = first_free;
  for (int v = 0; v < static_cast<int>(points.size()); ++v) {
    if (v < first_free) {
      index[v] = v;
    } else if (used[v]) {
      points[next_index] = points[v];
      index[v] = next_index++;
    }
  }
  points.resize(next_index);
  for (Tet& t : tets)
    for (int& v : t) v = index[v];
  census(report.below_after, report.least_after, nullptr);
  return report;
}

}  // namespace vesselmesh::volume
