// The concatenation costs' fit (merge_costs.hpp) and the shading ladder's table, on made-up
// measurements: no GL.
#include <gtest/gtest.h>

#include "meter/calibrate/merge_costs.hpp"
#include "meter/calibrate/shading_ladder.hpp"

using namespace meter;
using namespace meter::calibrate;

// Times made from known oh, m, s (plus a constant frame part the equations leave out) come back.
TEST(MergeCosts, FitRecoversTheCostsTheTimesWereMadeOf) {
  const double oh = 0.0016, m = 0.0004, s = 0.000012, c0 = 0.9;
  std::vector<MergeSample> samples;
  for (const auto& [n, v] : std::vector<std::pair<int, int>>{{10, 4000}, {100, 4000}, {400, 4000}, {100, 2000}, {100, 8000}})
    samples.push_back({n, v, c0 + oh * n + m * v, c0 + oh + (s + m) * v, c0 + oh + m * v});
  const auto costs = fit_merge_costs(samples);
  EXPECT_NEAR(costs.draw_ms, oh, 1e-9);
  EXPECT_NEAR(costs.vertex_ms, m, 1e-9);
  EXPECT_NEAR(costs.transform_ms, s, 1e-9);
  // Noise that makes a slope negative gives 0, never a negative cost.
  for (auto& x : samples) x.merged_moving_ms = x.merged_static_ms - 0.01;
  EXPECT_EQ(fit_merge_costs(samples).transform_ms, 0.0);
  // One object count only: oh cannot be fitted.
  EXPECT_THROW(fit_merge_costs({{10, 4000, 1, 1, 1}, {10, 2000, 1, 1, 1}}), std::invalid_argument);
}

// The whole-frame rungs with their PSNR and their cost against the rung above (one that costs more
// is not counted as cheaper), then one row per timed unit with shadings.
TEST(ShadingLadder, TableListsEveryRungAndCountsTheCheaperOnes) {
  CostMeasurements m;
  using bridge::ShadingModel;
  m.ladders.push_back({"Dial", false, {ShadingModel::PbrMetallicRoughness, ShadingModel::Gouraud, ShadingModel::Flat, ShadingModel::Unlit}, {0.0f}, {1.0f}});
  m.ladders.push_back({"Lamp", true, {ShadingModel::PbrMetallicRoughness}, {0.0f}, {1.0f}});
  const double ms[] = {0.40, 0.20, 0.25, 0.10};  // flat costs more than Gouraud here
  for (int sh = 0; sh < 4; ++sh) {
    const std::optional<double> db = sh ? std::optional<double>(50.0 - sh * 5) : std::nullopt;
    m.levels.push_back({0, {sh, 0}, {{1000.0, ms[sh]}}, db});
    m.shading_rungs.push_back({m.ladders[0].shadings[static_cast<std::size_t>(sh)], 10.0 * ms[sh], sh ? ms[sh] / ms[sh - 1] : 1.0, db});
  }
  const std::string t = shading_ladder_table(m);
  EXPECT_NE(t.find("Dial"), std::string::npos) << t;
  EXPECT_EQ(t.find("Lamp"), std::string::npos) << t;  // a safety unit has no ladder
  EXPECT_NE(t.find(" 0.2500 ( 40.0 dB)"), std::string::npos) << t;
  EXPECT_NE(t.find("flat             2.500 ms    40.0 dB  +25.0 % vs the rung above"), std::string::npos) << t;
  EXPECT_NE(t.find("each rung cheaper than the one above: 2 of 3"), std::string::npos) << t;
}
