#include "mesh/trimesh.h"

#include <gtest/gtest.h>

namespace vesselmesh {
namespace {

// A vector field back as vectors; a field found by name, components and count, none where one differs.
TEST(Field, VectorsRoundTripAndFindByNameComponentsAndCount) {
  const std::vector<Vec3> v{Vec3(1, 2, 3), Vec3(-4, 5.5, 6)};
  const std::vector<Field> fields{Field::scalar("p", {7.0, 8.0}), Field::vector("u", v)};
  EXPECT_EQ(fields[1].vectors(), v);
  ASSERT_NE(find_field(fields, "u", 3, 2), nullptr);
  EXPECT_EQ(find_field(fields, "u", 3, 2)->vectors(), v);
  EXPECT_EQ(find_field(fields, "p", 1, 2)->values, (std::vector<double>{7.0, 8.0}));
  EXPECT_EQ(find_field(fields, "u", 1, 2), nullptr);  // not a scalar
  EXPECT_EQ(find_field(fields, "u", 3, 3), nullptr);  // another count of points
  EXPECT_EQ(find_field(fields, "w", 3, 2), nullptr);
}

}  // namespace
}  // namespace vesselmesh
