// The pixel checks of display integrity: telltale looks, needle angles, readout glyphs, region
// hashes. Pure functions over an RgbaView (meter/engine/integrity_check.hpp).
#include "meter/engine/integrity_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace meter::engine {
namespace {

std::string fmt(const char* f, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, a);
  return buf;
}

std::string rgb_text(const std::array<double, 3>& c) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.0f,%.0f,%.0f", c[0], c[1], c[2]);
  return buf;
}

std::string rect_text(const PixelRect& r) {
  return std::to_string(r.width) + "x" + std::to_string(r.height) + "+" + std::to_string(r.x) + "+" +
         std::to_string(r.y);
}

// The verdict for a view that does not hold the whole region.
Verdict uncovered(const SafetyRegion& region, const RgbaView& frame, std::string expected) {
  Verdict v;
  v.expected = std::move(expected);
  v.seen = "pixels not available: region " + rect_text(region.rect) + " outside the " +
           std::to_string(frame.width) + "x" + std::to_string(frame.height) + " view at " +
           std::to_string(frame.x0) + "," + std::to_string(frame.y0);
  v.difference = 0.0;
  return v;
}

double channel_distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

}  // namespace

double wrap_degrees(double d) {
  d = std::fmod(d, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d < -180.0) d += 360.0;
  return d;
}

bool RgbaView::covers(const PixelRect& r) const {
  if (data == nullptr || r.empty() || width <= 0 || height <= 0) return false;
  return r.x >= x0 && r.y >= y0 && r.x + r.width <= x0 + width && r.y + r.height <= y0 + height;
}

const std::uint8_t* RgbaView::pixel(int x, int y) const {
  const std::size_t row = stride > 0 ? std::size_t(stride) : std::size_t(width) * 4;
  return data + std::size_t(y - y0) * row + std::size_t(x - x0) * 4;
}

std::array<double, 3> lamp_mean(const SafetyRegion& region, const RgbaView& frame) {
  const PixelRect& r = region.rect;
  const auto& mask = region.telltale.mask;
  std::array<double, 3> sum{0, 0, 0};
  std::size_t n = 0;
  for (int y = 0; y < r.height; ++y) {
    for (int x = 0; x < r.width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(r.width) + std::size_t(x);
      if (i >= mask.size() || mask[i] == 0) continue;
      const std::uint8_t* p = frame.pixel(r.x + x, r.y + y);
      for (int c = 0; c < 3; ++c) sum[std::size_t(c)] += p[c];
      ++n;
    }
  }
  if (n > 0) {
    for (auto& s : sum) s /= double(n);
  }
  return sum;
}

Verdict check_telltale(const SafetyRegion& region, const RgbaView& frame, bool expected_lit) {
  const std::string expected = expected_lit ? "lit" : "not lit";
  if (!frame.covers(region.rect)) return uncovered(region, frame, expected);
  const auto mean = lamp_mean(region, frame);
  // Nearest look overall (what the frame shows) and nearest look of the expected state.
  const TelltaleLook* nearest = nullptr;
  const TelltaleLook* nearest_expected = nullptr;
  double d_nearest = 1e9, d_expected = 1e9;
  for (const auto& look : region.telltale.looks) {
    const double d = channel_distance(mean, look.mean);
    if (d < d_nearest) d_nearest = d, nearest = &look;
    if (look.lit == expected_lit && d < d_expected) d_expected = d, nearest_expected = &look;
  }
  Verdict v;
  v.expected = expected + (nearest_expected ? " (" + nearest_expected->name + " " + rgb_text(nearest_expected->mean) + ")" : "");
  v.difference = d_expected;
  if (nearest == nullptr || nearest_expected == nullptr) {
    v.seen = "mean " + rgb_text(mean) + "; the region has no look for this state";
    return v;
  }
  v.ok = nearest->lit == expected_lit && d_expected <= region.telltale.tolerance;
  if (d_nearest <= region.telltale.tolerance) {
    v.seen = std::string(nearest->lit ? "lit" : "not lit") + " (" + nearest->name + ", mean " + rgb_text(mean) + ")";
  } else {
    v.seen = "no known look (mean " + rgb_text(mean) + ", nearest " + nearest->name + " at " + fmt("%.1f", d_nearest) + ")";
  }
  return v;
}

double expected_angle(const NeedleModel& needle, double time) {
  const auto& s = needle.samples;
  if (s.empty()) return 0.0;
  if (time <= s.front().time) return s.front().angle_deg;
  if (time >= s.back().time) return s.back().angle_deg;
  auto hi = std::lower_bound(s.begin(), s.end(), time, [](const NeedleSample& a, double t) { return a.time < t; });
  auto lo = std::prev(hi);
  const double span = hi->time - lo->time;
  if (span <= 0.0) return hi->angle_deg;
  return lo->angle_deg + (hi->angle_deg - lo->angle_deg) * (time - lo->time) / span;
}

namespace {

PixelRect intersect(const PixelRect& a, const PixelRect& b) {
  const int x0 = std::max(a.x, b.x), y0 = std::max(a.y, b.y);
  const int x1 = std::min(a.x + a.width, b.x + b.width), y1 = std::min(a.y + a.height, b.y + b.height);
  return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

// Whether the pixels around (x, y) within kNeedleWindowEdge are all inside the bands or outside
// the rect. Band j holds (x, y); bands are ordered along one axis and longer than twice the edge,
// so the square around it reaches at most its neighbours, and its 3 x 3 corner, side and centre
// points decide (each band is a rectangle: a row or column of the square is inside where both
// its ends are).
bool deep_inside(int x, int y, std::span<const PixelRect> bands, std::size_t j, const PixelRect& rect) {
  const PixelRect& b = bands[j];
  constexpr int e = kNeedleWindowEdge;
  if (x - e >= b.x && x + e < b.x + b.width && y - e >= b.y && y + e < b.y + b.height) return true;  // most pixels
  const std::size_t lo = j > 0 ? j - 1 : 0, hi = std::min(bands.size(), j + 2);
  for (int dy = -kNeedleWindowEdge; dy <= kNeedleWindowEdge; dy += kNeedleWindowEdge) {
    for (int dx = -kNeedleWindowEdge; dx <= kNeedleWindowEdge; dx += kNeedleWindowEdge) {
      const int px = x + dx, py = y + dy;
      if (!rect.contains(px, py)) continue;
      bool in = false;
      for (std::size_t k = lo; k < hi && !in; ++k) in = bands[k].contains(px, py);
      if (!in) return false;
    }
  }
  return true;
}

}  // namespace

NeedlePixels needle_pixels(const SafetyRegion& region, std::span<const RgbaView> views, std::span<const PixelRect> bands) {
  const NeedleModel& m = region.needle;
  // Cheapest test first: most of a needle's box is dial face, refused by its colour alone; the
  // ring (squared radii, no square root) and the sector (one atan2) are tested only for pixels of
  // the needle's colour. The pixels counted are the ones the ring-sector-colour rule selects in
  // any order (a ring edge decided on dx^2 + dy^2 instead of hypot can differ only by rounding at
  // exactly r_min or r_max).
  const double r_min2 = m.r_min > 0.0 ? m.r_min * m.r_min : 0.0, r_max2 = m.r_max * m.r_max;
  const bool sector = m.sector_half_deg < 180.0;
  NeedlePixels n;
  for (std::size_t j = 0; j < bands.size() && j < views.size(); ++j) {
    const PixelRect b = intersect(bands[j], region.rect);
    if (b.empty() || !views[j].covers(b)) continue;
    for (int y = b.y; y < b.y + b.height; ++y) {
      const double dy = y + 0.5 - m.pivot_y;
      if (dy * dy > r_max2) continue;
      const std::uint8_t* p = views[j].pixel(b.x, y);
      for (int x = b.x; x < b.x + b.width; ++x, p += 4) {
        if (p[0] < m.color_min[0] || p[0] > m.color_max[0] || p[1] < m.color_min[1] || p[1] > m.color_max[1] ||
            p[2] < m.color_min[2] || p[2] > m.color_max[2]) {
          continue;
        }
        const double dx = x + 0.5 - m.pivot_x;
        const double rr2 = dx * dx + dy * dy;
        if (rr2 < r_min2 || rr2 > r_max2) continue;
        if (sector && std::abs(wrap_degrees(std::atan2(dx, -dy) * 180.0 / M_PI - m.sector_center_deg)) > m.sector_half_deg) {
          continue;
        }
        ++n.count, n.sum_x += x, n.sum_y += y;
        if (!deep_inside(x, y, bands, j, region.rect)) ++n.at_edge;
      }
    }
  }
  return n;
}

NeedlePixels needle_pixels(const SafetyRegion& region, const RgbaView& frame, const PixelRect& within) {
  return needle_pixels(region, std::span<const RgbaView>(&frame, 1), std::span<const PixelRect>(&within, 1));
}

std::optional<double> centroid_angle(const NeedleModel& m, const NeedlePixels& n) {
  if (n.count < std::max(1, m.min_pixels)) return std::nullopt;
  // The centroid relative to the pivot (pixel centres); screen direction (sin a, -cos a) for
  // angle a clockwise from up, y pointing down.
  const double cx = double(n.sum_x) / n.count + 0.5 - m.pivot_x, cy = double(n.sum_y) / n.count + 0.5 - m.pivot_y;
  return std::atan2(cx, -cy) * 180.0 / M_PI;
}

std::optional<double> needle_angle(const SafetyRegion& region, const RgbaView& frame, int* pixels) {
  const NeedlePixels n = needle_pixels(region, frame, region.rect);
  if (pixels) *pixels = n.count;
  return centroid_angle(region.needle, n);
}

namespace {

// check_needle's verdict from the needle pixels counted.
Verdict needle_verdict(const SafetyRegion& region, const NeedlePixels& n, double expected_deg, const std::string& label) {
  Verdict v;
  v.expected = (label.empty() ? std::string() : label + " at ") + fmt("%.2f deg", expected_deg);
  const auto seen = centroid_angle(region.needle, n);
  if (!seen) {
    v.seen = "no needle (" + std::to_string(n.count) + " needle pixels, at least " +
             std::to_string(region.needle.min_pixels) + " needed)";
    v.difference = 180.0;
    return v;
  }
  // The samples are unwrapped; compare on the circle.
  const double d = wrap_degrees(*seen - expected_deg);
  v.difference = std::abs(d);
  v.seen = fmt("%.2f deg", expected_deg + d);
  v.ok = v.difference <= region.needle.tolerance_deg;
  return v;
}

}  // namespace

Verdict check_needle(const SafetyRegion& region, const RgbaView& frame, double expected_deg, const std::string& label) {
  if (!frame.covers(region.rect))
    return uncovered(region, frame, (label.empty() ? std::string() : label + " at ") + fmt("%.2f deg", expected_deg));
  return needle_verdict(region, needle_pixels(region, frame, region.rect), expected_deg, label);
}

std::vector<PixelRect> needle_window(const SafetyRegion& region, double expected_deg, int half_width) {
  const NeedleModel& m = region.needle;
  const PixelRect& r = region.rect;
  const double a = expected_deg * M_PI / 180.0, ux = std::sin(a), uy = -std::cos(a);
  const double r_min = std::max(0.0, m.r_min);
  const double margin = m.r_max * std::sin(kNeedleWindowSlackDeg * M_PI / 180.0) + std::max(0, half_width) + kNeedleWindowEdge;
  if (!std::isfinite(margin) || !std::isfinite(m.pivot_x) || !std::isfinite(m.pivot_y) || !std::isfinite(a)) return {r};
  // The segment in (major, cross) coordinates: the major axis is the one it runs along most.
  const bool along_x = std::abs(ux) >= std::abs(uy);
  const double pa = along_x ? m.pivot_x : m.pivot_y, pc = along_x ? m.pivot_y : m.pivot_x;
  const double ua = along_x ? ux : uy, uc = along_x ? uy : ux;
  const double t_a = pa + r_min * ua, t_b = pa + m.r_max * ua, c_a = pc + r_min * uc, c_b = pc + m.r_max * uc;
  const double lo = std::min(t_a, t_b), hi = std::max(t_a, t_b);
  // The cross coordinate of the segment at major coordinate t (clamped to its ends).
  auto cross = [&](double t) {
    if (t_b == t_a) return c_a;
    const double f = std::clamp((t - t_a) / (t_b - t_a), 0.0, 1.0);
    return c_a + f * (c_b - c_a);
  };
  const int rect_lo = along_x ? r.x : r.y, rect_hi = along_x ? r.x + r.width : r.y + r.height;
  const int cross_lo = along_x ? r.y : r.x, cross_hi = along_x ? r.y + r.height : r.x + r.width;
  auto clamp_int = [](double v, int a0, int a1) { return int(std::clamp(v, double(a0), double(a1))); };
  const int start = clamp_int(std::floor(lo - margin), rect_lo, rect_hi), end = clamp_int(std::ceil(hi + margin), rect_lo, rect_hi);
  std::vector<PixelRect> bands;
  for (int t0 = start, t1 = start; t0 < end; t0 = t1) {
    // A last piece shorter than the edge test reaches joins this band (deep_inside looks at the
    // neighbours only).
    t1 = std::min(end, t0 + kNeedleWindowBand);
    if (end - t1 <= 2 * kNeedleWindowEdge) t1 = end;
    // The widened segment over [t0, t1): its pieces within the margin of the band, widened.
    const double e0 = cross(std::clamp(t0 - margin, lo, hi)), e1 = cross(std::clamp(t1 + margin, lo, hi));
    const int c0 = clamp_int(std::floor(std::min(e0, e1) - margin), cross_lo, cross_hi);
    const int c1 = clamp_int(std::ceil(std::max(e0, e1) + margin), cross_lo, cross_hi);
    if (c1 <= c0) continue;
    bands.push_back(along_x ? PixelRect{t0, c0, t1 - t0, c1 - c0} : PixelRect{c0, t0, c1 - c0, t1 - t0});
  }
  return bands;
}

std::optional<Verdict> check_needle_window(const SafetyRegion& region, std::span<const RgbaView> views,
                                           std::span<const PixelRect> bands, double expected_deg, NeedlePixels* pixels) {
  if (bands.empty() || views.size() != bands.size()) return std::nullopt;
  for (std::size_t j = 0; j < bands.size(); ++j)
    if (!views[j].covers(intersect(bands[j], region.rect))) return std::nullopt;
  const NeedlePixels n = needle_pixels(region, views, bands);
  if (pixels) *pixels = n;
  if (n.at_edge > 0) return std::nullopt;
  Verdict v = needle_verdict(region, n, expected_deg, "");
  if (!v.ok) return std::nullopt;
  return v;
}

Verdict check_readout(const SafetyRegion& region, const RgbaView& frame, const RgbaView& reference,
                      const std::string& expected_text) {
  const std::string expected = "\"" + expected_text + "\"";
  if (!frame.covers(region.rect)) return uncovered(region, frame, expected);
  if (!reference.covers(region.rect)) {
    Verdict v = uncovered(region, reference, expected);
    v.seen = "reference " + v.seen;
    return v;
  }
  const PixelRect& r = region.rect;
  int differing = 0;
  for (int y = r.y; y < r.y + r.height; ++y) {
    for (int x = r.x; x < r.x + r.width; ++x) {
      const std::uint8_t* a = frame.pixel(x, y);
      const std::uint8_t* b = reference.pixel(x, y);
      int d = 0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a[c]) - int(b[c])));
      if (d > kReadoutInkStep) ++differing;
    }
  }
  Verdict v;
  v.expected = expected;
  v.difference = differing;
  v.ok = differing <= region.readout.tolerance_pixels;
  v.seen = v.ok ? expected : std::to_string(differing) + " pixels differ from " + expected + " as the engine draws it";
  return v;
}

Verdict check_region(const SafetyRegion& region, const RgbaView& frame, const RegionExpectation& e,
                     const RgbaView* reference) {
  switch (region.kind) {
    case SafetyKind::Telltale: return check_telltale(region, frame, e.lit);
    case SafetyKind::Needle: return check_needle(region, frame, e.angle_deg, fmt("%.2f", e.value));
    case SafetyKind::Readout:
      if (reference == nullptr) {
        Verdict v;
        v.expected = "\"" + e.text + "\"";
        v.seen = "no reference render of the expected text";
        return v;
      }
      return check_readout(region, frame, *reference, e.text);
  }
  return {};
}

std::uint64_t region_hash(const SafetyRegion& region, const RgbaView& frame) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  if (!frame.covers(region.rect)) return h;
  const PixelRect& r = region.rect;
  for (int y = r.y; y < r.y + r.height; ++y) {
    const std::uint8_t* p = frame.pixel(r.x, y);
    for (int i = 0; i < r.width * 4; ++i) {
      h ^= p[i];
      h *= 0x100000001b3ull;
    }
  }
  return h;
}

}  // namespace meter::engine
