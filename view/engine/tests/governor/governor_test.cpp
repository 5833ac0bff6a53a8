// The Governor: the dead band between (1 - headroom) x target and the target, the minimum frames
// between changes, the state it reports, and what bad inputs do.
#include "meter/engine/governor/governor.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "governor_models.hpp"

namespace meter::engine::governor {
namespace {

using namespace fixtures;

// One unit: full 0.01 ms/px, level 1 0.005 ms/px. Target 10 ms, headroom 5 %: lower above
// 10 ms, raise only when full quality stays under 9.5 ms.
Governor one_unit(int min_frames) {
  GovernorOptions o;
  o.target_ms = 10;
  o.headroom = 0.05;
  o.min_frames_between_changes = min_frames;
  return Governor(model({unit("dial", 2, 1, {0.01, 0.005})}), o);
}

TEST(Governor, HysteresisDeadBand) {
  Governor g = one_unit(0);
  // 980 px: 9.8 ms at full, inside the band: no change.
  EXPECT_EQ(g.choose(load({980})), at({{0, 0}}));
  // 1020 px: 10.2 ms > 10: lowered (5.1 ms).
  EXPECT_EQ(g.choose(load({1020})), at({{1, 0}}));
  EXPECT_NEAR(g.predicted_ms(), 5.1, 1e-9);
  // 970 px: full would be 9.7 ms, over 9.5: stays lowered although under the target.
  EXPECT_EQ(g.choose(load({970})), at({{1, 0}}));
  // 940 px: full is 9.4 ms <= 9.5: raised.
  EXPECT_EQ(g.choose(load({940})), at({{0, 0}}));
  EXPECT_EQ(g.state().changes, 2u);
}

TEST(Governor, MinimumFramesBetweenChanges) {
  Governor g = one_unit(8);
  EXPECT_EQ(g.choose(load({2000})), at({{1, 0}}));  // the first change may happen at once
  // The load drops at once, but the next 7 drawn frames keep the choice; frames that are not
  // drawn do not count.
  FrameLoad skipped;
  skipped.unit_pixels = {0};
  for (int f = 1; f < 8; ++f) {
    EXPECT_EQ(g.choose(load({100})), at({{1, 0}})) << "frame " << f;
    EXPECT_EQ(g.choose(skipped), at({{1, 0}}));
  }
  EXPECT_EQ(g.state().frames_since_change, 7);
  EXPECT_EQ(g.choose(load({100})), at({{0, 0}}));  // the 8th frame after the change
}

// A frame predicted over the target is worse than a change sooner than the minimum: a step down
// is taken at once; only steps up wait for the minimum number of frames.
TEST(Governor, OverTheTargetAStepDownDoesNotWaitForTheMinimumFrames) {
  GovernorOptions o;
  o.target_ms = 10;
  o.min_frames_between_changes = 8;
  // Three shadings: 0.01, 0.005 and 0.002 ms per pixel.
  Governor g(model({unit("dial", 3, 1, {0.01, 0.005, 0.002})}), o);
  EXPECT_EQ(g.choose(load({1020})), at({{1, 0}}));  // 10.2 ms at full: lowered to 5.1 ms
  EXPECT_EQ(g.choose(load({100})), at({{1, 0}}));   // the load drops: a step up waits
  EXPECT_EQ(g.choose(load({2100})), at({{2, 0}}));  // 10.5 ms at shading 1, 2 frames after: lowered
  EXPECT_NEAR(g.predicted_ms(), 4.2, 1e-9);
  for (int f = 1; f < 8; ++f) EXPECT_EQ(g.choose(load({100})), at({{2, 0}})) << "frame " << f;
  EXPECT_EQ(g.choose(load({100})), at({{0, 0}}));  // the 8th frame after the last change
}

// Fast attack, slow release: three drawn frames in a row slower than the model by more than the
// headroom are a load step, not an outlier, and the next choice is made for it at once (the
// window's fit would take half the window to follow); the way back is the window's, so the
// quality does not flicker.
TEST(Governor, ThreeSlowFramesInARowLowerTheQualityAtOnce) {
  Governor g = one_unit(8);
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));  // 9 ms predicted: full quality
  for (int f = 0; f < 3; ++f) g.observe(load({900}), at({{0, 0}}), 13.5);  // measured 1.5x
  EXPECT_NEAR(g.state().scale.pixel, 1.5, 1e-9);  // the scale in use: the window's x 1.5
  EXPECT_EQ(g.choose(load({900})), at({{1, 0}}));  // 13.5 ms > 10: lowered (6.75 ms)
  EXPECT_NEAR(g.predicted_ms(), 6.75, 1e-9);
  // The load stays: frames at level 1 measure 1.5x the model (6.75 ms); no step up.
  for (int f = 0; f < 20; ++f) {
    g.observe(load({900}), at({{1, 0}}), 6.75);
    EXPECT_EQ(g.choose(load({900})), at({{1, 0}})) << "frame " << f;
  }
}

TEST(Governor, OneOrTwoSlowFramesDoNotMoveTheChoice) {
  Governor g = one_unit(0);
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
  for (int f = 0; f < 60; ++f) g.observe(load({900}), at({{0, 0}}), 9.0);  // the model holds
  for (double ms : {13.5, 13.5, 9.0, 13.5, 9.0, 13.5, 13.5, 9.0}) {  // never three in a row
    g.observe(load({900}), at({{0, 0}}), ms);
    EXPECT_EQ(g.choose(load({900})), at({{0, 0}})) << ms;
  }
  EXPECT_EQ(g.state().changes, 0u);
}

// A step up the model wrongly thinks fits costs one frame over the target, not the fast attack's
// three, and is not tried again every few frames: the wait before the next one doubles.
TEST(Governor, AStepUpWhoseFirstFrameMissesTheTargetIsUndoneAndTriedLater) {
  Governor g = one_unit(2);
  EXPECT_EQ(g.choose(load({1020})), at({{1, 0}}));  // 10.2 ms at full: lowered
  EXPECT_EQ(g.choose(load({900})), at({{1, 0}}));   // 1 frame after the change: a step up waits
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));   // 2 frames: full quality predicted 9 ms
  g.observe(load({900}), at({{0, 0}}), 12.0);        // ... and measured 12 ms, over the 10 ms target
  EXPECT_EQ(g.choose(load({900})), at({{1, 0}}));   // undone at once
  EXPECT_EQ(g.state().step_ups_undone, 1u);
  EXPECT_EQ(g.state().step_up_wait, 4);
  for (int f = 1; f < 4; ++f) EXPECT_EQ(g.choose(load({900})), at({{1, 0}})) << "frame " << f;
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));  // tried again after 4 frames
  g.observe(load({900}), at({{0, 0}}), 9.0);        // this time it fits
  for (int f = 1; f <= 4; ++f) EXPECT_EQ(g.choose(load({900})), at({{0, 0}})) << "frame " << f;
  EXPECT_EQ(g.state().step_up_wait, 2);  // the step up held for its wait: the backoff is over
  EXPECT_EQ(g.state().step_ups_undone, 1u);
}

// A global rung change makes new targets and redraws everything in its first frame, once; the
// undo judges the frame after it.
TEST(Governor, AStepUpToARungIsJudgedOnTheFrameAfterItsFirst) {
  CostModel m = model({unit("U", 1, 1, {0.01})});
  GlobalCost half;
  half.level = {1, 0.5f};
  half.pixel_factor = 0.25;
  m.globals.push_back(half);
  GovernorOptions o;
  o.target_ms = 10;
  o.min_frames_between_changes = 0;
  Governor g(m, o);
  const QualityChoice lowered = at({{0, 0}}, {1, 0.5f});
  EXPECT_EQ(g.choose(load({1200})), lowered);  // 12 ms at full resolution: the rung (3 ms)
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));  // 9 ms at full resolution fits: back up
  g.observe(load({900}), at({{0, 0}}), 40.0);  // its own frame made the targets: not judged
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
  g.observe(load({900}), at({{0, 0}}), 9.0);  // the frame after: within the target
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
  EXPECT_EQ(g.state().step_ups_undone, 0u);
  // Down and up again; this time the frame after the rung change is over the target: undone.
  EXPECT_EQ(g.choose(load({1200})), lowered);
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
  g.observe(load({900}), at({{0, 0}}), 40.0);
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
  g.observe(load({900}), at({{0, 0}}), 11.0);
  EXPECT_EQ(g.choose(load({900})), lowered);
  EXPECT_EQ(g.state().step_ups_undone, 1u);
  // The full-resolution rung measured 11 / 9 of its prediction, and its cost carries that error
  // now: 900 px is 11 ms (over the 9.5 ms budget), 800 px 9.78 ms, 700 px 8.56 ms.
  EXPECT_EQ(g.choose(load({900})), lowered);
  EXPECT_EQ(g.choose(load({800})), lowered);
  EXPECT_EQ(g.choose(load({700})), at({{0, 0}}));
  EXPECT_NEAR(g.predicted_ms(), 7.0 * 11.0 / 9.0, 1e-9);
  // Frames at that rung measuring 7 x 11/9 ms: the step up held, so the rung's error moved halfway
  // back to 1 (10/9) and the window learns what is left (1.1), against the model the choice is
  // made on. The prediction is the measured time, the error counted once (counted twice, 7 x 11/9
  // x 11/9 = 10.5 ms would be over the target and lower the quality).
  for (int f = 0; f < 60; ++f) {
    g.observe(load({700}), at({{0, 0}}), 7.0 * 11.0 / 9.0);
    EXPECT_EQ(g.choose(load({700})), at({{0, 0}})) << "frame " << f;
  }
  EXPECT_NEAR(g.predicted_ms(), 7.0 * 11.0 / 9.0, 0.01);
}

// Frames well within the budget never start a fast attack, however far off the model is for them
// (a partial redraw of a few pixels is mostly fixed overhead).
TEST(Governor, FramesWithinTheBudgetNeverStartAFastAttack) {
  Governor g = one_unit(0);
  // 3 frames at 3x the 1 ms predicted (too few for the window's fit, which stays at 1).
  for (int f = 0; f < 3; ++f) g.observe(load({100}), at({{0, 0}}), 3.0);
  EXPECT_EQ(g.state().fast_attack, 1.0);
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));  // 9 ms: full quality holds
}

TEST(Governor, StateNamesTheUnitsNotAtFullQuality) {
  GovernorOptions o;
  o.target_ms = 5;
  Governor g(model({unit("needle", 2, 2, {0.01, 0.008, 0.006, 0.001}), unit("dial", 1, 1, {0.001})}), o);
  g.choose(load({1000, 1000}));  // 11 ms: needle down to its cheapest (1 + 1 = 2 ms)
  const GovernorState s = g.state();
  ASSERT_EQ(s.reduced.size(), 1u);
  EXPECT_EQ(s.reduced[0].unit, 0);
  EXPECT_EQ(s.reduced[0].level, (UnitLevel{1, 1}));
  EXPECT_EQ(s.reduced[0].shading, bridge::ShadingModel::BlinnPhong);
  EXPECT_EQ(reduced_summary(s), "needle=blinn-phong/lod1");
  EXPECT_EQ(s.global_rung, 0);
  EXPECT_EQ(s.frames_chosen, 1u);
  EXPECT_NEAR(s.predicted_ms, 2.0, 1e-9);
}

TEST(Governor, ObservedSlowFramesScaleTheModelAndLowerTheQuality) {
  Governor g = one_unit(0);
  // 900 px predicts 9 ms (under the 9.5 ms budget): full quality holds ...
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
  // ... until the frames measure 1.5x the model (another process took a core): after a window's
  // worth of such frames the scale is 1.5, the prediction 13.5 ms > 10, and the unit is lowered.
  for (int f = 0; f < 60; ++f) g.observe(load({900}), at({{0, 0}}), 13.5);
  EXPECT_NEAR(g.state().scale.pixel, 1.5, 1e-6);
  EXPECT_EQ(g.choose(load({900})), at({{1, 0}}));
  EXPECT_EQ(g.state().measured_ms, 13.5);
  // The other process ends: the lowered frames measure what the model says (4.5 ms); once they
  // are the window's majority (31 of 60) the scale is 1 again and full quality (9 ms <= 9.5) is back.
  for (int f = 0; f < 31; ++f) g.observe(load({900}), at({{1, 0}}), 4.5);
  EXPECT_NEAR(g.state().scale.pixel, 1.0, 1e-6);
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
}

TEST(Governor, NonFiniteInputsNeverGiveANaN) {
  Governor g = one_unit(0);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const QualityChoice c = g.choose(load({nan}));
  EXPECT_TRUE(std::isfinite(g.predicted_ms()));
  for (double bad : {nan, inf, -1.0, 0.0}) g.observe(load({900}), c, bad);
  EXPECT_EQ(g.state().frames_observed, 0u);
  EXPECT_EQ(g.state().scale, ModelScale{});
  g.choose(load({inf}));
  EXPECT_TRUE(std::isfinite(g.predicted_ms()));
  EXPECT_TRUE(std::isfinite(g.state().scale.pixel));
}

TEST(Governor, OptionsAndModelsOutOfRangeAreErrors) {
  const CostModel m = model({unit("dial", 2, 1, {0.01, 0.005})});
  for (double t : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    GovernorOptions o;
    o.target_ms = t;
    EXPECT_THROW(Governor(m, o), std::invalid_argument) << t;
  }
  GovernorOptions o;
  o.headroom = 0.6;
  EXPECT_THROW(Governor(m, o), std::invalid_argument);
  o = {};
  o.window = 2;
  EXPECT_THROW(Governor(m, o), std::invalid_argument);
  o = {};
  o.fast_attack_frames = -1;
  EXPECT_THROW(Governor(m, o), std::invalid_argument);
  CostModel bad = m;
  bad.units[0].levels[1].cost.a_ms_per_pixel = std::numeric_limits<double>::quiet_NaN();
  try {
    Governor g(bad);
    FAIL() << "a NaN coefficient was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unit 'dial': level (blinn-phong, lod 0)"), std::string::npos) << e.what();
  }
  CostModel no_rungs = m;
  no_rungs.globals.clear();
  EXPECT_THROW(Governor{no_rungs}, std::invalid_argument);
}

}  // namespace
}  // namespace meter::engine::governor
