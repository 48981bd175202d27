#include "io/conformance.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>

namespace vesselmesh::io {
namespace {

// The header keywords both formats give the fluid by.
void read_fluid(ConformanceFile& file, const std::string& keyword, double value) {
  if (keyword == "fluid-volumetric-flow-rate") file.flow = value;
  if (keyword == "fluid-density") file.density = value;
  if (keyword == "fluid-viscosity") file.viscosity = value;
}

// The LDV files' format: fields separated by tabs and carriage returns (ends of line), blanks
// between them left out: `keyword value` pairs, then per section `<what>-at-z=`, the station z
// (m), the row count and that many `position value` pairs.
ConformanceFile read_tabbed(const std::string& path, const std::string& text) {
  std::vector<std::string> fields;
  std::string field;
  for (const char ch : text + "\t") {
    if (ch != '\t' && ch != '\r' && ch != '\n') {
      field += ch;
      continue;
    }
    const size_t first = field.find_first_not_of(' '), last = field.find_last_not_of(' ');
    if (first != std::string::npos) fields.push_back(field.substr(first, last - first + 1));
    field.clear();
  }
  const auto number = [&](size_t i, const std::string& what) {
    if (i >= fields.size())
      throw InputError(fmt::format("{}: the file ends where {} should be", path, what));
    char* end = nullptr;
    const double value = std::strtod(fields[i].c_str(), &end);
    if (end == fields[i].c_str() || *end != '\0')
      throw InputError(
          fmt::format("{}: field {} ('{}'), {}, is not a number", path, i + 1, fields[i], what));
    return value;
  };
  ConformanceFile file;
  const std::string suffix = "-at-z=";
  for (size_t i = 0; i < fields.size(); ++i) {
    const std::string& keyword = fields[i];
    if (keyword.rfind("fluid-", 0) == 0)
      read_fluid(file, keyword, number(i + 1, keyword + "'s value"));
    if (keyword.size() <= suffix.size() ||
        keyword.compare(keyword.size() - suffix.size(), suffix.size(), suffix))
      continue;
    ConformanceSection section;
    section.keyword = "plot-profile-" +
                      keyword.substr(0, keyword.size() - 1);  // as the conformance files name it
    section.parameters = {number(i + 1, "section " + keyword + "'s station")};
    const double count = number(i + 2, "section " + keyword + "'s row count");
    if (count < 0 || count > static_cast<double>(fields.size()) || count != std::floor(count))
      throw InputError(fmt::format("{}: section {} at z = {:g}: row count {:g} is not a count",
                                   path, keyword, section.parameters[0], count));
    for (int k = 0; k < static_cast<int>(count); ++k) {
      const std::string row =
          fmt::format("row {} of section {} at z = {:g}", k + 1, keyword, section.parameters[0]);
      section.rows.emplace_back(number(i + 3 + 2 * k, row), number(i + 4 + 2 * k, row));
    }
    i += 2 + 2 * static_cast<size_t>(count);
    file.sections.push_back(std::move(section));
  }
  return file;
}

}  // namespace

ConformanceFile read_conformance(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot read the file", path));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.find("-at-z=\t") != std::string::npos) return read_tabbed(path, text);
  in.clear(), in.seekg(0);
  ConformanceFile file;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream words(line);
    ConformanceSection section;
    words >> section.keyword;
    if (double value = 0.0; section.keyword.rfind("fluid-", 0) == 0 && words >> value)
      read_fluid(file, section.keyword, value);
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
