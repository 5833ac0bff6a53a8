// The robust fit of time = A x pixels + B, and the online scales over a window of frames.
#include "meter/engine/governor/cost_fit.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "meter/engine/governor/online_estimate.hpp"

namespace meter::engine::governor {
namespace {

// Deterministic noise in [-1, 1): the raw mt19937 sequence is fixed by the standard (the
// library's distributions are not), so the data are the same everywhere.
class Noise {
 public:
  double next() { return double(gen_()) / 2147483648.0 - 1.0; }

 private:
  std::mt19937 gen_{20260};
};

// A = 2e-5 ms/px, B = 0.8 ms over 10k..1M px (1.0 .. 20.8 ms); +-0.05 ms uniform noise; every
// 10th sample an outlier 2..4x slower (a frame where another process ran).
std::vector<CostSample> timings_with_outliers() {
  Noise n;
  std::vector<CostSample> s;
  for (int i = 0; i < 60; ++i) {
    const double px = 1e4 + double(i) * (1e6 - 1e4) / 59.0;
    double ms = 2e-5 * px + 0.8 + 0.05 * n.next();
    if (i % 10 == 3) ms *= 3.0 + n.next();
    s.push_back({px, ms});
  }
  return s;
}

TEST(CostFit, RecoversAAndBFromTimingsWithTenPercentOutliers) {
  const std::vector<CostSample> s = timings_with_outliers();
  const CostFit f = fit_cost(s);
  // With +-0.05 ms noise (sd 0.029) on 54 inliers spread over 1M px, least squares has a standard
  // error of ~1e-7 ms/px... below 0.1 % of A and ~0.008 ms on B; the bounds (1 % and 0.05 ms) are
  // 10x and 6x that, and far below what one kept outlier would do (below).
  EXPECT_NEAR(f.a_ms_per_pixel, 2e-5, 2e-7);
  EXPECT_NEAR(f.b_ms, 0.8, 0.05);
  EXPECT_EQ(f.points_rejected, 6);
  EXPECT_EQ(f.points_used, 54);
  EXPECT_GT(f.r2, 0.999);
  // The same data by plain least squares misses both bounds: the outliers are what the test is about.
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const CostSample& c : s) sx += c.pixels, sy += c.ms, sxx += c.pixels * c.pixels, sxy += c.pixels * c.ms;
  const double n = double(s.size());
  const double a = (n * sxy - sx * sy) / (n * sxx - sx * sx), b = (sy - a * sx) / n;
  EXPECT_TRUE(std::abs(a - 2e-5) > 2e-7 || std::abs(b - 0.8) > 0.05) << a << " " << b;
}

TEST(CostFit, AnExactLineIsRecoveredExactly) {
  std::vector<CostSample> s;
  for (double px : {0.0, 1000.0, 5000.0, 20000.0}) s.push_back({px, 3e-5 * px + 0.25});
  const CostFit f = fit_cost(s);
  EXPECT_NEAR(f.a_ms_per_pixel, 3e-5, 1e-15);
  EXPECT_NEAR(f.b_ms, 0.25, 1e-12);
  EXPECT_EQ(f.r2, 1.0);
  EXPECT_EQ(f.points_used, 4);
}

TEST(CostFit, TimeFallingWithPixelsIsReadAsNoPixelCost) {
  const std::vector<CostSample> s = {{100, 2.0}, {200, 1.9}, {300, 1.8}};
  const CostFit f = fit_cost(s);
  EXPECT_EQ(f.a_ms_per_pixel, 0.0);
  EXPECT_NEAR(f.b_ms, 1.9, 1e-12);
  EXPECT_TRUE(std::isfinite(f.r2));
}

TEST(CostFit, DegenerateOrNonFiniteInputIsAnErrorNeverANaN) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const std::vector<CostSample>& s :
       {std::vector<CostSample>{}, {{100, 1.0}}, {{100, 1.0}, {100, 1.2}, {100, 0.9}}}) {
    try {
      fit_cost(s);
      ADD_FAILURE() << s.size() << " samples accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("2 or more distinct pixel counts"), std::string::npos) << e.what();
    }
  }
  const std::vector<std::vector<CostSample>> bad = {{{100, 1.0}, {200, 2.0}, {300, nan}},
                                                    {{100, 1.0}, {200, 2.0}, {-1, 3.0}},
                                                    {{100, 1.0}, {200, 2.0}, {std::numeric_limits<double>::infinity(), 3.0}}};
  for (const auto& s : bad) {
    try {
      fit_cost(s);
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("sample 2"), std::string::npos) << e.what();
    }
  }
}

// Frames of a partial-redraw run: the pixel part varies 2..10 ms with the damage, the fixed part
// is 1 ms. measured = factor x (pixel + fixed) with +-2 % noise and 10 % outlier frames at 3x.
struct FrameSeries {
  Noise noise;
  int frame = 0;
  PredictionParts next_parts() {
    const double p = 6.0 + 4.0 * noise.next();
    return {p, 1.0};
  }
  double measure(const PredictionParts& parts, double factor) {
    double ms = factor * parts.total() * (1.0 + 0.02 * noise.next());
    if (++frame % 10 == 0) ms *= 3.0;
    return ms;
  }
};

// The prediction for a typical frame (pixel 6 ms + fixed 1 ms) against the truth at `factor`.
double typical_error(const OnlineEstimate& e, double factor) {
  const PredictionParts typical{6.0, 1.0};
  return std::abs(typical.total(e.scale()) - factor * typical.total()) / (factor * typical.total());
}

TEST(OnlineEstimate, ALoadStepMovesTheModelWithinHalfAWindowAndBack) {
  constexpr int kWindow = 30;
  OnlineEstimate e(kWindow);
  FrameSeries run;
  for (int f = 0; f < 100; ++f) {
    const PredictionParts p = run.next_parts();
    e.add(p, run.measure(p, 1.0));
  }
  // Settled: 27 inliers with +-2 % noise; the typical frame is predicted within 3 % (the noise's
  // full range is 2 %; the fit averages it down) despite the 3x outliers.
  EXPECT_LT(typical_error(e, 1.0), 0.03);
  // The frame (counted from the step) at which a typical frame is predicted within 3 % of the
  // truth at `factor`, over 40 frames at that factor; -1 when it never is.
  auto frames_to_follow = [&](double factor) {
    int at = -1;
    for (int f = 1; f <= 40; ++f) {
      const PredictionParts p = run.next_parts();
      e.add(p, run.measure(p, factor));
      if (at < 0 && typical_error(e, factor) < 0.03) at = f;
    }
    return at;
  };
  // Another process takes a core: every frame 1.8x slower. The fit follows once the new frames
  // are the majority of the window (16 of 30); allow 20 frames (= 1/3 s at 60 fps): 16 plus the
  // outliers among them (every 10th frame, 2) plus 2 of margin. Not before 6: a few slow frames
  // are not a load step.
  const int moved_at = frames_to_follow(1.8);
  EXPECT_GT(moved_at, 5);
  EXPECT_LE(moved_at, 20);
  EXPECT_LT(typical_error(e, 1.8), 0.03);
  // The load goes away: back within the same number of frames.
  const int back_at = frames_to_follow(1.0);
  EXPECT_GT(back_at, 5);
  EXPECT_LE(back_at, 20);
}

TEST(OnlineEstimate, OneOutlierFrameDoesNotMoveTheModel) {
  OnlineEstimate e(60);
  for (int f = 0; f < 60; ++f) e.add({5.0 + double(f % 7), 1.0}, 1.2 * (6.0 + double(f % 7)));
  const ModelScale before = e.scale();
  EXPECT_NEAR(before.pixel, 1.2, 1e-9);
  EXPECT_NEAR(before.fixed, 1.2, 1e-9);
  e.add({6.0, 1.0}, 70.0);  // a 10x frame (the process was descheduled)
  EXPECT_NEAR(e.scale().pixel, 1.2, 1e-9);
  EXPECT_NEAR(e.scale().fixed, 1.2, 1e-9);
  EXPECT_EQ(e.rejected_last_fit(), 1);
}

TEST(OnlineEstimate, BadFramesAreIgnoredAndScalesStayFiniteAndBounded) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  OnlineEstimate e(8);
  EXPECT_FALSE(e.add({1.0, 1.0}, nan));
  EXPECT_FALSE(e.add({1.0, 1.0}, inf));
  EXPECT_FALSE(e.add({1.0, 1.0}, -1.0));
  EXPECT_FALSE(e.add({nan, 1.0}, 1.0));
  EXPECT_FALSE(e.add({0.0, 0.0}, 1.0));
  EXPECT_EQ(e.points(), 0);
  EXPECT_EQ(e.scale(), ModelScale{});
  // 1000x slower than predicted: clamped to the largest scale, not followed to infinity.
  for (int f = 0; f < 8; ++f) EXPECT_TRUE(e.add({1.0, 1.0}, 2000.0));
  EXPECT_EQ(e.scale().pixel, OnlineEstimate::kMaxScale);
  EXPECT_THROW(OnlineEstimate(3), std::invalid_argument);
}

}  // namespace
}  // namespace meter::engine::governor
