#include "mesh/reporter.h"

namespace vesselmesh {

const Reporter& silent_reporter() {
  static const Reporter silent;
  return silent;
}

}  // namespace vesselmesh
