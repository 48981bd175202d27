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

std::vector<Vec3> Field::vectors() const {
  std::vector<Vec3> out(values.size() / 3);
  for (size_t i = 0; i < out.size(); ++i) out[i] = Vec3(values[3 * i], values[3 * i + 1], values[3 * i + 2]);
  return out;
}

const Field* find_field(const std::vector<Field>& fields, const std::string& name, int components, size_t count) {
  for (const Field& f : fields)
    if (f.name == name && f.components == components && f.values.size() == count * static_cast<size_t>(components))
      return &f;
  return nullptr;
}

Field Field::labels(std::string name, const std::vector<int>& values) {
  Field f{.name = std::move(name), .components = 1, .values = {}, .integer = true};
  f.values.assign(values.begin(), values.end());
  return f;
}

}  // namespace vesselmesh
