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
Governor one_unit(int min_frames, double miss_share = 0.02) {
  GovernorOptions o;
  o.target_ms = 10;
  o.headroom = 0.05;
  o.min_frames_between_changes = min_frames;
  o.miss_share = miss_share;
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

// The fast attack alone (no spread margin: that one would count the slow frames, see below).
TEST(Governor, OneOrTwoSlowFramesDoNotMoveTheChoice) {
  Governor g = one_unit(0, 0.0);
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

// Up, held, then down again within a window, over and over (the model drifting between two
// levels): each reversal doubles the wait before the next step up, so the flapping gets rarer;
// a step up that stays for a window (60 frames) ends the backoff.
TEST(Governor, AStepUpReversedWithinAWindowDoublesTheWaitSoTheChoiceStopsFlapping) {
  Governor g = one_unit(2);
  EXPECT_EQ(g.choose(load({1020})), at({{1, 0}}));  // 10.2 ms at full: lowered
  int expected_wait = 2;
  for (int flap = 0; flap < 4; ++flap) {
    // Full quality (9 ms) fits again: the step up comes after the wait ...
    for (int f = 1; f < expected_wait; ++f) EXPECT_EQ(g.choose(load({900})), at({{1, 0}})) << "flap " << flap << " frame " << f;
    EXPECT_EQ(g.choose(load({900})), at({{0, 0}})) << "flap " << flap;
    g.observe(load({900}), at({{0, 0}}), 9.0);  // its judged frame fits: not undone
    for (int f = 0; f < 5; ++f) EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
    // ... and 6 frames later the frames are predicted over the target again: down at once.
    EXPECT_EQ(g.choose(load({1020})), at({{1, 0}})) << "flap " << flap;
    expected_wait = 4 << flap;  // 4, 8, 16, 32
    EXPECT_EQ(g.state().step_up_wait, expected_wait);
  }
  EXPECT_EQ(g.state().step_ups_undone, 0u);
  // A step up that stays: 60 frames later the backoff is over, and a step down after that is an
  // ordinary one (the next step up waits the minimum 2 frames).
  for (int f = 1; f < expected_wait; ++f) g.choose(load({900}));
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
  for (int f = 0; f < 60; ++f) EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
  EXPECT_EQ(g.choose(load({1020})), at({{1, 0}}));
  EXPECT_EQ(g.choose(load({900})), at({{1, 0}}));
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
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

// The window's scale alone (no spread margin: while the window holds both loads the slow frames
// are over the fit and would hold the choice down for the rest of the window).
TEST(Governor, ObservedSlowFramesScaleTheModelAndLowerTheQuality) {
  Governor g = one_unit(0, 0.0);
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

// 57 frames as the model says and 3 (5 %, more than the 2 % allowed) at 1.3x, never three in a
// row (no fast attack). The fit stays 1 (the slow frames are its outliers), but full quality,
// predicted 9 ms, would miss the 10 ms target on each such frame: the spread is 1.3, the limit
// 10 / 1.3 = 7.7 ms, and the unit is lowered (4.5 ms). Without the margin it stays at full.
TEST(Governor, TheSpreadOfSlowFramesLowersTheChoiceSoThatFewMissTheTarget) {
  for (double share : {0.02, 0.0}) {
    Governor g = one_unit(0, share);
    EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
    for (int f = 0; f < 60; ++f) g.observe(load({900}), at({{0, 0}}), f % 20 == 7 ? 11.7 : 9.0);
    EXPECT_NEAR(g.state().scale.pixel, 1.0, 1e-6);
    EXPECT_EQ(g.state().fast_attack, 1.0);
    if (share > 0) {
      EXPECT_NEAR(g.state().spread, 1.3, 1e-9);
      EXPECT_EQ(g.choose(load({900})), at({{1, 0}}));
      // Lowered, its frames (4.5 ms) are under half the target and do not count; once the window
      // holds only them there is no spread left and full quality (9 ms <= 9.5) comes back.
      for (int f = 0; f < 60; ++f) g.observe(load({900}), at({{1, 0}}), 4.5);
      EXPECT_EQ(g.state().spread, 1.0);
      EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
    } else {
      EXPECT_EQ(g.state().spread, 1.0);
      EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
    }
  }
}

TEST(Governor, OneSlowFrameInAWindowOrSmallFramesGiveNoSpreadAndItIsCapped) {
  Governor g = one_unit(0);
  g.choose(load({900}));
  for (int f = 0; f < 60; ++f) g.observe(load({900}), at({{0, 0}}), f == 30 ? 18.0 : 9.0);  // 1 of 60: 1.7 %
  EXPECT_EQ(g.state().spread, 1.0);
  // Frames predicted under half the target (1 ms) do not count, however far off they come.
  Governor small = one_unit(0);
  small.choose(load({100}));
  for (int f = 0; f < 60; ++f) small.observe(load({100}), at({{0, 0}}), f % 2 ? 1.0 : 4.0);
  EXPECT_EQ(small.state().spread, 1.0);
  // A third of the frames at 3x: the spread is capped at 1.5 (the fast attack is for load steps).
  Governor slow = one_unit(0);
  slow.choose(load({900}));
  for (int f = 0; f < 60; ++f) slow.observe(load({900}), at({{0, 0}}), f % 3 ? 9.0 : 27.0);
  EXPECT_EQ(slow.state().spread, 1.5);
}

FrameLoad read_back(FrameLoad l) {
  l.read_back = true;
  return l;
}

// A dumped frame costs its readback on top of its drawing. one_unit: 900 px is 9 ms at full
// quality (fits the 9.5 ms budget), 4.5 ms at level 1.
TEST(Governor, AReadBackFrameTeachesTheReadbackWhichIsReservedWhileFramesAreDumped) {
  Governor g = one_unit(0);
  // The first dumped frame: nothing known of the readback yet, full quality; it measures 12 ms.
  const QualityChoice first = g.choose(read_back(load({900})));
  EXPECT_EQ(first, at({{0, 0}}));
  g.observe(read_back(load({900})), first, 12.0);
  EXPECT_NEAR(g.state().readback_ms, 3.0, 1e-9);  // 12 - 9
  EXPECT_EQ(g.state().scale, ModelScale{}) << "the readback was learnt as a slower drawing";
  // From now on, while frames are dumped, 3 ms is reserved: trigger 10 - 3 = 7 ms, budget 6.5 ms.
  // Full quality (9 ms) is over: level 1 (4.5 ms), predicted 7.5 ms with the readback. The frames
  // between the dumps hold it too, so a dump shows what its neighbours show.
  EXPECT_EQ(g.choose(load({900})), at({{1, 0}}));
  EXPECT_NEAR(g.predicted_ms(), 7.5, 1e-9);
  EXPECT_TRUE(g.state().readback_reserved);
  // Dumps drawn at level 1 that measure 4.5 + 3 ms: the window sees the drawing alone (4.5 ms,
  // what the model says), its scale stays 1, and the estimate stays 3 ms.
  for (int f = 0; f < 40; ++f) g.observe(read_back(load({900})), at({{1, 0}}), 7.5);
  EXPECT_NEAR(g.state().scale.pixel, 1.0, 1e-6);
  EXPECT_NEAR(g.state().readback_ms, 3.0, 1e-9);
  // 3 ms reserved: full quality (9 ms > the 6.5 ms budget) stays out while dumps go on. Once a
  // window (60 drawn frames) has passed without a dump nothing is reserved and full quality is back.
  for (int f = 2; f < 60; ++f) EXPECT_EQ(g.choose(load({900})), at({{1, 0}})) << "frame " << f << " after the dump";
  EXPECT_EQ(g.choose(load({900})), at({{0, 0}}));
  EXPECT_FALSE(g.state().readback_reserved);
}

TEST(Governor, TheReadbackEstimateMovesHalfwayToEachSampleAndIsNeverNegative) {
  Governor g = one_unit(0);
  const QualityChoice full = g.choose(read_back(load({900})));  // 9 ms predicted
  g.observe(read_back(load({900})), full, 12.0);
  EXPECT_NEAR(g.state().readback_ms, 3.0, 1e-9);  // the first sample: 12 - 9
  g.observe(read_back(load({900})), full, 14.0);
  EXPECT_NEAR(g.state().readback_ms, 4.0, 1e-9);  // halfway to 5
  g.observe(read_back(load({900})), full, 12.0);
  EXPECT_NEAR(g.state().readback_ms, 3.5, 1e-9);  // halfway to 3
  g.observe(read_back(load({900})), full, 8.0);   // under its prediction: a sample of 0, not -1
  EXPECT_NEAR(g.state().readback_ms, 1.75, 1e-9);
  g.observe(load({900}), full, 30.0);  // a frame that is not read back teaches nothing of it
  EXPECT_NEAR(g.state().readback_ms, 1.75, 1e-9);
}

TEST(Governor, TheReadbackReservedIsAtMostHalfTheTarget) {
  Governor g = one_unit(0);
  const QualityChoice first = g.choose(read_back(load({100})));  // 1 ms
  g.observe(read_back(load({100})), first, 21.0);                // a 20 ms readback
  EXPECT_NEAR(g.state().readback_ms, 20.0, 1e-9);
  // 5 ms reserved, not 20 (which would leave nothing to draw with): trigger 5, budget 4.5 ms.
  // 400 px is 4 ms at full quality: it fits.
  EXPECT_EQ(g.choose(load({400})), at({{0, 0}}));
  EXPECT_NEAR(g.predicted_ms(), 9.0, 1e-9);
  // 600 px (6 ms) does not: level 1, 3 ms.
  EXPECT_EQ(g.choose(load({600})), at({{1, 0}}));
  EXPECT_NEAR(g.predicted_ms(), 8.0, 1e-9);
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
  for (double share : {-0.01, 0.5, std::numeric_limits<double>::quiet_NaN()}) {
    o = {};
    o.miss_share = share;
    EXPECT_THROW(Governor(m, o), std::invalid_argument) << share;
  }
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
