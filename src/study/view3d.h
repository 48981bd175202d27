// The study report's interactive 3D view (issue 53): the wall of every compared mesh and of the
// reference, coloured by |WSS| on one shared scale, the rings drawn as lines and the points as
// markers, the views' cameras linked (turning or zooming one turns every one), and a toggle to each
// mesh's difference from the reference on the reference's wall. Self-contained HTML: three.js
// (Debian's libjs-three, read when the report is written) and the data inlined, no network needed.
// Walls are made coarser for display only (at most kViewTriangles triangles each).
#pragma once

#include "mesh/trimesh.h"

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace vesselmesh::study {

inline constexpr int kViewTriangles = 50000;

// One wall as shown: its display mesh and the values on its points.
struct ViewedWall {
  std::string name;
  TriMesh mesh;                             // mesh units
  std::vector<double> magnitude;            // |WSS| per point, Pa
  std::vector<double> difference;           // per point of the reference's display wall: this mesh's |WSS|
                                            // there minus the reference's, Pa; empty for the reference
  std::vector<std::vector<Vec3>> rings;     // the rings on this wall, as polylines
};

// A wall made ready for display: at most `max_triangles` triangles, |WSS| moved onto them.
ViewedWall viewed_wall(const std::string& name, const TriMesh& wall, const std::vector<double>& magnitude,
                       int max_triangles = kViewTriangles);
// `wall`'s |WSS| (per point of `wall`) on the reference's display wall, minus the reference's there.
std::vector<double> difference_on(const ViewedWall& reference, const TriMesh& wall,
                                  const std::vector<double>& magnitude);

struct ViewScene {
  std::vector<ViewedWall> walls;
  size_t reference = 0;                              // index into walls
  std::vector<std::pair<std::string, Vec3>> points;  // the study's points, marked
  double high = 1.0;                                 // |WSS| colours from 0 to this, Pa
  double difference_range = 1.0;                     // difference colours from -this to +this, Pa
  Vec3 view = Vec3::UnitZ();                         // the direction first looked along
  std::string unit = "mm";
};

// The difference colours: blue (t = -1), white (0), red (+1), as RGB in [0, 1]; t clamped.
std::array<double, 3> diverging(double t);

// three.js and its orbit controls, as text.
struct ThreeScripts {
  std::string three, controls;
};
// From $VESSELMESH_THREE_DIR, else Debian's /usr/share/javascript/three; nothing when absent.
std::optional<ThreeScripts> read_three_scripts();

// The view as one HTML block (a <section id="view3d"> with its scripts; three.js kept as text and run
// when the section comes near the window, so that the rest of the report opens without it). Opening the report with
// "?view3d" after its file name shows this section alone ("?view3d=difference": in the difference
// mode). When drawn, the page's element #view3d-status holds JSON: {"drawn": views, "errors":
// [messages], "rects": [[x, y, w, h] per view, CSS pixels], "milliseconds": from the page's start}.
std::string view3d_html(const ViewScene& scene, const ThreeScripts& scripts);

}  // namespace vesselmesh::study
