#include "io/process.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <string_view>

extern char** environ;

namespace vesselmesh::io {
namespace {

volatile std::sig_atomic_t child_pid = 0;
extern "C" void pass_on(int signal) {
  if (child_pid > 0) kill(static_cast<pid_t>(child_pid), signal);
}

}  // namespace

int run_process(const std::vector<std::string>& argv, const std::vector<std::string>& environment,
                const std::vector<std::string>& drop) {
  VM_CHECK(!argv.empty(), "a program to run");
  std::vector<char*> args, env;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<std::string> left_out = drop;  // and ours of the names `environment` sets
  for (const std::string& e : environment) left_out.push_back(e.substr(0, e.find('=') + 1));
  for (char** e = environ; *e; ++e) {
    const std::string_view entry(*e);
    if (std::none_of(left_out.begin(), left_out.end(), [&](const std::string& p) { return entry.starts_with(p); }))
      env.push_back(*e);
  }
  for (const std::string& e : environment) env.push_back(const_cast<char*>(e.c_str()));
  env.push_back(nullptr);

  pid_t pid = 0;
  const int failed = posix_spawnp(&pid, argv[0].c_str(), nullptr, nullptr, args.data(), env.data());
  if (failed != 0)
    throw InputError(fmt::format("cannot run {}: {} (is it installed and on PATH?)", argv[0], std::strerror(failed)));
  child_pid = pid;
  const auto term = std::signal(SIGTERM, pass_on), interrupt = std::signal(SIGINT, pass_on);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  std::signal(SIGTERM, term);
  std::signal(SIGINT, interrupt);
  child_pid = 0;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 1;
}

double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

double file_memory_mb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("RssFile:", 0) == 0) return std::strtod(line.c_str() + 8, nullptr) / 1024.0;
  return 0.0;
}

}  // namespace vesselmesh::io
