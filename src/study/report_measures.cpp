#include "study/report_document.h"

#include "study/envelope.h"
#include "study/resolution.h"
#include "study/wall_difference.h"

#include <algorithm>
#include <array>

namespace vesselmesh::study::report {

// How many times finer the reference is than mesh m at place k: the ratio of their mean sizes over
// the place's positions (a single position's few cells scatter by 20-30 % with the triangles' shapes
// and each mesh's own local radius), the least of the three measures (surface, first layer,
// interior); NaN when not measured.
static double mean_ratio(const std::vector<double>& coarse, const std::vector<double>& fine) {
  return mean_of(fine) > 0.0 ? mean_of(coarse) / mean_of(fine) : NAN;
}
double outresolution(const MeshRun& m, const MeshRun& reference, size_t k) {
  if (k >= m.resolution.size() || k >= reference.resolution.size()) return NAN;
  const PlaceResolution& a = m.resolution[k];
  const PlaceResolution& b = reference.resolution[k];
  double least = NAN;
  for (const double r : {mean_ratio(a.surface, b.surface), mean_ratio(a.first_height, b.first_height),
                         mean_ratio(a.interior, b.interior)})
    if (std::isfinite(r) && !(r >= least)) least = r;
  return least;
}

// The verdict on a difference where the reference may not out-resolve the mesh: "cannot tell" with
// the reason, or the band's verdict.
std::string resolved_verdict(const std::string& verdict, double ratio) {
  if (std::isfinite(ratio) && ratio < kOutResolves)
    return fmt::format("cannot tell: the reference only {:.2f}x as fine here", ratio);
  return verdict;
}


// A verdict "larger" than the spatial band that the temporal error could explain: said so.
std::string timed_verdict(const std::string& verdict, double difference, double time_error) {
  if (verdict == "larger" && std::isfinite(time_error) && std::abs(difference) <= time_error)
    return "within the temporal error (time step, start-up)";
  return verdict;
}

std::pair<const MeshRun*, const MeshRun*> check_pair(const StudyResult& result, const std::optional<MeshRun>& check) {
  if (!check) return {nullptr, nullptr};
  for (const MeshRun& m : result.meshes)
    if (m.series) return {&*check, &m};
  return {nullptr, nullptr};
}

void TemporalError::rank_into(Ranked& rank, double scale) const {
  rank.time_band = 100.0 * time_step / scale;
  rank.start_band = 100.0 * start_up / scale;
  std::vector<std::string> parts;
  if (std::isfinite(rank.time_band)) parts.push_back(fmt::format("time step: {:.2f} %", rank.time_band));
  if (std::isfinite(rank.start_band)) parts.push_back(fmt::format("start-up: {:.2f} %", rank.start_band));
  if (!parts.empty()) rank.uncertainty += fmt::format(" ({})", fmt::join(parts, ", "));
}

double TemporalError::total() const { return measured_sum(time_step, start_up); }

TemporalError temporal_error(const StudyResult& result, const std::function<double(const MeshRun&)>& value) {
  TemporalError e;
  if (const auto [half, level] = check_pair(result, result.half_step); half)
    e.time_step = kTimeErrorFactor * std::abs(value(*half) - value(*level));
  if (const auto [next, level] = check_pair(result, result.next_period); next)
    e.start_up = std::abs(value(*next) - value(*level));
  return e;
}

std::vector<std::string> unsettled_quantities(const std::vector<Ranked>& ranked) {
  std::vector<std::string> out;
  for (const Ranked& q : ranked)
    if (std::isfinite(q.start_band) && std::isfinite(q.band) && q.start_band > q.band)
      out.push_back(fmt::format("{} (start-up {:.2f} % against {:.2f} %)", q.quantity, q.start_band, q.band));
  return out;
}

// The whole-wall change of a check (times `factor`) in a field's L2 or P95 measure, over the
// reference's mean.
static WallDifference check_wall(const StudyResult& result, const std::optional<MeshRun>& check,
                                 const std::string& key, double factor) {
  const auto [run, level] = check_pair(result, check);
  const MeshRun& reference = result.meshes[result.reference];
  if (!run || !reference.wall.count(key)) return {NAN, NAN, NAN};
  const bool wss = key == "wss";
  const std::vector<double>* hs = key == "tawss" ? &run->tawss_on_reference : &run->osi_on_reference;
  const std::vector<double>* ls = key == "tawss" ? &level->tawss_on_reference : &level->osi_on_reference;
  if (wss ? run->wss_on_reference.empty() : hs->empty()) return {NAN, NAN, NAN};
  const WallDifference d = wss ? wall_difference(result.reference_area, run->wss_on_reference, level->wss_on_reference)
                               : wall_difference(result.reference_index_area, *hs, *ls);
  const double mean = reference.wall.at(key).mean;
  return {factor * d.l2 * d.mean / mean, factor * d.p95 * d.mean / mean, mean};
}

// A check's share of the reference's error: the series' first level and the check at every ring
// minimum and point, and over the whole wall; returns the same for study.json. `factor` turns the
// change into the error; `header` names the table's columns (the level's value, the check's, the change,
// the error), `keys` study.json's (the level's value, the check's, the error).
static Json check_section(Document& doc, const StudyConfig& config, const StudyResult& result,
                          const std::optional<MeshRun>& check, double factor, const std::string& heading,
                          const std::string& paragraph, const std::array<std::string, 4>& header,
                          const std::array<std::string, 3>& keys) {
  Json out = Json::array();
  const auto [run, level] = check_pair(result, check);
  if (!run) return out;
  doc.heading(heading);
  std::vector<std::vector<std::string>> rows;
  const auto add = [&](const std::string& quantity, double at_level, double at_check, const std::string& unit) {
    const double error = factor * std::abs(at_level - at_check);
    rows.push_back({quantity, number(at_level), number(at_check), number(at_level - at_check, 3), number(error, 3),
                    unit});
    out.push_back({{"quantity", quantity}, {keys[0], at_level}, {keys[1], at_check}, {keys[2], error}, {"unit", unit}});
  };
  for (size_t r = 0; r < result.rings.size(); ++r) {
    const post::Ring& a = level->rings[r];
    const post::Ring& b = run->rings[r];
    add(fmt::format("ring {}: minimum", result.rings[r].name), a.samples[a.minimum].magnitude,
        b.samples[b.minimum].magnitude, "Pa");
  }
  for (size_t p = 0; p < config.points.size(); ++p)
    add("point " + config.points[p].name, level->points[p].value.norm(), run->points[p].value.norm(), "Pa");
  for (const char* key : {"wss", "tawss", "osi"}) {
    const WallDifference w = check_wall(result, check, key, factor);
    if (!std::isfinite(w.l2)) continue;
    rows.push_back({fmt::format("whole wall: {} L2, P95", key), "-", "-", "-",
                    fmt::format("{:.2f} %, {:.2f} %", 100 * w.l2, 100 * w.p95), "of the reference's mean"});
    out.push_back({{"quantity", fmt::format("whole wall: {}", key)},
                   {keys[2] + "_l2_percent", 100 * w.l2},
                   {keys[2] + "_p95_percent", 100 * w.p95}});
  }
  doc.paragraph(paragraph);
  std::vector<std::string> columns = {"quantity"};
  for (size_t k = 0; k < header.size(); ++k) columns.push_back(k == 0 ? level->name + " " + header[0] : header[k]);
  columns.push_back("unit");
  doc.table(columns, rows);
  return out;
}

// The time step's share of the reference's error: the series' first level at dt and at dt / 2.
Json time_step_section(Document& doc, const StudyConfig& config, const StudyResult& result, double dt) {
  const auto [half, level] = check_pair(result, result.half_step);
  if (!half) return Json::array();
  return check_section(
      doc, config, result, result.half_step, kTimeErrorFactor, "The time step's share",
      fmt::format("{} run again at half the time step ({:g} s instead of {:g} s), saving at the same times: BDF2's "
                  "error goes as dt^2, so the run at dt is off the converged one by about 4/3 of its difference from "
                  "the run at dt / 2. That is the reference's temporal error (its time step is the same), set beside "
                  "its spatial uncertainty: a difference from the reference is called larger than its uncertainty only "
                  "where it exceeds both.",
                  level->name, dt / 2, dt),
      {"at dt", "at dt / 2", "difference", "temporal error (4/3 of it)"}, {"at_dt", "at_half_dt", "time_step_error"});
}

// The start-up's share: the series' first level and the same flow one period more.
Json start_up_section(Document& doc, const StudyConfig& config, const StudyResult& result) {
  const auto [next, level] = check_pair(result, result.next_period);
  if (!next) return Json::array();
  return check_section(
      doc, config, result, result.next_period, 1.0, "The start-up's share",
      fmt::format("{0}'s flow run one period ({1:g} s) more, from its last step, and read one period later (t = {2:g} "
                  "s), its indices over the new last period: the flows start from rest (or the Stokes flow), and what "
                  "changes from one period to the next is what is left of that start. Where a period takes the flow at "
                  "least halfway to its periodic state, that change bounds what is left, the start-up's error, set "
                  "beside the time step's: a difference is called larger than the reference's uncertainty only where "
                  "it exceeds the spatial band and their sum. A large share says to run the case's flow longer "
                  "(its [time] end one or more periods later).",
                  level->name, result.period, result.time + result.period),
      {"at t", "a period later", "change", "start-up error"}, {"at_t", "a_period_later", "start_up_error"});
}

// The whole-wall measures: per field (WSS at the study's time; TAWSS and OSI where the flows wrote
// them) the L2 and 95th-percentile differences of each mesh from the reference on the reference's
// wall, the reference's own uncertainty in each (the same measure between the series' finer levels,
// through Richardson: the distance of level 2 from the reference e21 and of level 3 from level 2
// e32 give the order, and 1.25 e21 / (r21^p - 1) bounds the reference's own distance from the
// converged field), the rows for the summary's ranking; returns the same for study.json.
Json whole_wall_section(Document& doc, const StudyResult& result,
                        const std::vector<const MeshRun*>& grids, std::vector<Ranked>& ranked) {
  Json out = Json::array();
  const MeshRun& reference = result.meshes[result.reference];
  if (!reference.wall.count("wss")) return out;
  doc.heading("Over the whole wall against the reference");
  const bool converges = grids.size() == 3 && grids[0] == &reference;
  std::vector<std::vector<std::string>> rows;
  const std::vector<std::pair<std::string, std::string>> fields = {
      {"wss", fmt::format("WSS at t = {:g} s", result.time)}, {"tawss", "TAWSS"}, {"osi", "OSI"}};
  for (const auto& [key, label] : fields) {
    if (!reference.wall.count(key)) continue;
    const double mean = reference.wall.at(key).mean;
    // The coarse step of the series, level 3 against level 2, in the reference's mean.
    WallDifference step{NAN, NAN, NAN};
    if (converges && grids[2]->wall.count(key)) {
      const std::vector<double>& area = key == "wss" ? result.reference_area : result.reference_index_area;
      const WallDifference d =
          key == "wss" ? wall_difference(area, grids[2]->wss_on_reference, grids[1]->wss_on_reference)
          : key == "tawss" ? wall_difference(area, grids[2]->tawss_on_reference, grids[1]->tawss_on_reference)
                           : wall_difference(area, grids[2]->osi_on_reference, grids[1]->osi_on_reference);
      step = {d.l2 * d.mean / mean, d.p95 * d.mean / mean, mean};
    }
    for (const bool l2 : {true, false}) {
      const std::string quantity = fmt::format("whole wall: {} {}", label, l2 ? "L2" : "95th percentile");
      GridConvergence g;
      g.found = false;
      g.spread = NAN;
      if (converges && grids[1]->wall.count(key)) {
        const double e21 = l2 ? grids[1]->wall.at(key).l2 : grids[1]->wall.at(key).p95;
        const double e32 = l2 ? step.l2 : step.p95;
        if (std::isfinite(e21) && std::isfinite(e32))
          g = grid_convergence(grids[0]->volume_points, grids[1]->volume_points, grids[2]->volume_points, 1.0,
                               1.0 + e21, 1.0 + e21 + e32);
      }
      Ranked rank{quantity, {}, g.found ? 100.0 * g.band() : NAN,
                  g.found ? fmt::format("{:.2f} %", 100.0 * g.band()) : converges ? g.status : "not estimated", {}, true};
      const WallDifference in_time = check_wall(result, result.half_step, key, kTimeErrorFactor);
      const WallDifference in_start = check_wall(result, result.next_period, key, 1.0);
      TemporalError{l2 ? in_time.l2 : in_time.p95, l2 ? in_start.l2 : in_start.p95}.rank_into(rank, 1.0);
      for (const MeshRun& m : result.meshes) {
        if (&m == &reference || !m.wall.count(key)) continue;
        const double d = 100.0 * (l2 ? m.wall.at(key).l2 : m.wall.at(key).p95);
        if (!m.series) rank.differences.emplace_back(m.name, d);
        const std::string verdict =
            timed_verdict(!g.found ? "unknown" : d > 100.0 * g.band() ? "larger" : "within", d, rank.temporal_band());
        rows.push_back({quantity, m.name, fmt::format("{:.2f} %", d), rank.uncertainty, verdict});
        out.push_back({{"quantity", quantity},
                       {"field", key},
                       {"measure", l2 ? "L2" : "P95"},
                       {"mesh", m.name},
                       {"difference_percent", std::isfinite(d) ? Json(d) : Json(nullptr)},
                       {"reference_mean", mean},
                       {"reference_uncertainty_percent", g.found ? Json(100.0 * g.band()) : Json(nullptr)},
                       {"order", g.found ? Json(g.order) : Json(nullptr)},
                       {"convergence", g.status},
                       {"beyond_uncertainty", verdict}});
      }
      ranked.push_back(rank);
    }
  }
  doc.paragraph(fmt::format(
      "Each mesh's field interpolated onto the reference's wall (at each of its points, the mesh wall's closest "
      "point): the L2 norm of the difference and the area-weighted 95th percentile of its magnitude, over the "
      "reference's mean (WSS as a vector; TAWSS and OSI over the flows' last period where they wrote them). Less "
      "fragile than one ring's minimum or one point. The reference's uncertainty in the same measure is "
      "Richardson's from the series' two finer steps ({}), 1.25 e21 / (r21^p - 1).",
      converges ? fmt::format("{}, {} and {}", grids[0]->name, grids[1]->name, grids[2]->name)
                : "not estimated: fewer than three levels"));
  doc.table({"measure", "mesh", "difference (of the reference's mean)", "reference's uncertainty",
             "beyond the reference's uncertainty"},
            rows);
  return out;
}

std::string times(double ratio) { return std::isfinite(ratio) ? fmt::format("{:.2f}x", ratio) : "n/a"; }

// The table of what each mesh resolves at each ring and point, and the reference's ratio to it
// (study/resolution.h); returns the same for study.json.
Json resolution_section(Document& doc, const StudyResult& result) {
  Json out = Json::array();
  if (result.places.empty()) return out;
  const MeshRun& reference = result.meshes[result.reference];
  doc.heading("Resolution where the study measures");
  std::vector<std::vector<std::string>> rows;
  double least = NAN;
  std::string least_where;
  for (size_t k = 0; k < result.places.size(); ++k) {
    for (const MeshRun& m : result.meshes) {
      if (k >= m.resolution.size()) continue;
      const PlaceResolution& r = m.resolution[k];
      const bool is_reference = &m == &reference;
      const double ratio = is_reference ? NAN : outresolution(m, reference, k);
      if (!m.series && std::isfinite(ratio) && !(ratio >= least)) {
        least = ratio;
        least_where = fmt::format("{} at {}", m.name, result.places[k].name);
      }
      const auto ratio_of = [&](const std::vector<double>& a, const std::vector<double>& b) {
        if (is_reference) return std::string("-");
        return a.size() > 1 ? fmt::format("{} ({})", times(mean_ratio(a, b)), times(least_ratio(a, b)))
                            : times(mean_ratio(a, b));
      };
      rows.push_back({result.places[k].name, m.name, number(mean_of(r.surface), 3), number(mean_of(r.first_height), 3),
                      number(mean_of(r.interior), 3), ratio_of(r.surface, reference.resolution[k].surface),
                      ratio_of(r.first_height, reference.resolution[k].first_height),
                      ratio_of(r.interior, reference.resolution[k].interior),
                      is_reference ? "(reference)"
                      : !std::isfinite(ratio) ? "not measured"
                      : ratio >= kOutResolves ? "yes"
                                              : "no"});
      out.push_back({{"place", result.places[k].name},
                     {"mesh", m.name},
                     {"positions", result.places[k].positions.size()},
                     {"surface_size", std::isfinite(mean_of(r.surface)) ? Json(mean_of(r.surface)) : Json(nullptr)},
                     {"first_layer_height",
                      std::isfinite(mean_of(r.first_height)) ? Json(mean_of(r.first_height)) : Json(nullptr)},
                     {"interior_size", std::isfinite(mean_of(r.interior)) ? Json(mean_of(r.interior)) : Json(nullptr)},
                     {"reference_finer_by", std::isfinite(ratio) ? Json(ratio) : Json(nullptr)},
                     {"reference_finer_by_surface_least",
                      is_reference || !std::isfinite(least_ratio(r.surface, reference.resolution[k].surface))
                          ? Json(nullptr)
                          : Json(least_ratio(r.surface, reference.resolution[k].surface))}});
    }
  }
  doc.paragraph(fmt::format(
      "At each ring (positions round it) and point, each mesh's surface size (the mean size of its wall triangles in "
      "their shortest direction, the side of the equilateral triangle of the same least altitude, within a fifth of "
      "the local radius), the height of its first cells above the wall there, and its interior size (the mean edge "
      "of its cells half a radius inward), in {}; and how many times finer the reference is than the mesh there: the "
      "ratio of their mean sizes over the place (at a ring, in brackets, the least over its positions, which "
      "scatters with the few cells a position sees). A difference from the reference is called beyond its uncertainty only where "
      "the reference is at least {:.1f} times as fine in all three; elsewhere the report says it cannot tell. The "
      "reference's least ratio to a compared mesh: {}{}.",
      result.length_unit, kOutResolves, times(least), least_where.empty() ? "" : " (" + least_where + ")"));
  doc.table({"place", "mesh", "surface size", "first layer height", "interior size", "reference finer: surface",
             "first layer", "interior", "out-resolved"},
            rows);
  return out;
}

}  // namespace vesselmesh::study::report
