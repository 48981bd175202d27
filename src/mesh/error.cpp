#include "mesh/error.h"

namespace vesselmesh {

void throw_internal(const char* condition, const char* file, int line,
                    const std::string& message) {
  throw InternalError("internal error: " + message + " (check '" + condition + "' failed at " +
                      file + ":" + std::to_string(line) + "; please report it)");
}

}  // namespace vesselmesh
