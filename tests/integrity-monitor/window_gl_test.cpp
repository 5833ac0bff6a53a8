// A needle's window on the cluster as drawn (docs/integrity.md, "A needle's window"): on right
// frames the window decides with the whole region's very verdict and pixel sums; the speed needle
// turned 3 degrees about its pivot, or left at an old angle, is never passed by its window (the
// whole region then fails it, as before); and the monitor itself, frame by frame over the sweep,
// reads its needles whole only for its heartbeat.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "meter/engine/integrity_check.hpp"
#include "monitor_rig.hpp"

namespace {
using SafetyKind = meter::bridge::SafetyKind;
using SafetyRegion = meter::bridge::SafetyRegion;
using RgbaView = meter::engine::RgbaView;
using Image = meter::platform::Image;
}  // namespace
using meter::platform::BackendKind;
using meter::testing::MonitorRig;

namespace {

RgbaView whole(const Image& img) { return {img.rgba.data(), img.width, img.height, 0, 0, 0}; }

// The window's bands of a full frame (views into the frame itself: each covers its band).
std::optional<meter::engine::Verdict> window_verdict(const SafetyRegion& r, const Image& img, double expected,
                                                     meter::engine::NeedlePixels* n = nullptr) {
  const auto bands = meter::engine::needle_window(r, expected, 4);
  const std::vector<RgbaView> views(bands.size(), whole(img));
  return meter::engine::check_needle_window(r, views, bands, expected, n);
}

// The region turned by `deg` about the needle's pivot within its sector (nearest pixel), as a
// needle drawn that far off would look (meter_verify_test doctors its PNG the same way).
Image turned(const Image& src, const SafetyRegion& r, double deg) {
  Image img = src;
  const double th = -deg * M_PI / 180.0;
  for (int y = r.rect.y; y < r.rect.y + r.rect.height; ++y)
    for (int x = r.rect.x; x < r.rect.x + r.rect.width; ++x) {
      const double dx = x + 0.5 - r.needle.pivot_x, dy = y + 0.5 - r.needle.pivot_y;
      const double a = std::atan2(dx, -dy) * 180.0 / M_PI;
      if (std::hypot(dx, dy) > r.needle.r_max + 3 ||
          std::abs(meter::engine::wrap_degrees(a - r.needle.sector_center_deg)) > r.needle.sector_half_deg)
        continue;
      const int sx = int(std::floor(r.needle.pivot_x + dx * std::cos(th) - dy * std::sin(th)));
      const int sy = int(std::floor(r.needle.pivot_y + dx * std::sin(th) + dy * std::cos(th)));
      if (sx < 0 || sy < 0 || sx >= src.width || sy >= src.height) continue;
      std::copy(src.pixel(sx, sy), src.pixel(sx, sy) + 4, img.pixel(x, y));
    }
  return img;
}

class NeedleWindow : public ::testing::TestWithParam<BackendKind> {};

TEST_P(NeedleWindow, DecidesRightFramesExactlyAndLeavesWrongNeedlesToTheWholeRegion) {
  MonitorRig rig(meter::testing::converted_cluster(), GetParam(), 4);
  ASSERT_TRUE(rig.monitor->on()) << rig.monitor->off_reason();
  int needles = 0, turned_checked = 0;
  std::vector<double> old_angle(rig.scene.integrity.regions.size(), std::nan(""));
  for (int step = 0; step <= 10; ++step) {
    for (const auto& f : rig.frame(rig.at(step / 10.0))) ADD_FAILURE() << "false alarm at step " << step << ": " << f.describe();
    const Image frame = rig.renderer->read();
    const auto expected = meter::engine::expected_states(rig.scene.integrity, rig.scene, *rig.evaluator);
    for (std::size_t i = 0; i < rig.scene.integrity.regions.size(); ++i) {
      const SafetyRegion& r = rig.scene.integrity.regions[i];
      if (r.kind != SafetyKind::Needle || !expected[i].known) continue;
      const double e = expected[i].angle_deg;
      ++needles;
      // Right: decided, with the whole region's verdict and needle pixels.
      meter::engine::NeedlePixels in_window;
      const auto decided = window_verdict(r, frame, e, &in_window);
      const auto full = meter::engine::check_needle(r, whole(frame), e);
      ASSERT_TRUE(full.ok) << r.name << " at step " << step << ": " << full.seen;
      ASSERT_TRUE(decided.has_value()) << r.name << " at step " << step << " was not decided by its window";
      EXPECT_EQ(decided->seen, full.seen) << r.name;
      EXPECT_EQ(in_window, meter::engine::needle_pixels(r, whole(frame), r.rect)) << r.name;
      // At an old angle (the frame of the step before, as a stale needle shows it): not passed.
      if (!std::isnan(old_angle[i]) && std::abs(old_angle[i] - e) > r.needle.tolerance_deg) {
        EXPECT_FALSE(window_verdict(r, frame, old_angle[i]).has_value()) << r.name << " at an old angle, step " << step;
        EXPECT_FALSE(meter::engine::check_needle(r, whole(frame), old_angle[i]).ok);
      }
      old_angle[i] = e;
      // Turned 3 degrees either way: not passed by the window; the whole region fails it.
      if (r.name == "Speedo_Needle") {
        for (double deg : {3.0, -3.0}) {
          const Image off = turned(frame, r, deg);
          const auto whole_verdict = meter::engine::check_needle(r, whole(off), e);
          if (!whole_verdict.ok) {
            ++turned_checked;
            EXPECT_FALSE(window_verdict(r, off, e).has_value()) << "turned " << deg << " deg at step " << step;
          }
        }
      }
    }
  }
  EXPECT_GT(needles, 30);
  // The turned copies the whole region catches (all but where the dial's end stops the turn).
  EXPECT_GE(turned_checked, 16);
  // Frame by frame over these 11 frames, the monitor read each needle whole only for its first
  // read and at most one heartbeat (the first heartbeats are staggered, some come early): never
  // because a window could not decide a right needle.
  std::size_t needle_regions = 0;
  for (const auto& r : rig.scene.integrity.regions) needle_regions += r.kind == SafetyKind::Needle;
  EXPECT_LE(rig.monitor->needles_read_whole(), 2 * needle_regions);
}

INSTANTIATE_TEST_SUITE_P(Both, NeedleWindow, ::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                         [](const auto& info) { return std::string(meter::platform::to_string(info.param)); });

}  // namespace
