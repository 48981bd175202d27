#include "post/wall_series.h"

#include "flow/case.h"
#include "io/atomic_file.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>

namespace vesselmesh::post {

WallSeries read_wall_series(const std::string& directory, const std::string& collection) {
  WallSeries series;
  series.directory = directory;
  const std::string pvd = directory + "/" + collection + ".pvd";
  if (!std::filesystem::exists(pvd))
    throw InputError(fmt::format("{}: no such file; give the output folder of 'vesselmesh simulate'", pvd));
  const std::string text = io::read_file(pvd);
  const std::regex dataset(R"re(<DataSet\s[^>]*timestep="([^"]*)"[^>]*file="([^"]*)")re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), dataset); it != std::sregex_iterator(); ++it) {
    WallFrame frame;
    try {
      size_t used = 0;
      frame.time = std::stod((*it)[1].str(), &used);
      if (used != static_cast<size_t>((*it)[1].length())) throw std::invalid_argument("trailing");
    } catch (const std::exception&) {
      throw InputError(fmt::format("{}: timestep \"{}\" is not a number", pvd, (*it)[1].str()));
    }
    frame.file = directory + "/" + (*it)[2].str();
    if (!series.frames.empty() && !(frame.time > series.frames.back().time))
      throw InputError(fmt::format("{}: timesteps not increasing ({:g} after {:g})", pvd, frame.time,
                                   series.frames.back().time));
    series.frames.push_back(frame);
  }
  if (series.frames.empty()) throw InputError(fmt::format("{}: lists no results", pvd));
  const std::string summary = directory + "/summary.json";
  if (std::filesystem::exists(summary)) {
    try {
      const nlohmann::json j = nlohmann::json::parse(io::read_file(summary));
      series.length_unit = j.at("units").at("points").get<std::string>();
      series.length_scale = j.at("units").at("length_scale_m").get<double>();
      if (j.contains("period")) series.period = j.at("period").get<double>();
      if (j.contains("fluid")) {
        series.density = j.at("fluid").at("density_kg_m3").get<double>();
        series.viscosity = j.at("fluid").at("viscosity_Pa_s").get<double>();
      } else if (j.contains("case") && std::filesystem::exists(j.at("case").get<std::string>())) {
        try {
          const flow::FlowCase c = flow::read_case(j.at("case").get<std::string>());
          series.density = c.density, series.viscosity = c.viscosity;
        } catch (const Error&) {  // the case no longer reads (moved, or no longer valid): the fluid unknown
        }
      }
    } catch (const nlohmann::json::exception& e) {
      throw InputError(fmt::format("{}: {}", summary, e.what()));
    }
  }
  return series;
}

WallField read_wall_frame(const WallFrame& frame) {
  io::SurfaceData data = io::read_vtk_surface(frame.file, io::VtkFormat::vtp);
  WallField field;
  field.time = frame.time;
  if (const Field* wss = find_field(data.point_data, "wss", 3, data.mesh.points.size())) field.wss = wss->vectors();
  if (field.wss.empty())
    throw InputError(fmt::format("{}: has no point data `wss` (3 components); is it a wall file of "
                                 "'vesselmesh simulate'?",
                                 frame.file));
  field.mesh = std::move(data.mesh);
  return field;
}

FramePair frames_around(const WallSeries& series, double time) {
  const std::vector<WallFrame>& frames = series.frames;
  const double tolerance = 1e-9 * std::max(1.0, std::abs(frames.back().time));
  if (time < frames.front().time - tolerance || time > frames.back().time + tolerance)
    throw InputError(fmt::format("t = {:g} s is outside the saved results ({:g} to {:g} s, {} frames in {})", time,
                                 frames.front().time, frames.back().time, frames.size(), series.directory));
  size_t k = 0;
  while (k + 1 < frames.size() && frames[k + 1].time < time - tolerance) ++k;
  if (std::abs(frames[k].time - time) <= tolerance || k + 1 == frames.size()) return {k, k, 0.0};
  if (std::abs(frames[k + 1].time - time) <= tolerance) return {k + 1, k + 1, 0.0};
  return {k, k + 1, (time - frames[k].time) / (frames[k + 1].time - frames[k].time)};
}

std::vector<const WallFrame*> last_period_frames(const WallSeries& series) {
  std::vector<const WallFrame*> out;
  if (series.frames.empty()) return out;
  const double last = series.frames.back().time;
  const double from = series.period > 0.0 ? last - series.period : last;
  for (const WallFrame& f : series.frames)
    if (f.time >= from - 1e-9 * std::max(1.0, std::abs(from))) out.push_back(&f);
  return out;
}

void append_components(std::vector<std::vector<double>>& fields, const std::vector<Vec3>& vectors) {
  for (int c = 0; c < 3; ++c) {
    std::vector<double>& component = fields.emplace_back(vectors.size());
    for (size_t v = 0; v < vectors.size(); ++v) component[v] = vectors[v][c];
  }
}

WallField wall_at_time(const WallSeries& series, double time) {
  const FramePair pair = frames_around(series, time);
  WallField a = read_wall_frame(series.frames[pair.first]);
  if (pair.second == pair.first) return a;
  const WallField b = read_wall_frame(series.frames[pair.second]);
  if (b.wss.size() != a.wss.size())
    throw InputError(fmt::format("{} and {}: different walls ({} and {} points)", series.frames[pair.first].file,
                                 series.frames[pair.second].file, a.wss.size(), b.wss.size()));
  for (size_t i = 0; i < a.wss.size(); ++i) a.wss[i] += pair.weight * (b.wss[i] - a.wss[i]);
  a.time = time;
  return a;
}

}  // namespace vesselmesh::post
