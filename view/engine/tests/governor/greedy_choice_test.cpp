// The greedy choice as a pure function: known costs and budgets -> known choices.
#include "meter/engine/governor/greedy_choice.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "governor_models.hpp"

namespace meter::engine::governor {
namespace {

using namespace fixtures;

// Two units, each 2 shadings x 2 lods; ms per pixel by rank (s0 l0, s1 l0, s0 l1, s1 l1):
// 0.01, 0.006, 0.005, 0.003. The small unit S has 100 pixels (1.0, 0.6, 0.5, 0.3 ms), the large
// L 1000 (10, 6, 5, 3 ms). Full quality: 11 ms.
CostModel two_units() {
  return model({unit("S", 2, 2, {0.01, 0.006, 0.005, 0.003}), unit("L", 2, 2, {0.01, 0.006, 0.005, 0.003})});
}
const FrameLoad kTwo = load({100, 1000});

TEST(GreedyChoice, OverBudgetLowersTheSmallestUnitShadingFirstThenItsLod) {
  // 11 > 10.55: S to (s1,l0) = 10.6, still over; S to (s0,l1) (LOD down, shading back to best)
  // = 10.5 <= 10.55: stop. Raising cannot undo either step without exceeding 10.55. (Budgets sit
  // between the sums, never on one, so rounding cannot decide a test.)
  const GreedyResult r = greedy_choice(two_units(), kTwo, {}, {10.55, 10.55});
  EXPECT_TRUE(r.lowered);
  EXPECT_EQ(r.choice.units[0], (UnitLevel{0, 1}));
  EXPECT_EQ(r.choice.units[1], (UnitLevel{0, 0}));
  EXPECT_NEAR(r.predicted_ms, 10.5, 1e-9);
}

TEST(GreedyChoice, OverBudgetMovesToTheNextSmallestOnceTheSmallestIsExhausted) {
  // Budget 10: S goes through all its levels (10.6, 10.5, 10.3), then L to (s1,l0): 6.3. The
  // raise pass then gives S back its best level that fits: 1.0 + 6 = 7.0 <= 10.
  const GreedyResult r = greedy_choice(two_units(), kTwo, {}, {10, 10});
  EXPECT_EQ(r.choice.units[0], (UnitLevel{0, 0}));
  EXPECT_EQ(r.choice.units[1], (UnitLevel{1, 0}));
  EXPECT_NEAR(r.predicted_ms, 7.0, 1e-9);
}

TEST(GreedyChoice, UnderBudgetRaisesTheLargestFirstAndStopsJustBeforeExceeding) {
  const QualityChoice cheapest = at({{1, 1}, {1, 1}});  // 0.3 + 3 = 3.3 ms
  // Budget 6.55: L's best level that fits is (s1,l0): 0.3 + 6 = 6.3 (full would be 10.3); then
  // S: full 7.0 and (s1,l0) 6.6 exceed, (s0,l1) 6.5 fits, just under.
  const GreedyResult r = greedy_choice(two_units(), kTwo, cheapest, {6.55, 6.55});
  EXPECT_FALSE(r.lowered);
  EXPECT_TRUE(r.raised);
  EXPECT_EQ(r.choice.units[1], (UnitLevel{1, 0}));
  EXPECT_EQ(r.choice.units[0], (UnitLevel{0, 1}));
  EXPECT_NEAR(r.predicted_ms, 6.5, 1e-9);
  // Budget 20: everything back to full (11 ms).
  const GreedyResult all = greedy_choice(two_units(), kTwo, cheapest, {20, 20});
  EXPECT_EQ(all.choice, at({{0, 0}, {0, 0}}));
}

TEST(GreedyChoice, TiesGoInUnitIndexOrderBothWays) {
  // Two identical units of 500 px: 5 ms full, 3 ms at (s1,l0). Budget 9 needs one step down:
  // the lower index (0) takes it. From both lowered (6 ms), budget 8.5 allows one step up: the
  // lower index again.
  const CostModel m = model({unit("A", 2, 1, {0.01, 0.006}), unit("B", 2, 1, {0.01, 0.006})});
  const FrameLoad l = load({500, 500});
  const GreedyResult down = greedy_choice(m, l, {}, {9, 9});
  EXPECT_EQ(down.choice, at({{1, 0}, {0, 0}}));
  const GreedyResult up = greedy_choice(m, l, at({{1, 0}, {1, 0}}), {8.5, 8.5});
  EXPECT_EQ(up.choice, at({{0, 0}, {1, 0}}));
}

TEST(GreedyChoice, AStepDownSkipsLevelsThatAreMeasuredToCostMore) {
  // Shadings pbr 0.01, blinn-phong 0.02 (slower, as flat is on llvmpipe), gouraud 0.004 ms/px at
  // 1000 px: 10, 20, 4 ms. Over budget 8 the step goes straight to gouraud.
  const CostModel m = model({unit("U", 3, 1, {0.01, 0.02, 0.004})});
  const GreedyResult r = greedy_choice(m, load({1000}), {}, {8, 8});
  EXPECT_EQ(r.choice.units[0], (UnitLevel{2, 0}));
}

TEST(GreedyChoice, SafetyUnitsNeverMove) {
  // The telltale T costs 20 ms and cannot be lowered; U goes to its cheapest and the prediction
  // stays over the budget rather than touching T. A current choice that claims T lowered is
  // read as T at level 0 (its only level).
  const CostModel m = model({safety_unit("T", 0.02), unit("U", 2, 1, {0.01, 0.001})});
  const GreedyResult r = greedy_choice(m, load({1000, 1000}), {}, {5, 5});
  EXPECT_EQ(r.choice, at({{0, 0}, {1, 0}}));
  EXPECT_NEAR(r.predicted_ms, 21.0, 1e-9);
  EXPECT_EQ(greedy_choice(m, load({1000, 1000}), at({{0, 1}, {0, 0}}), {5, 5}).choice, at({{0, 0}, {1, 0}}));
}

TEST(GreedyChoice, UnitsNotDrawnInAPartialFrameStayWithoutTheFullFrame) {
  // U is not in this frame's damage (0 px): without the full frame's load, raising it would
  // redraw its box, work the load does not describe, so it stays lowered.
  const CostModel m = model({unit("U", 2, 1, {0.01, 0.005}), unit("V", 2, 1, {0.01, 0.005})});
  const GreedyResult r = greedy_choice(m, load({0, 100}, false), at({{1, 0}, {0, 0}}), {10, 10});
  EXPECT_EQ(r.choice, at({{1, 0}, {0, 0}}));
  // With the full frame's load, raising U is judged on its whole box: 2000 px is 20 + 1 ms > 10
  // (stays), 800 px is 8 + 1 = 9 ms <= 10 (raised).
  const FrameLoad full = load({2000, 100});
  EXPECT_EQ(greedy_choice(m, load({0, 100}, false), at({{1, 0}, {0, 0}}), {10, 10}, {}, &full).choice.units[0],
            (UnitLevel{1, 0}));
  const FrameLoad smaller = load({800, 100});
  EXPECT_EQ(greedy_choice(m, load({0, 100}, false), at({{1, 0}, {0, 0}}), {10, 10}, {}, &smaller).choice.units[0],
            (UnitLevel{0, 0}));
}

// One unit of 1000 px (10 ms full, 8 ms at its level 1) and a rung at a quarter of the pixel work.
CostModel with_rung(std::optional<double> unit_psnr, std::optional<double> rung_psnr) {
  CostModel m = model({unit("U", 2, 1, {0.01, 0.008})});
  if (unit_psnr) m.units[0].levels[1].psnr_db = unit_psnr;
  GlobalCost half;
  half.level = {1, 0.5f};
  half.pixel_factor = 0.25;
  half.psnr_db = rung_psnr;
  m.globals.push_back(half);
  return m;
}

TEST(GreedyChoice, WithoutPsnrRungsGoDownLastAndComeBackFirst) {
  // Budget 9: the unit step (10 -> 8) is enough, the rung is not touched.
  EXPECT_EQ(greedy_choice(with_rung({}, {}), load({1000}), {}, {9, 9}).choice, at({{1, 0}}));
  // Budget 5: the unit step (8) is not enough; then the rung: 8 x 0.25 = 2. Raising: the rung
  // first (back to full resolution: 8 > 5, no), then the unit: 10 x 0.25 = 2.5 fits.
  const GreedyResult r = greedy_choice(with_rung({}, {}), load({1000}), {}, {5, 5});
  EXPECT_EQ(r.choice, at({{0, 0}}, {1, 0.5f}));
  EXPECT_NEAR(r.predicted_ms, 2.5, 1e-9);
}

TEST(GreedyChoice, ARungChangeIsJudgedOnTheFullFrameItForces) {
  // A partial frame of 100 px: 0.25 ms at the quarter-pixel rung, 1 ms at full resolution, so
  // on this load alone raising the rung fits a 9 ms budget. But a rung change redraws everything:
  // on the last full frame (1000 px) full resolution is 10 ms > 9, so the rung stays.
  const CostModel m = with_rung({}, {});
  const QualityChoice lowered = at({{0, 0}}, {1, 0.5f});
  EXPECT_EQ(greedy_choice(m, load({100}, false), lowered, {9, 9}).choice, at({{0, 0}}));
  const FrameLoad full = load({1000});
  EXPECT_EQ(greedy_choice(m, load({100}, false), lowered, {9, 9}, {}, &full).choice, lowered);
}

TEST(GreedyChoice, WithPsnrTheRungIsTakenWhereItIsTheCheaperTradePerDb) {
  // Unit step: saves 2 ms for an error of 10^-3 (30 dB): 2000 ms per unit error.
  // Rung at 40 dB (10^-4): saves 7.5 ms, 75000 per unit error: taken first; 2.5 <= 9.
  EXPECT_EQ(greedy_choice(with_rung(30.0, 40.0), load({1000}), {}, {9, 9}).choice, at({{0, 0}}, {1, 0.5f}));
  // Rung at 20 dB (10^-2): 750 per unit error, the unit step is the better trade; 8 <= 9.
  EXPECT_EQ(greedy_choice(with_rung(30.0, 20.0), load({1000}), {}, {9, 9}).choice, at({{1, 0}}));
}

TEST(GreedyChoice, CheapestQualityIsByMeasuredCostNotByPosition) {
  // U: pbr 0.01, blinn-phong 0.002, gouraud 0.004 ms/px: blinn-phong is the cheapest although
  // gouraud comes later. The safety unit stays; the quarter-pixel rung is cheaper than rung 0.
  CostModel m = with_rung({}, {});
  m.units = {unit("U", 3, 1, {0.01, 0.002, 0.004}), safety_unit("T", 0.5)};
  EXPECT_EQ(cheapest_quality(m), at({{1, 0}, {0, 0}}, {1, 0.5f}));
  EXPECT_EQ(full_quality(m), at({{0, 0}, {0, 0}}));
}

TEST(GreedyChoice, ANonDrawnFrameKeepsTheChoice) {
  FrameLoad none;
  none.unit_pixels = {0, 0};
  const GreedyResult r = greedy_choice(two_units(), none, at({{1, 1}, {0, 1}}), {1, 1});
  EXPECT_EQ(r.choice, at({{1, 1}, {0, 1}}));
  EXPECT_EQ(r.predicted_ms, 0.0);
}

TEST(GreedyChoice, NonFiniteInputsNeverGiveANonFinitePrediction) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  FrameLoad l = load({nan, inf});
  l.redrawn_pixels = -inf;
  for (const GreedyBudget b : {GreedyBudget{nan, nan}, GreedyBudget{10, 10}, GreedyBudget{inf, inf}}) {
    const GreedyResult r = greedy_choice(two_units(), l, {}, b, {nan, inf});
    EXPECT_TRUE(std::isfinite(r.predicted_ms));
    ASSERT_EQ(r.choice.units.size(), 2u);
  }
  // An infinite pixel count reads as kMaxPixels: 1e12 x 0.003 ms at the cheapest level.
  const GreedyResult r = greedy_choice(two_units(), l, {}, {10, 10});
  EXPECT_EQ(r.choice.units[1], (UnitLevel{1, 1}));
  EXPECT_NEAR(r.predicted_ms, 1e12 * 0.003, 1.0);
}

TEST(GreedyChoice, ALoadOrChoiceThatDoesNotFitTheModelIsAnError) {
  EXPECT_THROW(greedy_choice(two_units(), load({1, 2, 3}), {}, {1, 1}), std::invalid_argument);
  EXPECT_THROW(greedy_choice(two_units(), kTwo, at({{2, 0}, {0, 0}}), {1, 1}), std::invalid_argument);
  EXPECT_THROW(greedy_choice(two_units(), kTwo, at({{0, 0}}), {1, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace meter::engine::governor
