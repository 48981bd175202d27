#include "mesh/trimesh.h"

namespace vesselmesh {

Field Field::scalar(std::string name, std::vector<double> values) {
  return Field{.name = std::move(name), .components = 1, .values = std::move(values)};
}

Field Field::vector(std::string name, const std::vector<Vec3>& values) {
  Field f{.name = std::move(name), .components = 3, .values = {}};
  f.values.reserve(values.size() * 3);
  for (const Vec3& v : values) f.values.insert(f.values.end(), {v.x(), v.y(), v.z()});
  return f;
}

Field Field::labels(std::string name, const std::vector<int>& values) {
  Field f{.name = std::move(name), .components = 1, .values = {}, .integer = true};
  f.values.assign(values.begin(), values.end());
  return f;
}

}  // namespace vesselmesh
