// The fluid results of `vesselmesh simulate` read back and sampled anywhere inside the mesh: the
// tetrahedron that holds a point is found through a uniform grid of buckets, and the point's
// values interpolated linearly in it (the solver's own P1 interpolation). The frames come from
// DIR/fluid.pvd; lengths in the mesh's unit, velocity in m/s, pressure in Pa.
#pragma once

#include "mesh/tetmesh.h"
#include "post/wall_series.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace vesselmesh::post {

// Point location in a tetrahedral mesh (prisms split as the solver splits them). Built once;
// queries are const and may run concurrently.
class TetLocator {
 public:
  struct Hit {
    int tet = -1;                    // index into tets()
    std::array<double, 4> weights{};  // barycentric, summing to one, each >= -tolerance
  };
  explicit TetLocator(const TetMesh& mesh);

  // The tetrahedron holding p (within a relative tolerance of its size, so points on faces and
  // on the boundary are found), the one of least index where several do; none outside.
  std::optional<Hit> locate(const Vec3& p) const;
  const std::vector<Tet>& tets() const { return tets_; }
  // A field given per mesh point (velocity, pressure, the statistics' RMS...), linear at a hit.
  template <typename T>
  T interpolate(const Hit& hit, const std::vector<T>& values) const {
    const Tet& t = tets_[hit.tet];
    T sum = hit.weights[0] * values[t[0]];
    for (int k = 1; k < 4; ++k) sum += hit.weights[k] * values[t[k]];
    return sum;
  }

 private:
  std::vector<Vec3> points_;
  std::vector<Tet> tets_;
  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1.0;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<int> bucket_start_, bucket_tets_;  // CSR: the tetrahedra whose box meets a bucket
};

struct FluidField {
  TetMesh mesh;                 // in the mesh's length unit
  std::vector<Vec3> velocity;   // m/s, per point
  std::vector<double> pressure;  // Pa, per point
  double time = 0.0;             // s
};

// One saved frame of DIR/fluid.pvd (read_result_series(dir, "fluid")). InputError naming the
// file when it lacks point data `velocity` (3 components) or `pressure`.
FluidField read_fluid_frame(const WallFrame& frame);

// The fluid at `time`, linear between the two saved frames around it (frames_around).
FluidField fluid_at_time(const WallSeries& series, double time);

// The time statistics of a run with [output] statistics_from (DIR/statistics.vtu, or .pvtu under
// mpirun; flow/statistics.h): `mean` the time means (its velocity the mean velocity, its pressure the
// mean pressure, its time the span's end), `rms` per point the RMS of the velocity's fluctuation about
// its mean, per component (m/s), over t = start to end (s, from the run's summary). InputError naming
// the folder where the run kept none.
struct FluidStatistics {
  FluidField mean;
  std::vector<Vec3> rms;
  double start = 0.0, end = 0.0;
};
FluidStatistics read_fluid_statistics(const std::string& directory);

struct FluidSample {
  Vec3 point = Vec3::Zero();
  double distance = 0.0;  // from the line's start, in the mesh's unit
  bool inside = false;    // false: outside the mesh, values zero
  Vec3 velocity = Vec3::Zero();
  double pressure = 0.0;
};

// `samples` (>= 2) points evenly spaced from a to b, both included.
std::vector<FluidSample> sample_line(const FluidField& field, const TetLocator& locator, const Vec3& a, const Vec3& b,
                                    int samples);

// The values at given points.
std::vector<FluidSample> sample_points(const FluidField& field, const TetLocator& locator,
                                      const std::vector<Vec3>& points);

}  // namespace vesselmesh::post
