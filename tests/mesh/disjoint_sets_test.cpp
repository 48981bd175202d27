#include "mesh/disjoint_sets.h"

#include <gtest/gtest.h>

namespace vesselmesh::mesh {
namespace {

TEST(DisjointSets, RootIsTheSmallestMemberWhateverTheOrder) {
  DisjointSets a(6), b(6);
  EXPECT_TRUE(a.unite(5, 3));
  EXPECT_TRUE(a.unite(3, 1));
  EXPECT_FALSE(a.unite(1, 5));
  EXPECT_TRUE(b.unite(1, 3));
  EXPECT_TRUE(b.unite(5, 1));
  for (int i : {1, 3, 5}) {
    EXPECT_EQ(a.find(i), 1);
    EXPECT_EQ(b.find(i), 1);
  }
  for (int i : {0, 2, 4}) EXPECT_EQ(a.find(i), i);
}

}  // namespace
}  // namespace vesselmesh::mesh
