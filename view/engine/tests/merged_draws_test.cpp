// Mesh concatenation at runtime, pure parts: the CPU vertex transform of a member and the index
// compaction / winding of the merged draw.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "meter/engine/merged_draws.hpp"
#include "test_scenes.hpp"

using namespace meter::engine;
using test::quad_primitive;

TEST(ConcatRuntime, TransformMemberMovesPositionsNormalsAndSetsAlpha) {
  Primitive p = quad_primitive(0);
  const glm::mat4 w = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(10, 20, 30)), glm::vec3(2, 2, 4));
  std::vector<float> out(std::size_t(4 * merged_stride(p)), -1.0f);
  transform_member(p, w, 1.0f, out);
  // vertex 2: (0.5, 0.5, 0) -> (11, 21, 30); normal (0,0,1) -> inverse transpose -> (0,0,0.25)
  const float* v = out.data() + 2 * 7;
  EXPECT_FLOAT_EQ(v[0], 11.0f);
  EXPECT_FLOAT_EQ(v[1], 21.0f);
  EXPECT_FLOAT_EQ(v[2], 30.0f);
  EXPECT_FLOAT_EQ(v[5], 0.25f);
  EXPECT_FLOAT_EQ(v[6], 1.0f);
  set_member_alpha(p, 0.0f, out);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(out[std::size_t(i * 7 + 6)], 0.0f);
  EXPECT_FLOAT_EQ(out[2 * 7], 11.0f);  // positions untouched
}

TEST(ConcatRuntime, IndicesAreOffsetAndMirroredMembersFlipWinding) {
  Primitive p = quad_primitive(0);
  std::vector<std::uint32_t> idx;
  append_member_indices(p, 100, false, idx);
  append_member_indices(p, 4, true, idx);
  EXPECT_EQ(idx, (std::vector<std::uint32_t>{100, 101, 102, 100, 102, 103, 4, 6, 5, 4, 7, 6}));
}
