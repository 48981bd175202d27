#include "study/study_report.h"

#include "study/report_document.h"

#include "io/atomic_file.h"
#include "post/wall_series.h"
#include "study/chart.h"
#include "study/envelope.h"
#include "study/gci.h"
#include "study/picture.h"
#include "study/raster.h"
#include "study/view3d.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>

#ifndef VESSELMESH_VERSION
#define VESSELMESH_VERSION "0.0.0"
#endif
#ifndef VESSELMESH_DEPENDENCIES
#define VESSELMESH_DEPENDENCIES "unknown"
#endif

namespace vesselmesh::study {
namespace {

namespace fs = std::filesystem;
using namespace report;

// The ring's mean WSS magnitude over its arc length (trapezoids between samples).
double ring_mean(const post::Ring& ring) {
  double sum = 0.0, length = 0.0;
  for (size_t k = 1; k < ring.samples.size(); ++k) {
    const double ds = ring.samples[k].arc_length - ring.samples[k - 1].arc_length;
    sum += 0.5 * ds * (ring.samples[k].magnitude + ring.samples[k - 1].magnitude);
    length += ds;
  }
  return length > 0.0 ? sum / length : ring.samples.empty() ? 0.0 : ring.samples.front().magnitude;
}

// The three finest meshes of the reference's family, finest first; empty when there are fewer: the
// envelope series, or the uniform family (the series and the compared uniform mesh when its
// interior was made as the series' were).
std::vector<const MeshRun*> convergence_grids(const StudyConfig& config, const std::vector<MeshRun>& meshes) {
  std::vector<const MeshRun*> family;
  for (const MeshRun& m : meshes)
    if (m.series || (config.reference == ReferenceKind::uniform && m.name == "uniform" &&
                     m.interior_size == config.interior.factor))
      family.push_back(&m);
  std::sort(family.begin(), family.end(),
            [](const MeshRun* a, const MeshRun* b) { return a->volume_points > b->volume_points; });
  if (family.size() < 3 || family[0]->volume_points <= family[1]->volume_points ||
      family[1]->volume_points <= family[2]->volume_points)
    return {};
  family.resize(3);
  return family;
}

// A difference d (of the quantity's unit) against the reference's uncertainty: "larger" than its
// GCI band, "within" it; without an order, "within" the series' spread (the uncertainty is at
// least that), else "unknown".
std::string against_band(double d, const GridConvergence& g) {
  if (g.found) return std::abs(d) > g.band() ? "larger" : "within";
  if (std::isfinite(g.spread) && std::abs(d) <= g.spread * std::abs(g.phi1)) return "within (the series' spread)";
  return "unknown";
}

// The reference's uncertainty in a table cell: the GCI, or the series' spread as a lower bound.
std::string uncertainty(const GridConvergence& g) {
  if (g.found) return fmt::format("{:.2f} %", 100 * g.gci_fine);
  if (std::isfinite(g.spread) && g.spread > 0.0) return fmt::format(">= {:.2f} % (spread)", 100 * g.spread);
  return "n/a";
}

// A least dihedral angle in a table cell ("-": no such cells, or not measured).
// The envelope series' scales, level by level ("1.1, 1.46 and 1.95 (levels 1 to 3)").
std::string envelope_scales(const StudyConfig& config) {
  std::vector<std::string> scales;
  for (int k = 1; k <= config.levels; ++k)
    scales.push_back(fmt::format("{:.3g}", envelope_level_scale(config.factor, k, config.levels)));
  if (scales.size() == 1) return scales[0] + " (its one level)";
  const std::string last = scales.back();
  scales.pop_back();
  return fmt::format("{} and {} (levels 1 to {})", fmt::join(scales, ", "), last, config.levels);
}

std::string angle(double degrees) { return degrees >= 0.0 ? number(degrees, 3) : "-"; }

// Issue 27's bounds on the meshes the study compares and refers to: 5 degrees in the boundary
// layer, 10 inside. A layer's tetrahedra are flat by design (their least dihedral angle about atan
// of the height over the wall edge, whatever the cut: 0.070 and 0.046 median height/edge under 5
// degrees on the demo's uniform and anisotropic volumes), so the layer's bound is judged in the
// layer's own frame (volume::VolumeQuality::min_dihedral_layer_frame: each cell mapped onto the
// unit prism of its column), where a small angle is what the layer made (a bad cut, a bent or
// pinched column); inside, a small angle is a sliver. A mesh without the frame's figure (a stamp
// from before) is judged on its raw one.
constexpr double kLayerDihedralBound = 5.0, kInteriorDihedralBound = 10.0;

// Table 1's sentence on those bounds: met by every mesh, or the meshes and parts that miss them.
std::string dihedral_verdict(const std::vector<MeshRun>& meshes) {
  std::vector<std::string> below;
  double flattest = 180.0;
  for (const MeshRun& m : meshes) {
    const double layer = m.min_dihedral_layer_frame >= 0.0 ? m.min_dihedral_layer_frame : m.min_dihedral_layer;
    if (layer >= 0.0 && layer < kLayerDihedralBound)
      below.push_back(fmt::format("{}'s layer ({:.2f} deg{})", m.name, layer,
                                  m.min_dihedral_layer_frame >= 0.0 ? " in its frame" : ""));
    if (m.min_dihedral_interior >= 0.0 && m.min_dihedral_interior < kInteriorDihedralBound)
      below.push_back(fmt::format("{}'s interior ({:.2f} deg)", m.name, m.min_dihedral_interior));
    if (m.min_dihedral_layer >= 0.0) flattest = std::min(flattest, m.min_dihedral_layer);
  }
  const std::string bounds = fmt::format(
      "at least {:g} degrees in the boundary layer, its cells measured in the layer's own frame (each cell mapped "
      "by the affine map that takes its column's wall triangle to the equilateral triangle and its height to "
      "that triangle's side, where a straight column cut well has 40.9 degrees), and {:g} inside",
      kLayerDihedralBound, kInteriorDihedralBound);
  const std::string flat =
      flattest < 180.0
          ? fmt::format(" The layer's raw least angles (down to {:.2f} deg) are those of cells flat by design: about "
                        "the arctangent of their height over their wall edge, whatever the cut; in the layer's frame "
                        "a small angle would be a cut gone wrong or a column bent or pinched.",
                        flattest)
          : std::string();
  if (below.empty())
    return fmt::format("The least dihedral angles meet the bounds asked of the meshes: {}.{}", bounds, flat);
  return fmt::format("Below the bounds asked of the meshes ({}): {}.{} Inside, an angle under the bound is a sliver "
                     "('vesselmesh quality' measures a volume mesh's layer and interior apart).",
                     bounds, fmt::format("{}", fmt::join(below, ", ")), flat);
}

// The interactive 3D view of the pictured walls (the compared meshes, the reference last; issue 53):
// HTML only, the Markdown says where it is. Without three.js on the machine, both say so.
void view_section(Document& doc, const StudyConfig& config, const std::vector<const MeshRun*>& pictured,
                  const std::vector<post::WallField>& walls, double high, const Vec3& view, const std::string& unit,
                  const Reporter& reporter) {
  doc.heading("Interactive 3D view");
  const std::optional<ThreeScripts> scripts = read_three_scripts();
  if (!scripts) {
    doc.paragraph("No interactive 3D view: three.js was not found when the report was written (apt-get install "
                  "libjs-three, or set VESSELMESH_THREE_DIR to a folder with three.min.js and "
                  "examples/js/controls/OrbitControls.js).");
    reporter.warning("study: no interactive 3D view in report.html (three.js not found: apt-get install libjs-three)");
    return;
  }
  ViewScene scene;
  scene.view = view;
  scene.unit = unit;
  scene.high = high > 0.0 ? high : 1.0;
  scene.reference = pictured.size() - 1;
  std::vector<std::vector<double>> magnitude(pictured.size());
  for (size_t k = 0; k < pictured.size(); ++k)
    for (const Vec3& t : walls[k].wss) magnitude[k].push_back(t.norm());
  for (size_t k = 0; k < pictured.size(); ++k) {
    scene.walls.push_back(viewed_wall(pictured[k]->name, walls[k].mesh, magnitude[k]));
    for (const post::Ring& ring : pictured[k]->rings) {
      std::vector<Vec3> line;
      for (const post::RingSample& sample : ring.samples) line.push_back(sample.point);
      if (ring.closed && !line.empty()) line.push_back(line.front());
      scene.walls.back().rings.push_back(line);
    }
  }
  std::vector<double> spread;  // |differences| of every compared wall, for the colour range
  for (size_t k = 0; k + 1 < pictured.size(); ++k) {
    scene.walls[k].difference = difference_on(scene.walls.back(), walls[k].mesh, magnitude[k]);
    for (double d : scene.walls[k].difference) spread.push_back(std::abs(d));
  }
  if (!spread.empty()) {
    const size_t at = static_cast<size_t>(0.95 * static_cast<double>(spread.size() - 1));
    std::nth_element(spread.begin(), spread.begin() + static_cast<long>(at), spread.end());
    scene.difference_range = spread[at];
  }
  if (!(scene.difference_range > 0.0)) scene.difference_range = 0.25 * scene.high;
  for (const post::PointSpec& p : config.points) scene.points.emplace_back(p.name, p.point);
  const std::string block = view3d_html(scene, *scripts);
  const std::string about = fmt::format(
      "Every wall in 3D, coloured by |WSS| on one scale (0 to the reference's 99th percentile, {:.3g} Pa), the rings "
      "as black lines and the points as magenta dots: drag to turn, scroll to zoom, right-drag to pan; the views turn "
      "together. The toggle shows each compared mesh's |WSS| minus the reference's, on the reference's wall (colours "
      "from -{:.3g} to +{:.3g} Pa, the 95th percentile of the differences). Walls over {} triangles are made coarser "
      "for display only. Open report.html?view3d to see the views alone. This view adds {:.1f} MB to report.html "
      "(three.js {:.1f} MB of it).",
      scene.high, scene.difference_range, scene.difference_range, kViewTriangles, block.size() / 1e6,
      (scripts->three.size() + scripts->controls.size()) / 1e6);
  doc.markdown += "In report.html: an interactive 3D view of every wall. " + about + "\n\n";
  doc.html += "<p>" + xml_escape(about) + "</p>\n" + block;
}

// Table 1: each mesh's counts, layers and least angles, and the verdict on the angles.
void meshes_table(Document& doc, const std::vector<MeshRun>& meshes) {
  doc.heading("Table 1: the meshes");
  std::vector<std::vector<std::string>> rows;
  for (const MeshRun& m : meshes)
    rows.push_back({m.name, m.series ? "refinement series" : "compared", fmt::format("{:.0f}", m.target_triangles),
                    fmt::format("{} ({:+.1f} %)", m.surface_triangles,
                                100.0 * (m.surface_triangles / m.target_triangles - 1.0)),
                    std::to_string(m.surface_points),
                    std::to_string(m.volume_points), number(m.interior_size, 3),
                    m.layer_growth == 1.0 ? std::to_string(m.layers)
                                          : fmt::format("{} (growth {:.3f})", m.layers, m.layer_growth),
                    std::to_string(m.tetrahedra), std::to_string(m.dofs), angle(m.min_dihedral_layer),
                    angle(m.min_dihedral_layer_frame), angle(m.min_dihedral_interior)});
  doc.table({"mesh", "role", "target triangles", "surface triangles", "surface nodes", "volume nodes",
             "interior size factor", "layers", "tetrahedra (prisms as 3)", "flow unknowns",
             "least dihedral, layer (deg)", "least dihedral, layer in its frame (deg)",
             "least dihedral, interior (deg)"},
            rows);
  doc.paragraph(dihedral_verdict(meshes));
}

// Fig. 11: WSS along each ring, the refinement series and the compared meshes against the reference.
void ring_charts(Document& doc, const StudyConfig& config, const StudyResult& result) {
  const std::vector<MeshRun>& meshes = result.meshes;
  const std::string& unit = result.length_unit;
  for (size_t r = 0; r < result.rings.size(); ++r) {
    const std::string& ring = result.rings[r].name;
    doc.heading(fmt::format("WSS along ring {}", ring));
    for (const bool series : {true, false}) {
      LineChart chart;
      chart.title = fmt::format("Ring {}: {} (t = {:g} s)", ring, series ? "refinement series" : "compared meshes",
                                result.time);
      chart.x_label = fmt::format("arc length ({}) from angle 0", unit);
      chart.y_label = "wall shear stress magnitude (Pa)";
      chart.y_from_zero = true;
      for (size_t m = 0; m < meshes.size(); ++m) {
        if (meshes[m].series != series && static_cast<int>(m) != result.reference) continue;
        Series s{meshes[m].name, {}, {}, static_cast<int>(m) == result.reference && !series};
        for (const post::RingSample& sample : meshes[m].rings[r].samples) {
          s.x.push_back(sample.arc_length);
          s.y.push_back(sample.magnitude);
        }
        chart.series.push_back(s);
      }
      doc.figure(fmt::format("ring_{}_{}", ring, series ? "series" : "meshes"), svg(chart),
                 fmt::format("WSS magnitude along ring {}, {}", ring,
                             series ? (config.reference == ReferenceKind::envelope ? "the envelope refinement series"
                                                                                   : "the uniform refinement series")
                                    : "the compared meshes against the reference"));
    }
  }

}

// A bar chart of differences from the reference, a category per other mesh (Figs. 12-14).
BarChart difference_chart(const StudyResult& result, const std::string& title) {
  BarChart chart;
  chart.title = title;
  chart.y_label = "difference from the reference (%)";
  for (size_t m = 0; m < result.meshes.size(); ++m)
    if (static_cast<int>(m) != result.reference) chart.categories.push_back(result.meshes[m].name);
  return chart;
}

// The reference's grid convergence: per ring its minimum's and mean's, per point its value's, and
// the rows study.json keeps (empty when the series has no three levels).
struct Convergence {
  std::vector<GridConvergence> ring_min, ring_mean, point;
  Json json = Json::array();
  bool known() const { return !json.empty(); }
};

// Pointwise along each ring: the three levels' profiles on a common angle (or length fraction),
// the reference's GCI band and the extrapolated profile where the series converges.
void ring_profiles(Document& doc, const StudyResult& result, const std::vector<const MeshRun*>& grids, Json& convergence) {
  constexpr int kProfile = 360;
  std::vector<std::vector<std::string>> profile_rows;
  for (size_t r = 0; r < result.rings.size(); ++r) {
    std::array<std::vector<double>, 3> profile;
    bool closed = true;
    for (int k = 0; k < 3; ++k) {
      profile[k] = post::resampled_magnitude(grids[k]->rings[r], kProfile);
      closed = closed && grids[k]->rings[r].closed;
    }
    if (!closed)  // one open: all by length fraction
      for (int k = 0; k < 3; ++k) {
        post::Ring open = grids[k]->rings[r];
        open.closed = false;
        profile[k] = post::resampled_magnitude(open, kProfile);
      }
    LineChart chart;
    chart.title = fmt::format("Ring {}: the reference and its uncertainty (t = {:g} s)", result.rings[r].name,
                              result.time);
    chart.x_label = closed ? "angle (deg)" : "fraction of the ring's length";
    chart.y_label = "wall shear stress magnitude (Pa)";
    chart.y_from_zero = true;
    Series ref{grids[0]->name + " (reference)", {}, {}, false}, low{"- GCI", {}, {}, true},
        high{"+ GCI", {}, {}, true}, ext{"extrapolated", {}, {}, true};
    std::vector<double> gcis;
    int found = 0;
    for (int i = 0; i < kProfile; ++i) {
      const double x = closed ? 360.0 * i / kProfile : static_cast<double>(i) / kProfile;
      const GridConvergence g = grid_convergence(grids[0]->volume_points, grids[1]->volume_points,
                                                 grids[2]->volume_points, profile[0][i], profile[1][i],
                                                 profile[2][i]);
      for (Series* sr : {&ref, &low, &high, &ext}) sr->x.push_back(x);
      ref.y.push_back(profile[0][i]);
      low.y.push_back(g.found ? profile[0][i] - g.band() : NAN);
      high.y.push_back(g.found ? profile[0][i] + g.band() : NAN);
      ext.y.push_back(g.found ? g.extrapolated : NAN);
      if (g.found) {
        ++found;
        gcis.push_back(100 * g.gci_fine);
      }
    }
    chart.series = {ref, low, high, ext};
    doc.figure(fmt::format("ring_{}_uncertainty", result.rings[r].name), svg(chart),
               fmt::format("WSS along ring {} on the reference with its GCI band and the extrapolated profile, where "
                           "the series converges (gaps where it does not)",
                           result.rings[r].name));
    std::sort(gcis.begin(), gcis.end());
    const auto quantile = [&](double q) {
      return gcis.empty() ? NAN : gcis[static_cast<size_t>(q * static_cast<double>(gcis.size() - 1))];
    };
    profile_rows.push_back({result.rings[r].name, fmt::format("{:.0f} %", 100.0 * found / kProfile),
                            number(quantile(0.5), 3) + " %", number(quantile(0.9), 3) + " %"});
    convergence.push_back({{"quantity", fmt::format("ring {}: profile", result.rings[r].name)},
                           {"positions", kProfile},
                           {"converging_share", static_cast<double>(found) / kProfile},
                           {"gci_fine_percent_median", std::isfinite(quantile(0.5)) ? Json(quantile(0.5)) : Json(nullptr)},
                           {"gci_fine_percent_90th", std::isfinite(quantile(0.9)) ? Json(quantile(0.9)) : Json(nullptr)}});
  }
  if (!profile_rows.empty())
    doc.table({"ring profile", "positions where the series converges", "GCI_fine, median there",
               "GCI_fine, 90th percentile there"},
              profile_rows);
}

// The reference's own uncertainty: Richardson extrapolation and the GCI over the series' three finest
// meshes (Celik et al. 2008), for each ring's minimum and mean and each point.
Convergence convergence_section(Document& doc, const StudyConfig& config, const StudyResult& result,
                                const std::vector<const MeshRun*>& grids) {
  const MeshRun& reference = result.meshes[result.reference];
  std::vector<GridConvergence> ring_min_gci(result.rings.size()), ring_mean_gci(result.rings.size()),
      point_gci(config.points.size());
  Json convergence = Json::array();
  if (grids.size() == 3 && grids[0] == &reference) {
    doc.heading("The reference's uncertainty (grid convergence)");
    doc.paragraph(fmt::format(
        "Richardson extrapolation and Roache's Grid Convergence Index over the three finest meshes of the reference's "
        "series ({}, {} and {}: {}, {} and {} volume nodes), as in Celik et al., J. Fluids Eng. 130 (2008) 078001: the observed order p, "
        "the extrapolated value, and GCI_fine, the reference's relative uncertainty (a factor of safety of 1.25); the "
        "asymptotic ratio GCI32 / (r21^p GCI21) is near 1 when the series is in its asymptotic range.",
        grids[0]->name, grids[1]->name, grids[2]->name, grids[0]->volume_points, grids[1]->volume_points,
        grids[2]->volume_points));
    std::vector<std::vector<std::string>> gci_rows;
    const auto add = [&](const std::string& what, const std::array<double, 3>& phi) {
      const GridConvergence g = grid_convergence(grids[0]->volume_points, grids[1]->volume_points,
                                                 grids[2]->volume_points, phi[0], phi[1], phi[2]);
      gci_rows.push_back({what, number(phi[2]), number(phi[1]), number(phi[0]), number(g.order, 3),
                          number(g.extrapolated), uncertainty(g), number(g.asymptotic_ratio, 3), g.status});
      convergence.push_back({{"quantity", what},
                             {"meshes", {grids[0]->name, grids[1]->name, grids[2]->name}},
                             {"volume_points", {grids[0]->volume_points, grids[1]->volume_points, grids[2]->volume_points}},
                             {"values_Pa", {phi[0], phi[1], phi[2]}},
                             {"order", g.found ? Json(g.order) : Json(nullptr)},
                             {"extrapolated_Pa", g.found ? Json(g.extrapolated) : Json(nullptr)},
                             {"gci_fine_percent", g.found ? Json(100 * g.gci_fine) : Json(nullptr)},
                             {"asymptotic_ratio", g.found ? Json(g.asymptotic_ratio) : Json(nullptr)},
                             {"spread_percent", std::isfinite(g.spread) ? Json(100 * g.spread) : Json(nullptr)},
                             {"status", g.status}});
      return g;
    };
    for (size_t r = 0; r < result.rings.size(); ++r) {
      std::array<double, 3> least{}, mean{};
      for (int k = 0; k < 3; ++k) {
        const post::Ring& ring = grids[k]->rings[r];
        least[k] = ring.samples[ring.minimum].magnitude;
        mean[k] = ring_mean(ring);
      }
      ring_min_gci[r] = add(fmt::format("ring {}: minimum", result.rings[r].name), least);
      ring_mean_gci[r] = add(fmt::format("ring {}: mean", result.rings[r].name), mean);
    }
    for (size_t p = 0; p < config.points.size(); ++p) {
      std::array<double, 3> value{};
      for (int k = 0; k < 3; ++k) value[k] = grids[k]->points[p].value.norm();
      point_gci[p] = add(fmt::format("point {}", config.points[p].name), value);
    }
    doc.table({"quantity (Pa)", grids[2]->name, grids[1]->name, grids[0]->name + " (reference)", "order p",
               "extrapolated", "GCI_fine (or the series' spread)", "asymptotic ratio", "convergence"},
              gci_rows);

    ring_profiles(doc, result, grids, convergence);
  } else {
    doc.heading("The reference's uncertainty (grid convergence)");
    doc.paragraph(config.reference == ReferenceKind::uniform
                      ? "Not estimated: it needs three uniform meshes, the finest being the reference (the compared "
                        "uniform mesh and [reference] levels >= 2, or levels >= 3). Without it, a difference from the "
                        "reference cannot be told from the reference's own error."
                      : "Not estimated: it needs three levels of the envelope series ([reference] levels >= 3). "
                        "Without it, a difference from the reference cannot be told from the reference's own error.");
  }
  return {ring_min_gci, ring_mean_gci, point_gci, convergence};
}

// Each ring's minimum WSS against the reference's, per mesh: a row each in `numbers`, a ranked
// quantity each in `ranked`.
void ring_minimum_section(Document& doc, const StudyResult& result, const Convergence& gci, Json& numbers,
                          std::vector<Ranked>& ranked) {
  const std::vector<MeshRun>& meshes = result.meshes;
  const MeshRun& reference = meshes[result.reference];
  const std::string& unit = result.length_unit;
  const bool have_gci = gci.known();
  if (!result.rings.empty()) {
    doc.heading("Minimum WSS on each ring against the reference");
    BarChart chart = difference_chart(result, "Relative difference of the minimum WSS on each ring");
    std::vector<std::vector<std::string>> table;
    std::vector<std::string> beyond, within, unknown, unresolved;
    for (size_t r = 0; r < result.rings.size(); ++r) {
      const post::Ring& ref_ring = reference.rings[r];
      const double ref_min = ref_ring.samples[ref_ring.minimum].magnitude, ref_mean = ring_mean(ref_ring);
      const GridConvergence& g = gci.ring_min[r];
      BarSeries s{"ring " + result.rings[r].name, {}};
      // The reference's uncertainty over its ring's mean, as the differences the summary ranks by.
      Ranked rank{fmt::format("ring {}: minimum", result.rings[r].name), {}, NAN, "not estimated", {}, false};
      if (have_gci && ref_mean > 0.0 && g.found) {
        rank.band = 100.0 * g.band() / ref_mean;
        rank.uncertainty = fmt::format("{:.2f} %", rank.band);
      } else if (have_gci && ref_mean > 0.0 && std::isfinite(g.spread) && g.spread > 0.0) {
        rank.uncertainty = fmt::format(">= {:.2f} % (spread)", 100.0 * g.spread * std::abs(g.phi1) / ref_mean);
      }
      const TemporalError temporal = temporal_error(result, [r](const MeshRun& run) {
        return run.rings[r].samples[run.rings[r].minimum].magnitude;
      });
      const double time_error = temporal.total();  // Pa
      if (ref_mean > 0.0) temporal.rank_into(rank, ref_mean);
      for (const MeshRun& m : meshes) {
        if (&m == &reference) continue;
        const post::RingSample& least = m.rings[r].samples[m.rings[r].minimum];
        const double d = relative_difference(least.magnitude, ref_min);
        const double d_mean = ref_mean > 0.0 ? 100.0 * (least.magnitude - ref_min) / ref_mean : NAN;
        const double d_ext = have_gci && g.found ? relative_difference(least.magnitude, g.extrapolated) : NAN;
        double turn = std::fmod(least.angle - ref_ring.samples[ref_ring.minimum].angle + 540.0, 360.0) - 180.0;
        const double shift = ref_ring.closed ? turn / 360.0 * ref_ring.length
                                             : least.arc_length - ref_ring.samples[ref_ring.minimum].arc_length;
        const double finer = outresolution(m, reference, r);
        const std::string verdict = resolved_verdict(
            timed_verdict(have_gci ? against_band(least.magnitude - ref_min, g) : "unknown", least.magnitude - ref_min,
                          time_error),
            finer);
        if (!m.series) {
          (verdict == "larger"                ? beyond
           : verdict.starts_with("cannot") ? unresolved
           : verdict == "unknown"             ? unknown
                                              : within)
              .push_back(fmt::format("{} on {}", m.name, result.rings[r].name));
          rank.differences.emplace_back(m.name, d_mean);
          rank.outresolved[m.name] = finer;
        }
        s.values.push_back(d);
        table.push_back({result.rings[r].name, m.name, number(least.magnitude), number(ref_min), number(least.angle, 4),
                         number(shift, 3), percent(d), percent(d_mean), percent(d_ext),
                         have_gci ? uncertainty(g) : "n/a", verdict});
        numbers.push_back({{"what", "ring minimum"}, {"ring", result.rings[r].name}, {"mesh", m.name},
                           {"wss_Pa", least.magnitude}, {"reference_Pa", ref_min}, {"angle_deg", least.angle},
                           {"position_error", shift},
                           {"relative_difference_percent", d},
                           {"difference_of_ring_mean_percent", std::isfinite(d_mean) ? Json(d_mean) : Json(nullptr)},
                           {"relative_to_extrapolated_percent", std::isfinite(d_ext) ? Json(d_ext) : Json(nullptr)},
                           {"reference_uncertainty", verdict}});
      }
      chart.series.push_back(s);
      ranked.push_back(rank);
    }
    doc.figure("ring_minimum_differences", svg(chart),
               "Relative difference of each ring's minimum WSS from the reference's, per mesh");
    doc.table({"ring", "mesh", "minimum WSS (Pa)", "reference (Pa)", "at angle (deg)",
               fmt::format("position error ({})", unit), "difference", "of the ring's mean", "against extrapolated",
               "reference GCI", "beyond the reference's uncertainty"},
              table);
    const auto listed = [](const std::vector<std::string>& v) {
      return v.empty() ? std::string("none") : fmt::format("{} ({})", v.size(), fmt::join(v, ", "));
    };
    if (have_gci)
      doc.paragraph(fmt::format(
          "The compared meshes' ring minima that differ from the reference by more than the reference's own "
          "uncertainty (its GCI band): {}. Within it, so that the reference cannot tell them from itself: {}. Not known "
          "(no order of convergence, and the difference larger than the series' own spread): {}. Not told, the "
          "reference there less than {:.1f} times as fine as the mesh: {}. The position error "
          "is the arc length from the reference's minimum to the mesh's; \"of the ring's mean\" is the difference over "
          "the reference ring's mean WSS, which stays meaningful where the minimum is near zero.",
          listed(beyond), listed(within), listed(unknown), kOutResolves, listed(unresolved)));
  }
}

// The WSS at each point against the reference's, per mesh.
void point_section(Document& doc, const StudyConfig& config, const StudyResult& result, const Convergence& gci,
                   Json& numbers, std::vector<Ranked>& ranked) {
  const std::vector<MeshRun>& meshes = result.meshes;
  const MeshRun& reference = meshes[result.reference];
  const bool have_gci = gci.known();
  if (!config.points.empty()) {
    doc.heading("WSS at the points against the reference");
    BarChart chart = difference_chart(result, "Relative difference of the WSS at each point");
    std::vector<std::vector<std::string>> table;
    for (size_t p = 0; p < config.points.size(); ++p) {
      const double ref = reference.points[p].value.norm();
      const GridConvergence& g = gci.point[p];
      BarSeries s{"point " + config.points[p].name, {}};
      Ranked rank{"point " + config.points[p].name, {}, have_gci && g.found ? 100.0 * g.gci_fine : NAN,
                  have_gci ? uncertainty(g) : "not estimated", {}, false};
      const TemporalError temporal =
          temporal_error(result, [p](const MeshRun& run) { return run.points[p].value.norm(); });
      const double time_error = temporal.total();  // Pa
      if (ref > 0.0) temporal.rank_into(rank, ref);
      for (const MeshRun& m : meshes) {
        if (&m == &reference) continue;
        const double v = m.points[p].value.norm(), d = relative_difference(v, ref);
        const double d_ext = have_gci && g.found ? relative_difference(v, g.extrapolated) : NAN;
        const double finer = outresolution(m, reference, result.rings.size() + p);
        const std::string verdict =
            resolved_verdict(timed_verdict(have_gci ? against_band(v - ref, g) : "unknown", v - ref, time_error), finer);
        s.values.push_back(d);
        if (!m.series) {
          rank.differences.emplace_back(m.name, d);
          rank.outresolved[m.name] = finer;
        }
        table.push_back({config.points[p].name, m.name, number(v), number(ref), percent(d), percent(d_ext),
                         have_gci ? uncertainty(g) : "n/a", verdict});
        numbers.push_back({{"what", "point"}, {"point", config.points[p].name}, {"mesh", m.name}, {"wss_Pa", v},
                           {"reference_Pa", ref}, {"relative_difference_percent", d},
                           {"relative_to_extrapolated_percent", std::isfinite(d_ext) ? Json(d_ext) : Json(nullptr)},
                           {"reference_uncertainty", verdict}});
      }
      chart.series.push_back(s);
      ranked.push_back(rank);
    }
    doc.figure("point_differences", svg(chart), "Relative difference of the WSS at each point, per mesh");
    doc.table({"point", "mesh", "WSS (Pa)", "reference (Pa)", "difference", "against extrapolated", "reference GCI",
               "beyond the reference's uncertainty"},
              table);
  }
}

// The summary, read first, put in `doc` at (markdown_at, html_at): the compared meshes ranked per
// quantity (closest to the reference first), with the reference's uncertainty, then their mean place
// and their cost.
Json summary_section(Document& doc, size_t markdown_at, size_t html_at, const StudyResult& result,
                     std::vector<Ranked>& ranked) {
  const std::vector<MeshRun>& meshes = result.meshes;
  const MeshRun& reference = meshes[result.reference];
  // The summary, read first: the compared meshes ranked per quantity (closest to the reference
  // first), with the reference's uncertainty, then their mean place and their cost.
  Json summary;
  {
    Document top;
    top.folder = doc.folder;
    top.heading("Summary");
    Json rankings = Json::array();
    std::map<std::string, std::vector<int>> places;  // per compared mesh, its place per quantity
    std::map<std::string, std::vector<int>> wall_places;  // the same over the whole-wall measures
    std::vector<std::vector<std::string>> ranking_rows;
    int known = 0;
    const auto key = [](double d) { return std::isfinite(d) ? std::abs(d) : INFINITY; };
    for (Ranked& q : ranked) {
      std::stable_sort(q.differences.begin(), q.differences.end(),
                       [&](const auto& a, const auto& b) { return key(a.second) < key(b.second); });
      std::vector<std::string> order, beyond, untold;
      Json list = Json::array();
      for (size_t k = 0; k < q.differences.size(); ++k) {
        const auto& [name, d] = q.differences[k];
        places[name].push_back(static_cast<int>(k) + 1);
        if (q.whole_wall) wall_places[name].push_back(static_cast<int>(k) + 1);
        order.push_back(fmt::format("{} ({})", name, percent(d)));
        const double finer = q.outresolved.count(name) ? q.outresolved.at(name) : NAN;
        if (std::isfinite(finer) && finer < kOutResolves)
          untold.push_back(fmt::format("{} (reference {})", name, times(finer)));
        else if (std::isfinite(q.band) && !(std::abs(d) <= q.band) && !(std::abs(d) <= q.temporal_band()))
          beyond.push_back(name);
        list.push_back({{"mesh", name}, {"difference_percent", std::isfinite(d) ? Json(d) : Json(nullptr)},
                        {"place", k + 1}});
      }
      known += std::isfinite(q.band) ? 1 : 0;
      ranking_rows.push_back({q.quantity, fmt::format("{}", fmt::join(order, ", ")), q.uncertainty,
                              !std::isfinite(q.band) ? "not known"
                              : beyond.empty()       ? "none"
                                                     : fmt::format("{}", fmt::join(beyond, ", ")),
                              untold.empty() ? "none" : fmt::format("{}", fmt::join(untold, ", "))});
      rankings.push_back({{"quantity", q.quantity},
                          {"order", list},
                          {"reference_uncertainty_percent", std::isfinite(q.band) ? Json(q.band) : Json(nullptr)},
                          {"beyond_uncertainty", beyond},
                          {"time_step_error_percent", std::isfinite(q.time_band) ? Json(q.time_band) : Json(nullptr)},
                          {"start_up_error_percent", std::isfinite(q.start_band) ? Json(q.start_band) : Json(nullptr)},
                          {"not_out_resolved", untold}});
    }
    top.paragraph(
        "The compared meshes ranked by their difference from the reference, closest first, per quantity: at each "
        "ring's minimum the difference over the reference ring's mean WSS (meaningful where the minimum is near "
        "zero), at each point the relative difference. Beside it the reference's own uncertainty in the same "
        "measure (its GCI band, from the grid convergence below) and the meshes whose difference exceeds it: a "
        "difference within it cannot be told from the reference's own error, and neither can the order of two "
        "meshes whose differences are closer than it.");
    top.table({"quantity", "closest to the reference first (difference)", "reference's uncertainty",
               "meshes beyond it", fmt::format("not told (reference under {:.1f}x as fine there)", kOutResolves)},
              ranking_rows);
    const std::vector<std::string> unsettled = unsettled_quantities(ranked);
    if (!unsettled.empty())
      top.paragraph(fmt::format(
          "What is left of the flows' start (the start-up's share) exceeds the reference's spatial uncertainty at "
          "{}: over the span these cover the flows are not yet periodic, so that their differences partly measure "
          "the start. Run the case longer (its [time] end one or more periods later) for them.",
          fmt::join(unsettled, ", ")));
    std::vector<std::vector<std::string>> cost;
    std::vector<std::pair<double, std::string>> overall, on_wall;
    Json means = Json::array();
    const auto mean_of_places = [](const std::vector<int>& p) {
      return p.empty() ? NAN
                       : static_cast<double>(std::accumulate(p.begin(), p.end(), 0)) / static_cast<double>(p.size());
    };
    for (const MeshRun& m : meshes) {
      if (m.series || &m == &reference) continue;
      const std::vector<int>& p = places[m.name];
      const double mean = mean_of_places(p), wall_mean = mean_of_places(wall_places[m.name]);
      const long first = std::count(p.begin(), p.end(), 1);
      const double flow = m.seconds.count("flow") ? m.seconds.at("flow") : NAN;
      // The flow kind's cost counts the flows it adapts to (on another compared mesh, and on each cycle before).
      double before = m.adapted_from.empty() ? NAN : 0.0;
      std::vector<std::string> sources;
      for (std::string name = m.adapted_from; !name.empty() && std::isfinite(before);) {
        const auto source =
            std::find_if(meshes.begin(), meshes.end(), [&](const MeshRun& x) { return x.name == name; });
        before = source != meshes.end() && source->seconds.count("flow") ? before + source->seconds.at("flow") : NAN;
        sources.push_back(name + "'s");
        name = source != meshes.end() ? source->adapted_from : std::string();
      }
      cost.push_back({m.name, number(mean, 3), number(wall_mean, 3), std::to_string(first), std::to_string(m.dofs),
                      std::isfinite(before) ? fmt::format("{} + {} ({} flow{}, adapted to)", number(flow, 3),
                                                          number(before, 3), fmt::join(sources, " and "),
                                                          sources.size() > 1 ? "s" : "")
                                            : number(flow, 3)});
      means.push_back({{"mesh", m.name}, {"mean_place", std::isfinite(mean) ? Json(mean) : Json(nullptr)},
                       {"mean_place_whole_wall", std::isfinite(wall_mean) ? Json(wall_mean) : Json(nullptr)},
                       {"first_places", first}, {"dofs", m.dofs},
                       {"flow_seconds", std::isfinite(flow) ? Json(flow) : Json(nullptr)},
                       {"adapted_from", m.adapted_from.empty() ? Json(nullptr) : Json(m.adapted_from)},
                       {"adapted_from_flow_seconds", std::isfinite(before) ? Json(before) : Json(nullptr)}});
      if (std::isfinite(mean)) overall.emplace_back(mean, m.name);
      if (std::isfinite(wall_mean)) on_wall.emplace_back(wall_mean, m.name);
    }
    const auto best = [](std::vector<std::pair<double, std::string>>& v) {
      std::stable_sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      std::vector<std::string> names;  // the best mean place, ties together
      for (const auto& [mean, name] : v)
        if (mean == v.front().first) names.push_back(name);
      return names;
    };
    top.table({"mesh", "mean place (1: closest)", "mean place on the whole-wall measures", "first places",
               "flow unknowns", "flow wall time (s)"},
              cost);
    const std::vector<std::string> closest = best(overall), closest_on_wall = best(on_wall);
    if (!overall.empty())
      top.paragraph(fmt::format(
          "Closest on average: {} (mean place {:.2f} over {} quantities). The reference's uncertainty is known for {} "
          "of the {} quantities{}",
          fmt::join(closest, " and "), overall.front().first, ranked.size(), known, ranked.size(),
          known == 0 ? ": without it these differences cannot be told from the reference's own error (see the grid "
                       "convergence section)."
                     : "."));
    if (!on_wall.empty())
      top.paragraph(fmt::format("Closest on the whole-wall measures alone: {} (mean place {:.2f}).",
                                fmt::join(closest_on_wall, " and "), on_wall.front().first));
    doc.markdown.insert(markdown_at, top.markdown);
    doc.html.insert(html_at, top.html);
    summary = {{"rankings", rankings}, {"mean_place", means},
               {"closest_on_average", closest}, {"closest_on_whole_wall", closest_on_wall},
               {"start_up_exceeds_spatial_uncertainty", unsettled}};
  }

  return summary;
}

// Pictures: the compared surface meshes, the WSS field on them and on the reference, and the 3D view.
void pictures_section(Document& doc, const StudyConfig& config, const StudyResult& result, const Reporter& reporter) {
  const std::vector<MeshRun>& meshes = result.meshes;
  const MeshRun& reference = meshes[result.reference];
  // Pictures: the compared surface meshes, and the WSS field on them and on the reference.
  doc.heading("The surface meshes");
  const std::optional<Vec3> view;
  std::vector<const MeshRun*> pictured;
  for (const MeshRun& m : meshes)
    if (!m.series) pictured.push_back(&m);
  pictured.push_back(&reference);
  double high = 0.0;
  std::vector<post::WallField> walls;
  for (const MeshRun* m : pictured) {
    walls.push_back(post::wall_at_time(post::read_wall_series(m->folder + "/flow"), result.time));
    std::vector<double> magnitude;
    for (const Vec3& t : walls.back().wss) magnitude.push_back(t.norm());
    if (m == &reference && !magnitude.empty()) {  // the colour range: 0 to the reference's 99th percentile
      std::vector<double> sorted = magnitude;
      const size_t k = static_cast<size_t>(0.99 * static_cast<double>(sorted.size() - 1));
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(k), sorted.end());
      high = sorted[k];
    }
  }
  const Vec3 broadside = broadside_view(walls.back().mesh);
  for (size_t k = 0; k + 1 < pictured.size(); ++k) {
    PictureOptions o;
    o.title = fmt::format("{}: {} triangles", pictured[k]->name, pictured[k]->surface_triangles);
    o.view = broadside;
    doc.figure("mesh_" + pictured[k]->name, surface_svg(walls[k].mesh, nullptr, o),
               fmt::format("The {} surface mesh", pictured[k]->name));
  }
  doc.heading(fmt::format("The WSS field at t = {:g} s", result.time));
  for (size_t k = 0; k < pictured.size(); ++k) {
    std::vector<double> magnitude;
    for (const Vec3& t : walls[k].wss) magnitude.push_back(t.norm());
    PictureOptions o;
    o.title = fmt::format("WSS on {} (t = {:g} s)", pictured[k]->name, result.time);
    o.view = broadside;
    o.edges = false;
    o.scalar_label = "|wss| (Pa)";
    o.low = 0.0;
    o.high = high > 0.0 ? high : 1.0;
    doc.figure("wss_" + pictured[k]->name, surface_svg(walls[k].mesh, &magnitude, o),
               fmt::format("WSS magnitude on the {} mesh (colours 0 to the reference's 99th percentile, {:.3g} Pa)",
                           pictured[k]->name, o.high));
  }

  view_section(doc, config, pictured, walls, high, broadside, result.length_unit, reporter);

}

// The stage times, per mesh and per step of the study.
void timings_section(Document& doc, const StudyResult& result) {
  const std::vector<MeshRun>& meshes = result.meshes;
  doc.heading("Timings");
  std::vector<std::vector<std::string>> timing;
  for (const MeshRun& m : meshes) {
    const auto seconds = [&](const char* k) { return m.seconds.count(k) ? number(m.seconds.at(k), 3) : "-"; };
    timing.push_back({m.name, seconds("remesh"), seconds("volume"), seconds("flow"), m.reused ? "reused" : "computed"});
  }
  for (const std::optional<MeshRun>* check : {&result.half_step, &result.next_period}) {
    if (!*check) continue;
    const MeshRun& h = **check;
    timing.push_back({h.name, "-", "-", h.seconds.count("flow") ? number(h.seconds.at("flow"), 3) : "-",
                      h.reused ? "reused" : "computed"});
  }
  doc.table({"mesh", "surface mesh (s)", "volume mesh (s)", "flow (s)", "this run"}, timing);
  std::vector<std::vector<std::string>> steps;
  for (const auto& [name, s] : result.seconds) steps.push_back({name, number(s, 3)});
  doc.table({"step", "seconds"}, steps);

}

}  // namespace

void write_report(const StudyConfig& config, StudyResult& result, const std::string& folder, const Reporter& reporter) {
  reporter.info("study: report");
  fs::create_directories(folder + "/figures");
  const std::vector<MeshRun>& meshes = result.meshes;
  const MeshRun& reference = meshes[result.reference];
  const std::string& unit = result.length_unit;
  Document doc;
  doc.folder = folder;
  doc.html = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>vesselmesh mesh-impact study</title>\n"
             "<style>body{font-family:sans-serif;max-width:980px;margin:2em auto;padding:0 1em}"
             "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}"
             "figure{margin:1em 0}figcaption{font-style:italic}pre{background:#f4f4f4;padding:.6em}</style>"
             "</head><body>\n";
  doc.heading("Impact of the mesh on wall shear stress", 1);
  doc.paragraph(fmt::format(
      "Vessel: {}. Flow case: {}. WSS read at t = {:g} s. Reference: {} (the finest of the {}). Lengths in {}, "
      "stresses in Pa. vesselmesh {}.",
      config.surface, config.flow_case, result.time, reference.name,
      config.reference == ReferenceKind::envelope
          ? fmt::format("envelope series: level k's wall sizes the least of the compared meshes' achieved sizes at "
                        "each point divided by {}, its first layer height and interior likewise",
                        envelope_scales(config))
          : "uniform refinement series",
      unit, VESSELMESH_VERSION));

  for (const std::string& w : result.warnings) doc.paragraph("Warning: " + w + ".");
  // The summary goes here, made once every difference is known.
  const size_t summary_markdown = doc.markdown.size(), summary_html = doc.html.size();
  std::vector<Ranked> ranked;
  meshes_table(doc, meshes);
  const Json resolution = resolution_section(doc, result);

  ring_charts(doc, config, result);

  const std::vector<const MeshRun*> grids = convergence_grids(config, meshes);
  const Convergence gci = convergence_section(doc, config, result, grids);
  // Figs. 12-14: relative differences against the reference.
  Json numbers = Json::array();
  ring_minimum_section(doc, result, gci, numbers, ranked);
  point_section(doc, config, result, gci, numbers, ranked);
  const Json whole_wall = whole_wall_section(doc, result, grids, ranked);
  const Json time_step = time_step_section(doc, config, result, result.time_step);
  const Json start_up = start_up_section(doc, config, result);

  const Json summary = summary_section(doc, summary_markdown, summary_html, result, ranked);
  pictures_section(doc, config, result, reporter);
  timings_section(doc, result);

  doc.heading("Version and options");
  doc.paragraph(fmt::format("vesselmesh {} (built with {}). The study file {}:", VESSELMESH_VERSION,
                            VESSELMESH_DEPENDENCIES, config.path));
  doc.code(io::read_file(config.path));
  doc.paragraph(fmt::format("The flow case {}:", config.flow_case));
  doc.code(io::read_file(config.flow_case));
  doc.html += "</body></html>\n";

  io::write_text(folder + "/report.md", doc.markdown);
  io::write_text(folder + "/report.html", doc.html);
  result.report_markdown = folder + "/report.md";
  result.report_html = folder + "/report.html";

  Json j;
  j["version"] = VESSELMESH_VERSION;
  j["dependencies"] = VESSELMESH_DEPENDENCIES;
  j["study"] = config.path;
  j["time_s"] = result.time;
  j["units"] = {{"length", unit}, {"wss", "Pa"}, {"time", "s"}};
  j["reference"] = reference.name;
  Json list = Json::array();
  for (const MeshRun& m : meshes) {
    Json rings = Json::array();
    for (const post::Ring& r : m.rings)
      rings.push_back({{"name", r.name}, {"length", r.length}, {"minimum_wss_Pa", r.samples[r.minimum].magnitude},
                       {"minimum_angle_deg", r.samples[r.minimum].angle}});
    list.push_back({{"name", m.name}, {"series", m.series}, {"target_triangles", m.target_triangles},
                    {"surface_triangles", m.surface_triangles},
                    {"least_count", m.least_count > 0 ? Json(m.least_count) : Json(nullptr)},
                    {"surface_points", m.surface_points},
                    {"volume_points", m.volume_points}, {"tetrahedra", m.tetrahedra}, {"dofs", m.dofs},
                    {"min_dihedral_deg", m.min_dihedral},
                    {"min_dihedral_layer_deg", m.min_dihedral_layer >= 0.0 ? Json(m.min_dihedral_layer) : Json()},
                    {"min_dihedral_interior_deg", m.min_dihedral_interior >= 0.0 ? Json(m.min_dihedral_interior) : Json()},
                    {"min_dihedral_layer_frame_deg",
                     m.min_dihedral_layer_frame >= 0.0 ? Json(m.min_dihedral_layer_frame) : Json()},
                    {"interior_size", m.interior_size}, {"seconds", m.seconds}, {"reused", m.reused},
                    {"rings", rings}});
  }
  j["meshes"] = list;
  j["differences"] = numbers;
  j["grid_convergence"] = gci.json;
  j["reference_kind"] = reference_kind_name(config.reference);
  j["whole_wall"] = whole_wall;
  j["time_step"] = time_step;
  j["start_up"] = start_up;
  j["period_s"] = result.period;
  j["resolution"] = resolution;
  j["summary"] = summary;
  j["seconds"] = result.seconds;
  j["warnings"] = result.warnings;
  io::write_text(folder + "/study.json", j.dump(2) + "\n");
}

}  // namespace vesselmesh::study
