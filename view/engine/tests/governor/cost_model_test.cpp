// The frame-time prediction: overhead, rung factor and fixed part, units not drawn, bad inputs.
#include "meter/engine/governor/cost_model.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "governor_models.hpp"

namespace meter::engine::governor {
namespace {

using namespace fixtures;

// Unit U: 0.01 ms/px + 0.5 ms at full, 0.004 + 0.2 at level 1; V: 0.002 + 0.1. Overhead
// 1e-4 ms/px + 1 ms; rung 1 (MSAA 1, half scale): pixel factor 0.3, fixed 0.25 ms.
CostModel sample_model() {
  CostModel m = model({unit("U", 2, 1, {0.01, 0.004}), unit("V", 1, 1, {0.002})});
  m.units[0].levels[0].cost.b_ms = 0.5;
  m.units[0].levels[1].cost.b_ms = 0.2;
  m.units[1].levels[0].cost.b_ms = 0.1;
  m.overhead = {1e-4, 1.0};
  GlobalCost r;
  r.level = {1, 0.5f};
  r.pixel_factor = 0.3;
  r.fixed_ms = 0.25;
  m.globals.push_back(r);
  return m;
}

TEST(CostModel, PredictionAddsOverheadRungAndDrawnUnits) {
  const CostModel m = sample_model();
  FrameLoad l = load({1000, 500});  // redrawn 1500 px
  // Full: overhead 0.15 + 1; U 10 + 0.5; V 1 + 0.1 = 12.75 ms.
  EXPECT_NEAR(predict_ms(m, l, {}), 12.75, 1e-9);
  // Rung 1, U at level 1: pixel parts x 0.3: (0.15 + 4 + 1) x 0.3 = 1.545; fixed 1 + 0.25 + 0.2 + 0.1.
  const QualityChoice c = at({{1, 0}, {0, 0}}, {1, 0.5f});
  const PredictionParts p = predict_parts(m, l, c);
  EXPECT_NEAR(p.pixel_ms, 1.545, 1e-9);
  EXPECT_NEAR(p.fixed_ms, 1.55, 1e-9);
  // The online scales multiply the two parts separately.
  EXPECT_NEAR(predict_ms(m, l, c, {2.0, 0.5}), 2 * 1.545 + 0.5 * 1.55, 1e-9);
  // V not in this frame's damage: neither its pixels nor its B count.
  l.unit_pixels[1] = 0;
  l.redrawn_pixels = 1000;
  EXPECT_NEAR(predict_ms(m, l, {}), 0.1 + 1 + 10 + 0.5, 1e-9);
  // A frame that is not drawn costs nothing.
  l.drawn = false;
  EXPECT_EQ(predict_ms(m, l, {}), 0.0);
}

TEST(CostModel, BadPixelCountsAreReadSafely) {
  const CostModel m = sample_model();
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  FrameLoad l = load({nan, -5});
  l.redrawn_pixels = nan;
  EXPECT_EQ(predict_ms(m, l, {}), 1.0);  // only the overhead's fixed part
  l = load({inf, 0});
  const double p = predict_ms(m, l, {});
  EXPECT_TRUE(std::isfinite(p));
  EXPECT_NEAR(p, 0.01 * kMaxPixels + 1e-4 * kMaxPixels + 1.5, 1e3);
}

TEST(CostModel, AChoiceOrLoadThatDoesNotFitIsAnErrorNamingIt) {
  const CostModel m = sample_model();
  const FrameLoad l = load({1, 2});
  auto message = [&](const QualityChoice& c, const FrameLoad& fl) {
    try {
      predict_ms(m, fl, c);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(at({{0, 1}, {0, 0}}), l).find("unit 'U': level (shading 0, lod 1) is outside its 2 x 1 levels"),
            std::string::npos);
  EXPECT_NE(message(at({}, {2, 1.0f}), l).find("global rung msaa 2"), std::string::npos);
  EXPECT_NE(message({}, load({1})).find("the frame load has 1 units, the model 2"), std::string::npos);
}

}  // namespace
}  // namespace meter::engine::governor
