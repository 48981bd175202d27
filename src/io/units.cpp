#include "io/units.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

namespace vesselmesh::io {

Unit parse_unit(std::string_view name) {
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  static const std::array<std::pair<std::string_view, Unit>, 14> names{{
      {"um", Unit::um}, {"micron", Unit::um}, {"microns", Unit::um}, {"micrometer", Unit::um},
      {"mm", Unit::mm}, {"millimeter", Unit::mm}, {"millimetre", Unit::mm},
      {"cm", Unit::cm}, {"centimeter", Unit::cm}, {"centimetre", Unit::cm},
      {"m", Unit::m}, {"meter", Unit::m}, {"metre", Unit::m}, {"meters", Unit::m},
  }};
  for (const auto& [text, unit] : names)
    if (lower == text) return unit;
  throw OptionError(fmt::format("unknown length unit '{}': use um, mm, cm or m", name));
}

std::string unit_name(Unit unit) {
  switch (unit) {
    case Unit::um: return "um";
    case Unit::mm: return "mm";
    case Unit::cm: return "cm";
    case Unit::m: return "m";
  }
  return "mm";
}

double millimetres_per(Unit unit) {
  switch (unit) {
    case Unit::um: return 1e-3;
    case Unit::mm: return 1.0;
    case Unit::cm: return 10.0;
    case Unit::m: return 1000.0;
  }
  return 1.0;
}

}  // namespace vesselmesh::io
