#include "io/conformance.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

namespace vesselmesh::io {

ConformanceFile read_conformance(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot read the file", path));
  ConformanceFile file;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream words(line);
    ConformanceSection section;
    words >> section.keyword;
    if (section.keyword == "fluid-volumetric-flow-rate") words >> file.flow;
    if (section.keyword == "fluid-density") words >> file.density;
    if (section.keyword == "fluid-viscosity") words >> file.viscosity;
    if (section.keyword.rfind("plot-", 0) != 0) continue;
    for (double p = 0.0; words >> p;) section.parameters.push_back(p);
    int count = 0;
    if (!std::getline(in, line) || !(std::istringstream(line) >> count) || count < 0)
      throw InputError(fmt::format("{}:{}: section {} has no row count (a line with the number of rows)", path,
                                   line_number + 1, section.keyword));
    ++line_number;
    for (int i = 0; i < count; ++i) {
      if (!std::getline(in, line))
        throw InputError(fmt::format("{}: section {} ends after {} of its {} rows", path, section.keyword, i, count));
      ++line_number;
      double position = 0.0, value = 0.0;
      if (!(std::istringstream(line) >> position >> value))
        throw InputError(fmt::format("{}:{}: row {} of section {} is not two numbers: '{}'", path, line_number, i + 1,
                                     section.keyword, line));
      section.rows.emplace_back(position, value);
    }
    file.sections.push_back(std::move(section));
  }
  return file;
}

}  // namespace vesselmesh::io
