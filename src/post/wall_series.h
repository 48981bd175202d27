// The wall results of `vesselmesh simulate` read back: the frames listed by DIR/wall.pvd
// (time, VTP file with point data `wss` in Pa), the mesh's length unit from DIR/summary.json,
// and the wall shear stress at any time within the saved span (linear between frames).
#pragma once

#include "mesh/trimesh.h"

#include <string>
#include <vector>

namespace vesselmesh::post {

struct WallFrame {
  double time = 0.0;  // s
  std::string file;   // path of the VTP
};

struct WallSeries {
  std::string directory;
  std::vector<WallFrame> frames;  // increasing time
  std::string length_unit = "mm";
  double length_scale = 1e-3;  // metres per unit
  double period = 0.0;         // s, from the summary; 0 when the case gave none
  // The fluid, from the summary (or, for a flow made before the summary named it, the case file it
  // names, where that still exists); 0 when neither says.
  double density = 0.0;    // kg/m3
  double viscosity = 0.0;  // Pa s
};

// Throws InputError naming the file when the folder has no readable wall.pvd. `collection`
// "fluid" reads the volume's frames (DIR/fluid.pvd) instead.
WallSeries read_wall_series(const std::string& directory, const std::string& collection = "wall");

struct WallField {
  TriMesh mesh;            // the wall, in the mesh's length unit
  std::vector<Vec3> wss;   // Pa, per point
  double time = 0.0;
};

WallField read_wall_frame(const WallFrame& frame);

// The saved frames around `time` (indices into series.frames; equal when `time` falls on a
// frame) and the weight of the second; InputError when `time` lies outside the saved span.
struct FramePair {
  size_t first = 0, second = 0;
  double weight = 0.0;
};
FramePair frames_around(const WallSeries& series, double time);

// The saved frames of the series' last period where its flow has one (`period`), else the last
// frame alone: what a metric bounds by default (wall_metric.h, fluid_metric.h).
std::vector<const WallFrame*> last_period_frames(const WallSeries& series);

// The frames a metric bounds, in turn (`use(field, first)`): at each of `times`, `at(series, t)`
// (interpolated), or with no times each of last_period_frames read by `read` (one at a time: a
// cycle's frames of a large mesh do not all fit at once).
template <typename Read, typename At, typename Use>
void for_bounded_frames(const WallSeries& series, const std::vector<double>& times, Read read, At at, Use use) {
  if (times.empty()) {
    const std::vector<const WallFrame*> saved = last_period_frames(series);
    for (size_t i = 0; i < saved.size(); ++i) use(read(*saved[i]), i == 0);
  } else {
    for (size_t i = 0; i < times.size(); ++i) use(at(series, times[i]), i == 0);
  }
}

// A vector field's three components appended to `fields`, one scalar field each.
void append_components(std::vector<std::vector<double>>& fields, const std::vector<Vec3>& vectors);

// Linear in time between the two saved frames around `time`; InputError when `time` lies
// outside the saved span (the message gives it).
WallField wall_at_time(const WallSeries& series, double time);

}  // namespace vesselmesh::post
