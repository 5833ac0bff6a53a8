// The choices drawn once at load: every rung with every level of every unit, safety units never
// moved, nothing drawn twice in a row.
#include "meter/engine/governor/warm_up_choices.hpp"

#include <gtest/gtest.h>

#include "governor_models.hpp"

namespace meter::engine::governor {
namespace {

using namespace fixtures;

TEST(WarmUpChoices, EveryRungWithEveryLevelOfEveryUnit) {
  // dial: 3 shadings x 2 LODs, lamp: a safety unit, needle: 2 shadings x 1 LOD; two rungs.
  CostModel m = model({unit("dial", 3, 2, {1, 1, 1, 1, 1, 1}), safety_unit("lamp", 1), unit("needle", 2, 1, {1, 1})});
  GlobalCost half;
  half.level = {1, 0.5f};
  half.pixel_factor = 0.3;
  m.globals.push_back(half);
  const std::vector<QualityChoice> c = warm_up_choices(m);
  // K = 3 steps per rung, cheapest first, ending at full quality: dial {2,1} {1,1} {0,0}; needle
  // {1,0} {1,0} {0,0}; lamp always {0,0}.
  const std::vector<QualityChoice> expected = {
      at({{2, 1}, {0, 0}, {1, 0}}), at({{1, 1}, {0, 0}, {1, 0}}), at({{0, 0}, {0, 0}, {0, 0}}),
      at({{2, 1}, {0, 0}, {1, 0}}, {1, 0.5f}), at({{1, 1}, {0, 0}, {1, 0}}, {1, 0.5f}), at({{0, 0}, {0, 0}, {0, 0}}, {1, 0.5f})};
  EXPECT_EQ(c, expected);
}

TEST(WarmUpChoices, AModelWithoutLevelsDrawsEachRungOnce) {
  CostModel m = model({unit("dial", 1, 1, {1}), safety_unit("lamp", 1)});
  EXPECT_EQ(warm_up_choices(m), std::vector<QualityChoice>{at({{0, 0}, {0, 0}})});
  GlobalCost msaa2;
  msaa2.level = {2, 1.0f};
  m.globals.push_back(msaa2);
  EXPECT_EQ(warm_up_choices(m).size(), 2u);
  m.units[0].safety = true;  // a unit with levels that is a safety item would still not move
  EXPECT_EQ(warm_up_choices(m).size(), 2u);
}

}  // namespace
}  // namespace meter::engine::governor
