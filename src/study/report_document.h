// The study report's parts shared by its files (study_report.cpp, report_measures.cpp): the
// document they write to, the number formats, what the summary ranks, and the sections of the
// measures that judge the reference (issue 46: where it out-resolves a mesh, the whole wall, the time
// step's share). Internal to the study stage.
#pragma once

#include "study/chart.h"
#include "study/gci.h"
#include "study/raster.h"
#include "study/study.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace vesselmesh::study::report {

using Json = nlohmann::ordered_json;

// The report as a list of blocks, written out as Markdown and as HTML.
struct Document {
  std::string markdown, html;
  std::string folder;

  void heading(const std::string& text, int level = 2) {
    markdown += std::string(level, '#') + " " + text + "\n\n";
    html += fmt::format("<h{0}>{1}</h{0}>\n", level, xml_escape(text));
  }
  void paragraph(const std::string& text) {
    markdown += text + "\n\n";
    html += "<p>" + xml_escape(text) + "</p>\n";
  }
  void code(const std::string& text) {
    markdown += "```\n" + text + (text.empty() || text.back() == '\n' ? "" : "\n") + "```\n\n";
    html += "<pre>" + xml_escape(text) + "</pre>\n";
  }
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
    markdown += "|";
    for (const std::string& h : header) markdown += " " + h + " |";
    markdown += "\n|";
    for (size_t k = 0; k < header.size(); ++k) markdown += " --- |";
    markdown += "\n";
    html += "<table>\n<tr>";
    for (const std::string& h : header) html += "<th>" + xml_escape(h) + "</th>";
    html += "</tr>\n";
    for (const auto& row : rows) {
      markdown += "|";
      html += "<tr>";
      for (const std::string& cell : row) {
        markdown += " " + cell + " |";
        html += "<td>" + xml_escape(cell) + "</td>";
      }
      markdown += "\n";
      html += "</tr>\n";
    }
    markdown += "\n";
    html += "</table>\n";
  }
  // Writes figures/NAME.svg and .png; the Markdown links the PNG, the HTML holds the SVG.
  void figure(const std::string& name, const std::string& svg, const std::string& caption) {
    write_svg_and_png(folder + "/figures/" + name, svg);
    markdown += fmt::format("![{0}](figures/{1}.png)\n\n*{0}* ([SVG](figures/{1}.svg))\n\n", caption, name);
    const size_t at = svg.find("<svg");
    html += "<figure>" + svg.substr(at == std::string::npos ? 0 : at) + "<figcaption>" + xml_escape(caption) +
            "</figcaption></figure>\n";
  }
};

inline std::string number(double v, int digits = 4) { return std::isfinite(v) ? fmt::format("{:.{}g}", v, digits) : "n/a"; }
inline std::string percent(double v) { return std::isfinite(v) ? fmt::format("{:+.2f} %", v) : "n/a"; }

// How many times finer than the reference must be than a mesh at a place for a difference there to
// be told from the reference's own error (issue 46).
constexpr double kOutResolves = 1.3;

// BDF2's error goes as dt^2: the run at dt is off the converged one by 4/3 of its difference from
// the run at dt / 2.
constexpr double kTimeErrorFactor = 4.0 / 3.0;

// The sum of the parts measured (not NaN); NaN where neither is.
inline double measured_sum(double a, double b) {
  if (!std::isfinite(a) && !std::isfinite(b)) return NAN;
  return (std::isfinite(a) ? a : 0.0) + (std::isfinite(b) ? b : 0.0);
}

// One quantity's differences of the compared meshes from the reference, for the summary.
struct Ranked {
  std::string quantity;  // "ring NAME: minimum", "point NAME"
  std::vector<std::pair<std::string, double>> differences;  // per compared mesh, percent
  double band = NAN;         // the reference's uncertainty in the same percent (NaN: not known)
  std::string uncertainty;   // as a table cell
  std::map<std::string, double> outresolved;  // per compared mesh: how many times finer the reference is there
  bool whole_wall = false;   // a whole-wall measure (study/wall_difference.h)
  // The reference's temporal error in the same percent, its two parts (NaN: not measured; TemporalError).
  double time_band = NAN, start_band = NAN;
  // Their sum, which a difference must exceed to be called real (NaN: neither measured).
  double temporal_band() const { return measured_sum(time_band, start_band); }
};

// The reference's temporal error at one quantity, from the checks that run the series' first level
// again: the time step's (4/3 of its change at dt / 2) and the start-up's (its change over one more
// period: what is left of the start from rest when a period takes the flow at least halfway to its
// periodic state; on the anastomosis study's level 1 one period took the WSS's RMS change from 4.8e-2
// to 2.9e-6), in the quantity's unit; NaN where not run.
struct TemporalError {
  double time_step = NAN, start_up = NAN;
  // The parts over `scale`, in percent, into `rank`; " (time step: x %, start-up: y %)" for the
  // parts measured added to its uncertainty's cell.
  void rank_into(Ranked& rank, double scale) const;
  // Their sum in the quantity's unit (NaN: neither measured).
  double total() const;
};
// At the quantity `value` gives of a run (its ring's minimum, its point's WSS).
TemporalError temporal_error(const StudyResult& result, const std::function<double(const MeshRun&)>& value);
// The quantities whose start-up's share exceeds the reference's spatial uncertainty (both known), each
// "QUANTITY (start-up x % against y %)": over the span they cover the flows still carry their start.
std::vector<std::string> unsettled_quantities(const std::vector<Ranked>& ranked);

// How many times finer the reference is than mesh m at place k (the least of the three measures'
// mean ratios over the place; NaN when not measured).
double outresolution(const MeshRun& m, const MeshRun& reference, size_t k);
// The verdict where the reference may not out-resolve the mesh: "cannot tell" with the reason, or `verdict`.
std::string resolved_verdict(const std::string& verdict, double ratio);
// A verdict "larger" than the spatial band that the temporal error could explain: said so.
std::string timed_verdict(const std::string& verdict, double difference, double time_error);
// The check (the level run at half the time step, or one period more) and the level it repeats (the
// series' first), or nulls.
std::pair<const MeshRun*, const MeshRun*> check_pair(const StudyResult& result, const std::optional<MeshRun>& check);
// "1.50x", or "n/a".
std::string times(double ratio);

// The sections; each returns what it adds to study.json.
Json time_step_section(Document& doc, const StudyConfig& config, const StudyResult& result, double dt);
Json start_up_section(Document& doc, const StudyConfig& config, const StudyResult& result);
Json whole_wall_section(Document& doc, const StudyResult& result, const std::vector<const MeshRun*>& grids,
                        std::vector<Ranked>& ranked);
Json resolution_section(Document& doc, const StudyResult& result);

}  // namespace vesselmesh::study::report
