#include "cli_support.h"

#include "io/atomic_file.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include <unistd.h>

namespace vesselmesh::cli {

TerminalReporter::TerminalReporter(bool quiet) : quiet_(quiet), terminal_(::isatty(2) == 1) {}

void TerminalReporter::end_live_line() const {
  if (live_line_) {
    std::fputc('\n', stderr);
    live_line_ = false;
  }
}

void TerminalReporter::info(std::string_view message) const {
  if (quiet_) return;
  end_live_line();
  fmt::print(stderr, "vesselmesh: {}\n", message);
}

void TerminalReporter::warning(std::string_view message) const {
  end_live_line();
  fmt::print(stderr, "vesselmesh: warning: {}\n", message);
}

void TerminalReporter::progress(std::string_view task, double fraction) const {
  if (quiet_) return;
  const auto now = std::chrono::steady_clock::now();
  if (task != task_) {
    task_ = std::string(task);
    started_ = now;
    last_percent_ = -1;
    if (!terminal_) fmt::print(stderr, "vesselmesh: {} ...\n", task);
  }
  const int percent = static_cast<int>(std::floor(100.0 * std::clamp(fraction, 0.0, 1.0)));
  if (terminal_ && percent != last_percent_) {
    fmt::print(stderr, "\r\033[Kvesselmesh: {} {:3d}%", task, percent);
    live_line_ = true;
  }
  last_percent_ = percent;
  if (fraction >= 1.0) {
    const double seconds = std::chrono::duration<double>(now - started_).count();
    if (terminal_) {
      fmt::print(stderr, "\r\033[Kvesselmesh: {} done ({:.2f} s)\n", task, seconds);
      live_line_ = false;
    } else {
      fmt::print(stderr, "vesselmesh: {} done ({:.2f} s)\n", task, seconds);
    }
    task_.clear();
  }
}

int launch_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
    if (const char* value = std::getenv(name)) return std::atoi(value);
  return 0;
}

void add_common_options(CLI::App& app, CommonOptions& options) {
  app.add_flag("--json", options.json, "Print a machine-readable summary (JSON) on stdout");
  app.add_flag("-q,--quiet", options.quiet, "Print only warnings and errors on stderr");
}

double round_to(double value, int digits) {
  if (value == 0.0 || !std::isfinite(value)) return value;
  const double scale = std::pow(10.0, digits - 1 - static_cast<int>(std::floor(std::log10(std::abs(value)))));
  return std::round(value * scale) / scale;
}

Json to_json(const Vec3& v) { return Json::array({round_to(v.x()), round_to(v.y()), round_to(v.z())}); }

void print_json(const Json& json) { std::cout << json.dump(2) << std::endl; }

int run_action(const Action& action, const std::string& command) {
  try {
    return action();
  } catch (const InputError& e) {
    fmt::print(stderr, "vesselmesh {}: error: {}\n", command, e.what());
    return 2;
  } catch (const OptionError& e) {
    fmt::print(stderr, "vesselmesh {}: error: {}\n", command, e.what());
    return 2;
  } catch (const ComputationError& e) {
    fmt::print(stderr, "vesselmesh {}: error: {}\n", command, e.what());
    return 1;
  } catch (const StoppedError& e) {
    fmt::print(stderr, "vesselmesh {}: {}\n", command, e.what());
    return 128 + e.signal();
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "vesselmesh {}: error: out of memory\n", command);
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "vesselmesh {}: internal error: {}\n", command, e.what());
    return 1;
  }
}

Vec3 parse_point(const std::string& text, const char* option) {
  std::vector<double> v;
  size_t start = 0;
  const auto fail = [&]() {
    return OptionError(fmt::format("{} '{}' is not a point: give x,y,z in the file's unit", option, text));
  };
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    try {
      size_t used = 0;
      const std::string part = text.substr(start, comma - start);
      v.push_back(std::stod(part, &used));
      if (used != part.size() || !std::isfinite(v.back())) throw std::invalid_argument(part);
    } catch (const std::exception&) {
      throw fail();
    }
    start = comma + 1;
  }
  if (v.size() != 3) throw fail();
  return Vec3(v[0], v[1], v[2]);
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (;;) {
    const size_t at = text.find(separator, start);
    parts.push_back(text.substr(start, at == std::string::npos ? std::string::npos : at - start));
    if (at == std::string::npos) return parts;
    start = at + 1;
  }
}

std::string checked_name(const std::string& name, const std::string& text, const char* option) {
  if (!io::is_file_name_safe(name))
    throw OptionError(fmt::format("{} '{}': the name must be letters, digits, '_', '-' or '.' (it names files)",
                                  option, text));
  return name;
}

std::pair<std::string, Vec3> parse_named_point(const std::string& text, const char* option) {
  const std::vector<std::string> parts = split(text, ':');
  if (parts.size() != 2) throw OptionError(fmt::format("{} '{}': give NAME:x,y,z", option, text));
  return {checked_name(parts[0], text, option), parse_point(parts[1], option)};
}

}  // namespace vesselmesh::cli
