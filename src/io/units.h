// Length units of input files. Everything downstream of reading is in millimetres.
#pragma once

#include <string>
#include <string_view>

namespace vesselmesh::io {

enum class Unit { um, mm, cm, m };

// "um", "mm", "cm", "m" (also "micron", "millimeter", "metre", ...). Throws OptionError
// listing the accepted names for anything else.
Unit parse_unit(std::string_view name);
std::string unit_name(Unit unit);
// Factor that turns a length in `unit` into millimetres.
double millimetres_per(Unit unit);

}  // namespace vesselmesh::io
