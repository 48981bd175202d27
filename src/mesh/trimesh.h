// Core surface data: a triangle mesh as plain index-based arrays.
//
// Points are in the unit the caller works in (vesselmesh works in mm after reading).
// Triangles index `points`; for a closed lumen they are oriented outward (right-hand rule),
// open ends are boundary loops. `labels`, when not empty, holds one integer per triangle
// (a face id such as SimVascular's ModelFaceID) that every operation carries through.
// Connectivity is not stored here: build it on demand (mesh/connectivity.h).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

namespace vesselmesh {

using Vec3 = Eigen::Vector3d;
using Triangle = std::array<int, 3>;

struct TriMesh {
  std::vector<Vec3> points;
  std::vector<Triangle> triangles;
  std::vector<int> labels;  // empty, or one label per triangle

  bool has_labels() const { return !labels.empty(); }
  int num_points() const { return static_cast<int>(points.size()); }
  int num_triangles() const { return static_cast<int>(triangles.size()); }
};

// A named array of values attached to points or cells: `values.size() == count * components`.
// Vectors are stored xyz-interleaved; symmetric tensors as xx, xy, xz, yy, yz, zz.
struct Field {
  std::string name;
  int components = 1;
  std::vector<double> values;
  bool integer = false;  // written as Int32 (labels, tags)

  static Field scalar(std::string name, std::vector<double> values);
  static Field vector(std::string name, const std::vector<Vec3>& values);
  static Field labels(std::string name, const std::vector<int>& values);
  int count() const { return components == 0 ? 0 : static_cast<int>(values.size()) / components; }
  std::vector<Vec3> vectors() const;  // a field of 3 components as vectors (Field::vector's inverse)
};

// The field of this name with `components` components and `count` entries, or null.
const Field* find_field(const std::vector<Field>& fields, const std::string& name, int components, size_t count);

}  // namespace vesselmesh
