// What every subcommand shares: the terminal reporter, JSON output, how errors become exit
// codes (0 success, 2 bad input or options, 1 internal failure).
#pragma once

#include "mesh/reporter.h"
#include "mesh/trimesh.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <functional>
#include <string>

namespace vesselmesh::cli {

using Json = nlohmann::ordered_json;

// Messages and progress on stderr: a live line on a terminal, plain lines otherwise.
class TerminalReporter : public Reporter {
 public:
  explicit TerminalReporter(bool quiet = false);
  void info(std::string_view message) const override;
  void warning(std::string_view message) const override;
  void progress(std::string_view task, double fraction) const override;

 private:
  void end_live_line() const;
  bool quiet_;
  bool terminal_;
  mutable std::string task_;
  mutable bool live_line_ = false;
  mutable int last_percent_ = -1;
  mutable std::chrono::steady_clock::time_point started_;
};

// This process's rank among those mpirun (Open MPI, MPICH) started, from their environment
// (0 when none did), known before MPI is: under mpirun the first alone tells a bad command line.
int launch_rank();

// Options every subcommand has.
struct CommonOptions {
  bool json = false;
  bool quiet = false;
};
void add_common_options(CLI::App& app, CommonOptions& options);

Json to_json(const Vec3& v);
// Rounds to `digits` significant digits so that JSON stays readable.
double round_to(double value, int digits = 7);

// "x,y,z" as a point (or a direction); OptionError naming `option` otherwise.
Vec3 parse_point(const std::string& text, const char* option);
std::vector<std::string> split(const std::string& text, char separator);
// A name made of letters, digits, '_', '-', '.' (it names files), else OptionError quoting `text`.
std::string checked_name(const std::string& name, const std::string& text, const char* option);
// NAME:x,y,z
std::pair<std::string, Vec3> parse_named_point(const std::string& text, const char* option);

// Prints JSON to stdout (pretty, one document).
void print_json(const Json& json);

// A subcommand's action: returns the exit code. Exceptions are turned into messages here.
using Action = std::function<int()>;
int run_action(const Action& action, const std::string& command);

}  // namespace vesselmesh::cli
