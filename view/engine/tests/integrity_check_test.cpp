// The pure integrity checks on synthetic frames (no GL): telltale looks, needle angles read from
// pixels, readouts against a reference, region hashes, views of a region alone; and the expected
// states read from the binding evaluator of the dial test scene.
#include <gtest/gtest.h>

#include <cmath>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/engine/integrity_check.hpp"
#include "meter/platform/image.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::engine;

namespace {

RgbaView view_of(const platform::Image& img) { return {img.rgba.data(), img.width, img.height, 0, 0, 0}; }

void fill(platform::Image& img, const PixelRect& r, std::uint8_t cr, std::uint8_t cg, std::uint8_t cb) {
  for (int y = r.y; y < r.y + r.height; ++y)
    for (int x = r.x; x < r.x + r.width; ++x) {
      auto* p = img.pixel(x, y);
      p[0] = cr, p[1] = cg, p[2] = cb;
    }
}

SafetyRegion lamp() {
  SafetyRegion r;
  r.name = "TT_Test";
  r.kind = SafetyKind::Telltale;
  r.rect = {10, 8, 6, 4};
  r.telltale.mask.assign(24, 0);
  for (int i = 6; i < 18; ++i) r.telltale.mask[std::size_t(i)] = 1;  // rows 1 and 2 of the rect
  r.telltale.looks = {{"on", true, {0, 230, 30}}, {"off", false, {10, 10, 10}}};
  r.telltale.tolerance = 12;
  return r;
}

// A needle drawn as a 3 px wide orange ray from the pivot, angle clockwise from up.
void draw_needle(platform::Image& img, double px, double py, double angle_deg, double length) {
  const double a = angle_deg * M_PI / 180.0, ux = std::sin(a), uy = -std::cos(a);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double dx = x + 0.5 - px, dy = y + 0.5 - py;
      const double along = dx * ux + dy * uy, across = std::abs(dx * uy - dy * ux);
      if (along >= 0 && along <= length && across <= 1.5) {
        auto* p = img.pixel(x, y);
        p[0] = 240, p[1] = 90, p[2] = 10;
      }
    }
}

SafetyRegion needle() {
  SafetyRegion r;
  r.name = "Needle";
  r.kind = SafetyKind::Needle;
  r.rect = {10, 10, 81, 81};
  r.needle.pivot_x = 50.5, r.needle.pivot_y = 50.5;
  r.needle.r_min = 10, r.needle.r_max = 38;
  r.needle.color_min = {200, 40, 0}, r.needle.color_max = {255, 140, 60};
  r.needle.min_pixels = 20;
  r.needle.samples = {{0.0, 0.0, -120.0}, {10.0, 260.0, 120.0}};
  r.needle.tolerance_deg = 1.0;
  return r;
}

}  // namespace

TEST(IntegrityCheck, TelltaleLitAndUnlitAreTellApart) {
  platform::Image img(40, 20, 10, 10, 10);
  const SafetyRegion r = lamp();
  EXPECT_TRUE(check_telltale(r, view_of(img), false).ok);
  const Verdict lit_expected = check_telltale(r, view_of(img), true);
  EXPECT_FALSE(lit_expected.ok);
  EXPECT_NE(lit_expected.seen.find("not lit"), std::string::npos) << lit_expected.seen;
  EXPECT_NEAR(lit_expected.difference, 220.0, 1e-9);  // green 230 vs 10
  fill(img, {10, 9, 6, 2}, 0, 230, 30);
  EXPECT_TRUE(check_telltale(r, view_of(img), true).ok);
  EXPECT_FALSE(check_telltale(r, view_of(img), false).ok);
}

TEST(IntegrityCheck, TelltaleOfAnUnknownColourFailsEitherWay) {
  platform::Image img(40, 20, 10, 10, 10);
  const SafetyRegion r = lamp();
  fill(img, {10, 9, 6, 2}, 230, 30, 0);  // red instead of green
  for (bool lit : {true, false}) {
    const Verdict v = check_telltale(r, view_of(img), lit);
    EXPECT_FALSE(v.ok);
    EXPECT_NE(v.seen.find("no known look"), std::string::npos) << v.seen;
  }
  // Just inside the tolerance (12 in the worst channel) still reads as the look.
  fill(img, {10, 9, 6, 2}, 11, 242, 30);
  EXPECT_TRUE(check_telltale(r, view_of(img), true).ok);
  fill(img, {10, 9, 6, 2}, 0, 243, 30);
  EXPECT_FALSE(check_telltale(r, view_of(img), true).ok);
}

TEST(IntegrityCheck, NeedleAngleIsReadFromPixels) {
  const SafetyRegion r = needle();
  for (double angle : {-120.0, -45.0, 0.0, 30.0, 119.0}) {
    platform::Image img(100, 100, 20, 20, 24);
    draw_needle(img, 50.5, 50.5, angle, 40);
    const auto seen = needle_angle(r, view_of(img));
    ASSERT_TRUE(seen.has_value());
    EXPECT_NEAR(*seen, angle, 0.3) << "a symmetric 3 px ray's centroid lies on its axis";
  }
}

TEST(IntegrityCheck, NeedleThreeDegreesOffIsCaught) {
  const SafetyRegion r = needle();
  const double time = 6.25;  // -120 + 240 * 6.25 / 10 = 30 deg
  EXPECT_NEAR(expected_angle(r.needle, time), 30.0, 1e-12);
  EXPECT_DOUBLE_EQ(expected_angle(r.needle, -1.0), -120.0);  // clamped
  EXPECT_DOUBLE_EQ(expected_angle(r.needle, 11.0), 120.0);
  platform::Image good(100, 100, 20, 20, 24), bad(100, 100, 20, 20, 24), none(100, 100, 20, 20, 24);
  draw_needle(good, 50.5, 50.5, 30.0, 40);
  draw_needle(bad, 50.5, 50.5, 33.0, 40);
  EXPECT_TRUE(check_needle(r, view_of(good), 30.0).ok);
  const Verdict v = check_needle(r, view_of(bad), 30.0, "162.50");
  EXPECT_FALSE(v.ok);
  EXPECT_NEAR(v.difference, 3.0, 0.3);
  EXPECT_NE(v.expected.find("162.50 at 30.00 deg"), std::string::npos) << v.expected;
  const Verdict missing = check_needle(r, view_of(none), 30.0);
  EXPECT_FALSE(missing.ok);
  EXPECT_NE(missing.seen.find("no needle"), std::string::npos);
}

TEST(IntegrityCheck, ARegionReadBackAloneGivesTheSameVerdict) {
  const SafetyRegion r = needle();
  platform::Image img(100, 100, 20, 20, 24);
  draw_needle(img, 50.5, 50.5, -44.0, 40);
  // Copy only the region's pixels, as the monitor reads them back.
  std::vector<std::uint8_t> part;
  for (int y = r.rect.y; y < r.rect.y + r.rect.height; ++y)
    part.insert(part.end(), img.pixel(r.rect.x, y), img.pixel(r.rect.x, y) + 4 * r.rect.width);
  const RgbaView region_view{part.data(), r.rect.width, r.rect.height, r.rect.x, r.rect.y, 0};
  const Verdict whole = check_needle(r, view_of(img), -44.0), alone = check_needle(r, region_view, -44.0);
  EXPECT_TRUE(alone.ok);
  EXPECT_EQ(whole.seen, alone.seen);
  EXPECT_EQ(region_hash(r, view_of(img)), region_hash(r, region_view));
  // A view that misses part of the region is refused, never read out of range.
  const RgbaView short_view{part.data(), r.rect.width, r.rect.height - 1, r.rect.x, r.rect.y, 0};
  const Verdict v = check_needle(r, short_view, -44.0);
  EXPECT_FALSE(v.ok);
  EXPECT_NE(v.seen.find("pixels not available"), std::string::npos) << v.seen;
}

// A window's bands copied out of a frame, as the monitor reads a needle's window back.
struct WindowRead {
  std::vector<PixelRect> bands;
  std::vector<std::vector<std::uint8_t>> bytes;
  std::vector<RgbaView> views;
  long long area = 0;
};
WindowRead read_window(const platform::Image& img, std::vector<PixelRect> bands) {
  WindowRead out;
  out.bands = std::move(bands);
  for (const auto& w : out.bands) {
    auto& b = out.bytes.emplace_back();
    for (int y = w.y; y < w.y + w.height; ++y) b.insert(b.end(), img.pixel(w.x, y), img.pixel(w.x, y) + 4 * w.width);
    out.area += (long long)w.width * w.height;
  }
  for (std::size_t j = 0; j < out.bands.size(); ++j) {
    const auto& w = out.bands[j];
    out.views.push_back({out.bytes[j].data(), w.width, w.height, w.x, w.y, 0});
  }
  return out;
}

// The window check decides only where the whole rect's check gives the same verdict: a right
// needle at every angle of the sweep is decided in its window with the very angle the whole rect
// gives (the same pixels), and so are its freeze key's sums.
TEST(IntegrityCheck, NeedleWindowDecidesARightNeedleExactlyAsTheWholeRect) {
  const SafetyRegion r = needle();
  for (double angle = -120.0; angle <= 120.0; angle += 7.5) {
    for (double off : {0.0, 0.2, -0.2}) {
      platform::Image img(100, 100, 20, 20, 24);
      draw_needle(img, 50.5, 50.5, angle + off, 40);
      const WindowRead part = read_window(img, needle_window(r, angle, 4));
      ASSERT_FALSE(part.bands.empty());
      EXPECT_LT(part.area, r.rect.width * r.rect.height) << angle;
      NeedlePixels in_window;
      const auto decided = check_needle_window(r, part.views, part.bands, angle, &in_window);
      ASSERT_TRUE(decided.has_value()) << "a needle " << off << " deg off at " << angle << " deg was cut by its window";
      const Verdict whole = check_needle(r, view_of(img), angle);
      EXPECT_TRUE(decided->ok);
      EXPECT_EQ(decided->seen, whole.seen);
      EXPECT_DOUBLE_EQ(decided->difference, whole.difference);
      EXPECT_EQ(in_window, needle_pixels(r, view_of(img), r.rect));
    }
  }
}

// What the window cannot vouch for it leaves to the whole rect (nullopt): a needle 3 degrees off
// (the tolerance is 1), a needle at an old angle, no needle, a needle cut by the window's side;
// the whole rect's check then fails each of them as before.
TEST(IntegrityCheck, NeedleWindowLeavesEveryWrongNeedleToTheWholeRect) {
  const SafetyRegion r = needle();
  for (double expected : {-100.0, -30.0, 0.0, 45.0, 110.0}) {
    const auto w = needle_window(r, expected, 4);
    for (double seen : {expected + 3.0, expected - 3.0, expected + 1.5, expected - 60.0, expected + 90.0}) {
      platform::Image img(100, 100, 20, 20, 24);
      draw_needle(img, 50.5, 50.5, seen, 40);
      const WindowRead part = read_window(img, w);
      EXPECT_FALSE(check_needle_window(r, part.views, part.bands, expected).has_value())
          << "needle at " << seen << " for " << expected;
      EXPECT_FALSE(check_needle(r, view_of(img), expected).ok) << "needle at " << seen << " for " << expected;
    }
    platform::Image none(100, 100, 20, 20, 24);
    const WindowRead empty = read_window(none, w);
    EXPECT_FALSE(check_needle_window(r, empty.views, empty.bands, expected).has_value());
  }
  // A right needle wider than the window allows for is cut by its sides: not decided either.
  platform::Image wide(100, 100, 20, 20, 24);
  for (double d = -3.0; d <= 3.0; d += 0.5) draw_needle(wide, 50.5 + d * std::cos(0.3), 50.5 + d * std::sin(0.3), 0.0, 40);
  const WindowRead narrow = read_window(wide, needle_window(r, 0.0, 0));
  EXPECT_FALSE(check_needle_window(r, narrow.views, narrow.bands, 0.0).has_value());
  // Views that do not hold the bands are not read.
  std::vector<RgbaView> short_views = narrow.views;
  short_views.back().height -= 1;
  EXPECT_FALSE(check_needle_window(r, short_views, narrow.bands, 0.0).has_value());
  EXPECT_FALSE(check_needle_window(r, std::span<const RgbaView>(narrow.views).first(narrow.views.size() - 1), narrow.bands, 0.0)
                   .has_value());
}

TEST(IntegrityCheck, RegionHashSeesOnlyTheRegion) {
  const SafetyRegion r = lamp();
  platform::Image img(40, 20, 10, 10, 10);
  const auto h0 = region_hash(r, view_of(img));
  img.pixel(0, 0)[0] = 99;  // outside the rect
  EXPECT_EQ(region_hash(r, view_of(img)), h0);
  img.pixel(15, 11)[2] = 11;  // inside (its last pixel), not in the mask
  EXPECT_NE(region_hash(r, view_of(img)), h0);
}

TEST(IntegrityCheck, ReadoutCountsInkPixelsThatDiffer) {
  SafetyRegion r;
  r.name = "Text_Speed";
  r.kind = SafetyKind::Readout;
  r.rect = {4, 4, 20, 10};
  r.readout.tolerance_pixels = 3;
  platform::Image ref(30, 20, 0, 0, 0), frame(30, 20, 0, 0, 0);
  fill(ref, {6, 6, 4, 6}, 240, 240, 240);
  fill(frame, {6, 6, 4, 6}, 240, 240, 240);
  frame.pixel(6, 6)[0] = 200;  // antialiasing-sized change: below the ink step
  EXPECT_TRUE(check_readout(r, view_of(frame), view_of(ref), "1").ok);
  fill(frame, {12, 6, 4, 6}, 240, 240, 240);  // a second glyph: 24 pixels of ink more
  const Verdict v = check_readout(r, view_of(frame), view_of(ref), "1");
  EXPECT_FALSE(v.ok);
  EXPECT_DOUBLE_EQ(v.difference, 24.0);
  RegionExpectation e;
  e.text = "1";
  EXPECT_FALSE(check_region(r, view_of(frame), e, nullptr).ok);  // no reference: not passed
}

TEST(IntegrityCheck, ExpectationsComeFromTheEvaluatorsOutputs) {
  const Scene scene = [] {
    convert::ConvertOptions o;
    o.optimize = false;
    return convert::convert_gltf(test::write_dial_scene(test::scratch_dir("integrity_expect")),
                                 meter::config::parse_scene_config(test::dial_config_json()), o).scene;
  }();
  IntegrityTable t;
  SafetyRegion tt = lamp();
  tt.name = "TT_ABS";
  tt.bindings = {1};  // emissive TT_ABS_On
  SafetyRegion nd = needle();
  nd.bindings = {0};
  nd.needle.animation = "SpeedNeedle";
  nd.needle.samples = {{0.0, 0.0, -120.0}, {10.8333333, 260.0, 120.0}};
  SafetyRegion tx;
  tx.name = "Text_Speed";
  tx.kind = SafetyKind::Readout;
  tx.node = "Text_Speed";
  tx.bindings = {3};
  t.regions = {tt, nd, tx};
  BindingEvaluator ev(scene);
  protocol::SignalTable values;
  values.set(1, {130.0, protocol::SignalStatus::Valid, ""});  // Vehicle.Speed
  const int abs_id = bound_signal_id(scene.config.bindings[1]).value();
  values.set(protocol::SignalId(abs_id), {0.0, protocol::SignalStatus::Valid, ""});
  ev.update(values, true, -1.0);
  auto e = expected_states(t, scene, ev);
  ASSERT_EQ(e.size(), 3u);
  EXPECT_TRUE(e[0].known);
  EXPECT_FALSE(e[0].lit);
  EXPECT_NEAR(e[1].angle_deg, 0.0, 1e-6);
  EXPECT_DOUBLE_EQ(e[1].value, 130.0);
  EXPECT_EQ(e[2].text, "130");
  EXPECT_TRUE(e[2].known);
  // The ABS signal lost: its failsafe value 1 lights the lamp, as the binding draws it.
  values.set(protocol::SignalId(abs_id), {0.0, protocol::SignalStatus::NotAvailable, ""});
  ev.update(values, true, -1.0);
  EXPECT_TRUE(expected_state(t.regions[0], scene, ev).lit);
}
