// The CPU mip chain, pure: sizes, the rounding of each step, the 1-wide tail, and what it refuses.
#include <gtest/gtest.h>

#include "meter/engine/gl/texture_mips.hpp"

using namespace meter::engine;

TEST(TextureMips, OnlyLinearPowerOfTwoTextures) {
  EXPECT_TRUE(box_mips_apply(256, 256, false));
  EXPECT_TRUE(box_mips_apply(256, 1, false));
  EXPECT_FALSE(box_mips_apply(256, 256, true));  // sRGB: glGenerateMipmap
  EXPECT_FALSE(box_mips_apply(100, 64, false));
  EXPECT_FALSE(box_mips_apply(0, 64, false));
}

TEST(TextureMips, EachLevelHalvesDownToOneTexel) {
  const std::vector<std::uint8_t> image(8 * 2 * 4, 7);
  const auto levels = box_mip_chain(image, 8, 2);
  ASSERT_EQ(levels.size(), 3u);  // 4x1, 2x1, 1x1
  EXPECT_EQ(levels[0].size(), 4u * 1u * 4u);
  EXPECT_EQ(levels[1].size(), 2u * 4u);
  EXPECT_EQ(levels[2].size(), 4u);
  EXPECT_EQ(levels[2], std::vector<std::uint8_t>(4, 7));
}

TEST(TextureMips, AcrossThenDownEachARoundedMeanOfTwo) {
  // Texels 1 0 / 0 0 (every channel): across (1+0+1)>>1 = 1 and (0+0+1)>>1 = 0, down (1+0+1)>>1 = 1,
  // where the rounded mean of all four would give 0.
  const std::vector<std::uint8_t> one{1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(box_mip_chain(one, 2, 2)[0], std::vector<std::uint8_t>(4, 1));
  // 200 100 / 50 0: across 150 and 25, down (150+25+1)>>1 = 88 (the mean of four: 87.5).
  const std::vector<std::uint8_t> ramp{200, 200, 200, 200, 100, 100, 100, 100, 50, 50, 50, 50, 0, 0, 0, 0};
  EXPECT_EQ(box_mip_chain(ramp, 2, 2)[0], std::vector<std::uint8_t>(4, 88));
}

TEST(TextureMips, AOneWideTextureAveragesDownOnly) {
  const std::vector<std::uint8_t> column{10, 10, 10, 10, 21, 21, 21, 21};  // 1x2
  EXPECT_EQ(box_mip_chain(column, 1, 2)[0], std::vector<std::uint8_t>(4, 16));  // (10+21+1)>>1
}

TEST(TextureMips, AWrongSizeIsRefused) {
  EXPECT_THROW(box_mip_chain(std::vector<std::uint8_t>(12 * 4), 3, 4), std::invalid_argument);
  EXPECT_THROW(box_mip_chain(std::vector<std::uint8_t>(3), 1, 1), std::invalid_argument);
}
