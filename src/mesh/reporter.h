// How the library tells the caller what it does. The library never prints: a stage takes a
// `const Reporter&` and the program decides how to show messages and progress.
#pragma once

#include <string_view>

namespace vesselmesh {

class Reporter {
 public:
  virtual ~Reporter() = default;
  // A finding or step worth a line in the log.
  virtual void info(std::string_view /*message*/) const {}
  // Something the user should look at; the work goes on.
  virtual void warning(std::string_view /*message*/) const {}
  // Progress of a long task, fraction in [0, 1]; 1 closes the task.
  virtual void progress(std::string_view /*task*/, double /*fraction*/) const {}
};

// A reporter that drops everything: the default of every stage.
const Reporter& silent_reporter();

}  // namespace vesselmesh
