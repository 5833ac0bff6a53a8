// Which boxes of a reused back buffer a display writes again (EGL_EXT_buffer_age): pure.
#include "meter/platform/display_damage.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace meter::platform {
namespace {

using Boxes = std::vector<PixelRegion>;
const PixelRegion kWhole{0, 0, 100, 50};

TEST(DisplayDamage, UnknownAgeRepaintsTheWholeFrame) {
  DamageHistory h(100, 50);
  EXPECT_EQ(h.repaint(0, Boxes{{1, 2, 3, 4}}), Boxes{kWhole});
}

TEST(DisplayDamage, BufferShownLastFrameNeedsOnlyThisFramesDamage) {
  DamageHistory h(100, 50);
  h.presented(Boxes{kWhole});
  EXPECT_EQ(h.repaint(1, Boxes{{1, 2, 3, 4}}), (Boxes{{1, 2, 3, 4}}));
}

TEST(DisplayDamage, OlderBufferAlsoGetsTheFramesShownSinceIt) {
  DamageHistory h(100, 50);
  h.presented(Boxes{kWhole});          // three presents ago: not needed for age 3
  h.presented(Boxes{{10, 10, 5, 5}});  // two ago
  h.presented(Boxes{{20, 20, 5, 5}});  // the last one
  const Boxes want{{1, 1, 2, 2}, {20, 20, 5, 5}, {10, 10, 5, 5}};
  EXPECT_EQ(h.repaint(3, Boxes{{1, 1, 2, 2}}), want);
}

TEST(DisplayDamage, AgeBeyondTheHistoryRepaintsTheWholeFrame) {
  DamageHistory h(100, 50, 2);
  h.presented(Boxes{{10, 10, 5, 5}});
  h.presented(Boxes{{10, 10, 5, 5}});
  h.presented(Boxes{{10, 10, 5, 5}});
  EXPECT_EQ(h.repaint(3, Boxes{{1, 1, 2, 2}}).size(), 3u);  // depth 2 remembers two presents
  EXPECT_EQ(h.repaint(4, Boxes{{1, 1, 2, 2}}), Boxes{kWhole});
}

TEST(DisplayDamage, BoxesAreCutToTheFrame) {
  DamageHistory h(100, 50);
  h.presented(Boxes{{90, 40, 50, 50}, {200, 200, 5, 5}});
  EXPECT_EQ(h.repaint(2, Boxes{{-5, -5, 10, 10}}), (Boxes{{0, 0, 5, 5}, {90, 40, 10, 10}}));
}

TEST(DisplayDamage, KmsClipsHaveTheirOriginTopLeft) {
  // A 50-high surface: a box on the bottom row in GL coordinates is on the last rows for KMS, one
  // touching the top edge starts at row 0.
  EXPECT_EQ(top_left_origin(Boxes{{10, 0, 20, 5}, {0, 40, 4, 10}, {3, 7, 1, 1}}, 50),
            (Boxes{{10, 45, 20, 5}, {0, 0, 4, 10}, {3, 42, 1, 1}}));
}

TEST(DisplayDamage, AreaSumsTheBoxes) {
  EXPECT_EQ(area(Boxes{{0, 0, 10, 10}, {5, 5, 10, 10}, {0, 0, 0, 7}}), 200);
}

}  // namespace
}  // namespace meter::platform
