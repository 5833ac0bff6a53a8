// The cost file made from measurements: each level's A and B, the rungs' factors against the
// level-0 pixel part, their order by PSNR, and incomplete measurements refused by name.
#include <gtest/gtest.h>

#include "meter/calibrate/cost_samples.hpp"

namespace {

using meter::bridge::ShadingModel;
using meter::calibrate::CostMeasurements;
using meter::calibrate::cost_file;
using meter::calibrate::level_cost;
namespace gov = meter::engine::governor;

// Two units: "dial" (pbr, gouraud) x 2 LODs, "lamp" a safety unit with one level. Three node
// scales with the dial at 40000 / 22500 / 10000 pixels and the lamp at 400 / 225 / 100.
// dial level (s, l): A = (2 - s - 0.5 l) x 1e-5, B = 0.2; lamp: A = 1e-5, B = 0.05. Empty frame 0.5 ms.
CostMeasurements measurements() {
  CostMeasurements m;
  m.backend = "egl";
  m.ladders = {{"dial", false, {ShadingModel::PbrMetallicRoughness, ShadingModel::Gouraud}, {0.0f, 0.01f}, {1.0f, 0.5f}},
               {"lamp", true, {ShadingModel::Unlit}, {0.0f}, {1.0f}}};
  m.unit_pixels = {{40000, 400}, {22500, 225}, {10000, 100}};
  m.empty_ms = 0.5;
  for (int s = 0; s < 2; ++s)
    for (int l = 0; l < 2; ++l) {
      meter::calibrate::LevelSamples ls{0, {s, l}, {}, s + l > 0 ? std::optional(45.0 - 5 * (s + 2 * l)) : std::nullopt};
      for (const auto& px : m.unit_pixels) ls.samples.push_back({px[0], (2.0 - s - 0.5 * l) * 1e-5 * px[0] + 0.2});
      m.levels.push_back(ls);
    }
  meter::calibrate::LevelSamples lamp{1, {0, 0}, {}, std::nullopt};
  for (const auto& px : m.unit_pixels) lamp.samples.push_back({px[1], 1e-5 * px[1] + 0.05});
  m.levels.push_back(lamp);
  // Whole frames: overhead 0.5 + B's 0.25 + factor x pixel part (level 0: 2e-5 x dial + 1e-5 x lamp) + fixed.
  auto rung = [&](int msaa, float scale, double factor, double fixed, std::optional<double> db) {
    meter::calibrate::RungSamples r{{msaa, scale}, {}, db};
    for (const auto& px : m.unit_pixels) r.frame_ms.push_back(0.75 + factor * (2e-5 * px[0] + 1e-5 * px[1]) + fixed);
    return r;
  };
  m.rungs = {rung(4, 1.0f, 1.0, 0.0, std::nullopt), rung(1, 1.0f, 0.5, 0.1, 30.0), rung(4, 0.5f, 0.3, 0.2, 35.0)};
  return m;
}

TEST(CalibrationCostFile, EveryLevelsLineIsRecoveredFromTheMeasurements) {
  const gov::CostFile f = cost_file(measurements());
  ASSERT_EQ(f.units.size(), 2u);
  ASSERT_EQ(f.units[0].levels.size(), 4u);  // shading x lod, in that order
  for (const auto& l : f.units[0].levels) {
    const int s = l.shading == ShadingModel::Gouraud ? 1 : 0;
    // The samples lie exactly on their lines: the fit returns them to rounding (1e-9 relative).
    EXPECT_NEAR(l.cost.a_ms_per_pixel, (2.0 - s - 0.5 * l.lod) * 1e-5, 1e-12);
    EXPECT_NEAR(l.cost.b_ms, 0.2, 1e-9);
    if (s + l.lod == 0) EXPECT_FALSE(l.psnr_db.has_value());
    else EXPECT_DOUBLE_EQ(*l.psnr_db, 45.0 - 5 * (s + 2 * l.lod));
  }
  EXPECT_NEAR(f.units[1].levels[0].cost.b_ms, 0.05, 1e-9);
  EXPECT_DOUBLE_EQ(f.overhead.b_ms, 0.5);
}

TEST(CalibrationCostFile, RungsGetTheirFactorAndFixedPartAndComeBestPsnrFirst) {
  const gov::CostFile f = cost_file(measurements());
  ASSERT_EQ(f.globals.size(), 3u);
  EXPECT_EQ(f.globals[0].level, (gov::GlobalLevel{4, 1.0f}));
  EXPECT_EQ(f.globals[1].level, (gov::GlobalLevel{4, 0.5f}));  // 35 dB before 30 dB
  EXPECT_EQ(f.globals[2].level, (gov::GlobalLevel{1, 1.0f}));
  EXPECT_NEAR(f.globals[0].pixel_factor, 1.0, 1e-9);
  EXPECT_NEAR(f.globals[0].fixed_ms, 0.0, 1e-9);
  EXPECT_NEAR(f.globals[1].pixel_factor, 0.3, 1e-9);
  EXPECT_NEAR(f.globals[1].fixed_ms, 0.2, 1e-9);
  EXPECT_NEAR(f.globals[2].pixel_factor, 0.5, 1e-9);
  EXPECT_NEAR(f.globals[2].fixed_ms, 0.1, 1e-9);
  // What meter-view reads back is what was made.
  EXPECT_EQ(gov::parse_costs(gov::write_costs(f), "test"), f);
}

TEST(CalibrationCostFile, UnitsTimedAloneAreRescaledToTheWholeFrame) {
  // The units alone took half their time (A and B halved: the B's sum to 0.125) and the whole frame
  // has 0.25 ms more fixed time than their B's (0.5 in all): A x 2, B x 4, the rungs' factors and
  // fixed parts unchanged.
  auto m = measurements();
  for (auto& l : m.levels)
    for (auto& s : l.samples) s.ms = s.ms * 0.5;
  for (auto& r : m.rungs)
    for (auto& t : r.frame_ms) t += 0.25;
  const gov::CostFile f = cost_file(m);
  EXPECT_NEAR(f.units[0].levels[0].cost.a_ms_per_pixel, 2e-5, 1e-12);
  EXPECT_NEAR(f.units[0].levels[0].cost.b_ms, 0.4, 1e-9);
  EXPECT_NEAR(f.units[0].levels[3].cost.a_ms_per_pixel, 0.5e-5, 1e-12);  // gouraud/lod1: (2 - 1 - 0.5) x 1e-5
  EXPECT_NEAR(f.units[1].levels[0].cost.b_ms, 0.1, 1e-9);
  EXPECT_NEAR(f.globals[1].pixel_factor, 0.3, 1e-9);
  EXPECT_NEAR(f.globals[2].fixed_ms, 0.1, 1e-9);
}

TEST(CalibrationCostFile, AUnitTooSmallToTimeGetsItsMedianAsAFixedCost) {
  // Noise: the time falls as the pixels grow. A negative A is no cost model: A = 0, B = median.
  const auto c = level_cost({{100, 0.30}, {200, 0.10}, {300, 0.20}});
  EXPECT_EQ(c.a_ms_per_pixel, 0.0);
  EXPECT_DOUBLE_EQ(c.b_ms, 0.20);
  const auto one = level_cost({{0, -0.1}, {0, -0.3}});  // not on screen, timed below the empty frame
  EXPECT_EQ(one.a_ms_per_pixel, 0.0);
  EXPECT_EQ(one.b_ms, 0.0);
}

TEST(CalibrationCostFile, IncompleteMeasurementsAreNamed) {
  auto m = measurements();
  m.levels.erase(m.levels.begin() + 2);  // dial gouraud/lod0
  try {
    cost_file(m);
    FAIL() << "a missing level must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "no timing for dial gouraud/lod0");
  }
  m = measurements();
  m.rungs[1].frame_ms.pop_back();
  EXPECT_THROW(cost_file(m), std::invalid_argument);
}

}  // namespace
