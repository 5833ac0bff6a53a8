#include "meter/runner/integrity_monitor.hpp"

#include <utility>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "meter/platform/render_target.hpp"

namespace meter::runner {

namespace {

engine::RgbaView view_of(const platform::Image& image, const bridge::PixelRect& rect) {
  engine::RgbaView v;
  v.data = image.rgba.data();
  v.width = image.width, v.height = image.height;
  v.x0 = rect.x, v.y0 = rect.y;
  return v;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", v);
  return text;
}

// What the expectation says, for a frozen fault's message.
std::string look_text(const bridge::SafetyRegion& region, const engine::RegionExpectation& e) {
  switch (region.kind) {
    case bridge::SafetyKind::Telltale: return e.lit ? "on" : "off";
    case bridge::SafetyKind::Needle: return number(e.angle_deg) + " deg";
    case bridge::SafetyKind::Readout: return "\"" + e.text + "\"";
  }
  return "?";
}

}  // namespace

std::string IntegrityFault::describe() const {
  std::string s = region + " (" + bridge::to_string(kind) + "): ";
  if (frozen) s += "frozen: ";
  return s + "expected " + expected + ", seen " + seen + ", difference " + number(difference);
}

bool look_changed(const bridge::SafetyRegion& region, const engine::RegionExpectation& a,
                  const engine::RegionExpectation& b) {
  if (a.known != b.known) return true;
  if (!a.known) return false;
  switch (region.kind) {
    case bridge::SafetyKind::Telltale: return a.lit != b.lit;
    case bridge::SafetyKind::Needle:
      return std::abs(a.angle_deg - b.angle_deg) > std::max(1.0, region.needle.tolerance_deg);
    case bridge::SafetyKind::Readout: return a.text != b.text;
  }
  return false;
}

namespace {

// What a needle shows, as memory bytes: its needle pixels' count and sums.
std::vector<std::uint8_t> needle_key(const engine::NeedlePixels& n) {
  std::vector<std::uint8_t> key(sizeof n.count + sizeof n.sum_x + sizeof n.sum_y);
  std::memcpy(key.data(), &n.count, sizeof n.count);
  std::memcpy(key.data() + sizeof n.count, &n.sum_x, sizeof n.sum_x);
  std::memcpy(key.data() + sizeof n.count + sizeof n.sum_x, &n.sum_y, sizeof n.sum_y);
  return key;
}

}  // namespace

std::vector<IntegrityFault> judge_reads(const bridge::IntegrityTable& table,
                                        const std::vector<engine::RegionExpectation>& expected,
                                        std::vector<RegionRead>& reads, std::vector<RegionMemory>& memory,
                                        std::vector<std::size_t>* undecided) {
  std::vector<IntegrityFault> faults;
  memory.resize(table.regions.size());
  for (std::size_t i = 0; i < table.regions.size(); ++i) {
    const bridge::SafetyRegion& r = table.regions[i];
    const engine::RegionExpectation& e = expected.at(i);
    if (!e.known || i >= reads.size() || !reads[i].read()) continue;
    RegionRead& got = reads[i];
    std::vector<engine::RgbaView> views;
    for (std::size_t k = 0; k < got.images.size() && k < got.rects.size(); ++k) views.push_back(view_of(got.images[k], got.rects[k]));
    const bool whole = got.rects.size() == 1 && got.rects.front() == r.rect;
    std::optional<engine::Verdict> verdict;
    std::vector<std::uint8_t> shown;
    if (r.kind == bridge::SafetyKind::Telltale) verdict = engine::check_telltale(r, views.front(), e.lit);
    if (r.kind == bridge::SafetyKind::Needle) {
      engine::NeedlePixels n;
      if (whole) {
        verdict = engine::check_needle(r, views.front(), e.angle_deg);
        n = engine::needle_pixels(r, views.front(), r.rect);
      } else {
        verdict = engine::check_needle_window(r, views, got.rects, e.angle_deg, &n);
        if (!verdict) {
          if (undecided) undecided->push_back(i);
          continue;
        }
      }
      shown = needle_key(n);
    } else {
      shown = std::move(got.images.front().rgba);
    }
    if (verdict && !verdict->ok)
      faults.push_back({r.name, r.kind, false, verdict->expected, verdict->seen, verdict->difference});
    // Frozen: what it shows equals what an earlier frame showed whose expectation differed in look.
    RegionMemory& m = memory[i];
    if (!m.valid || m.pixels != shown) {
      m = {true, std::move(shown), e};
    } else if (look_changed(r, m.expected, e)) {
      const double change = r.kind == bridge::SafetyKind::Needle ? std::abs(e.angle_deg - m.expected.angle_deg) : 1.0;
      faults.push_back({r.name, r.kind, true, look_text(r, e) + " (was " + look_text(r, m.expected) + ")",
                        "the same pixels", change});
      // Judged against the look these pixels had when they last changed until they change again.
    }
  }
  return faults;
}

std::vector<IntegrityFault> judge_frame(const bridge::IntegrityTable& table,
                                        const std::vector<engine::RegionExpectation>& expected,
                                        const std::vector<platform::Image>& pixels, std::vector<RegionMemory>& memory) {
  std::vector<RegionRead> reads(pixels.size());
  for (std::size_t i = 0; i < pixels.size() && i < table.regions.size(); ++i) reads[i] = {{pixels[i]}, {table.regions[i].rect}};
  return judge_reads(table, expected, reads, memory);
}

IntegrityMonitor::IntegrityMonitor(const engine::Scene& scene, int width, int height, bool enabled, bool safe_path)
    : scene_(scene), table_(scene.integrity), safe_path_(safe_path), height_(height), expectations_(table_, scene) {
  if (table_.empty()) {
    off_reason_ = "the scene has no safety regions";
  } else if (!enabled) {
    off_reason_ = "turned off (--no-integrity-monitor)";
  } else if (width != table_.width || height != table_.height) {
    off_reason_ = "the regions were measured at " + std::to_string(table_.width) + "x" + std::to_string(table_.height) +
                  ", the view draws at " + std::to_string(width) + "x" + std::to_string(height);
  } else {
    on_ = true;
  }
  if (!on_) return;
  for (const auto& r : table_.regions) boxes_.push_back(gl_box(r.rect));
  memory_.resize(table_.regions.size());
  read_at_.resize(table_.regions.size());
  read_expected_.resize(table_.regions.size());
  whole_due_.resize(table_.regions.size());
  half_width_.assign(table_.regions.size(), kStartHalfWidth);
}

void IntegrityMonitor::read_whole(std::size_t i) {
  // The first whole reads are spread over kRefreshFrames calls (region i's second one comes
  // i % kRefreshFrames calls early), so the needles' heartbeat reads do not all fall on one frame.
  const std::uint64_t early = whole_due_[i] ? 0 : i % kRefreshFrames;
  whole_due_[i] = frame_ + kRefreshFrames - early;
  ++needles_whole_;
}

namespace {

bool overlaps(const platform::PixelRegion& a, const platform::PixelRegion& b) {
  return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

bool same_expectation(const engine::RegionExpectation& a, const engine::RegionExpectation& b) {
  return a.known == b.known && a.lit == b.lit && a.angle_deg == b.angle_deg && a.text == b.text;
}

}  // namespace

platform::PixelRegion IntegrityMonitor::gl_box(const bridge::PixelRect& r) const {
  return {r.x, height_ - r.y - r.height, r.width, r.height};
}

std::vector<bridge::PixelRect> IntegrityMonitor::read_rects(std::size_t i, std::uint64_t frame) const {
  const bridge::SafetyRegion& r = table_.regions[i];
  if (r.kind != bridge::SafetyKind::Needle || !whole_due_[i] || frame >= *whole_due_[i]) return {r.rect};
  auto bands = engine::needle_window(r, expected_[i].angle_deg, half_width_[i]);
  if (bands.empty()) return {r.rect};
  return bands;
}

void IntegrityMonitor::prepare(engine::Renderer& renderer, const engine::BindingEvaluator& evaluator, bool resolve) {
  if (!on_) return;
  expectations_.evaluate(evaluator, expected_);
  prepared_ = true;
  if (!resolve) return;
  std::vector<platform::PixelRegion> boxes;
  for (std::size_t i = 0; i < table_.regions.size(); ++i)
    if (expected_[i].known)
      for (const auto& rect : read_rects(i, frame_ + 1)) boxes.push_back(gl_box(rect));
  renderer.resolve_with_frame(std::move(boxes));
}

const std::vector<IntegrityFault>& IntegrityMonitor::check(engine::Renderer& renderer,
                                                           const engine::BindingEvaluator& evaluator,
                                                           const RegionReader* reader) {
  const auto read_boxes = [&](std::span<const platform::PixelRegion> boxes) {
    return reader ? (*reader)(boxes) : renderer.read_regions(boxes);
  };
  frame_faults_.clear();
  if (!on_) return frame_faults_;
  ++frame_;
  // The state the frame was drawn from: named at prepare(), before the frame was drawn (the
  // overlapped pipeline has evaluated the next frame by the time this one is checked).
  if (!std::exchange(prepared_, false)) expectations_.evaluate(evaluator, expected_);
  const std::vector<platform::PixelRegion> written = renderer.take_written();
  // A region is read when its pixels can differ from the ones read last (the renderer drew into
  // it, or was asked to show it differently), or when it was last read kRefreshFrames ago. A
  // region nothing drives yet is not judged, so not read.
  std::vector<std::size_t> read;
  std::vector<RegionRead> reads(table_.regions.size());
  std::vector<platform::PixelRegion> boxes;
  for (std::size_t i = 0; i < table_.regions.size(); ++i) {
    const bridge::SafetyRegion& r = table_.regions[i];
    if (!expected_[i].known) continue;
    bool need = !read_at_[i] || frame_ - *read_at_[i] >= kRefreshFrames || !same_expectation(read_expected_[i], expected_[i]);
    for (std::size_t w = 0; !need && w < written.size(); ++w) need = overlaps(boxes_[i], written[w]);
    if (!need) continue;
    read_at_[i] = frame_;
    read_expected_[i] = expected_[i];
    reads[i].rects = read_rects(i, frame_);
    if (r.kind == bridge::SafetyKind::Needle && reads[i].rects.front() == r.rect) read_whole(i);
    read.push_back(i);
    for (const auto& rect : reads[i].rects) boxes.push_back(gl_box(rect));
  }
  if (read.empty()) return frame_faults_;
  ++frames_checked_;
  regions_read_ += read.size();
  std::vector<platform::Image> got = read_boxes(boxes);
  std::size_t next = 0;
  for (std::size_t i : read)
    for (std::size_t k = 0; k < reads[i].rects.size(); ++k) reads[i].images.push_back(std::move(got[next++]));
  std::vector<std::size_t> undecided;
  frame_faults_ = judge_reads(table_, expected_, reads, memory_, &undecided);
  if (!undecided.empty()) {
    // A needle its window could not decide (off, gone, cut by a side): its whole rect, judged as
    // the offline check judges it. The faults stay in table order.
    std::vector<RegionRead> again(table_.regions.size());
    boxes.clear();
    for (std::size_t i : undecided) boxes.push_back(boxes_[i]);
    got = read_boxes(boxes);
    for (std::size_t k = 0; k < undecided.size(); ++k) {
      again[undecided[k]] = {{std::move(got[k])}, {table_.regions[undecided[k]].rect}};
      read_whole(undecided[k]);
    }
    auto more = judge_reads(table_, expected_, again, memory_);
    // A needle right in its whole rect that its window could not decide is wider than the window
    // allowed for: its later windows are twice as wide (up to kMaxHalfWidth).
    for (std::size_t i : undecided)
      if (std::none_of(more.begin(), more.end(), [&](const auto& f) { return f.region == table_.regions[i].name; }))
        half_width_[i] = std::min(kMaxHalfWidth, 2 * half_width_[i]);
    frame_faults_.insert(frame_faults_.end(), more.begin(), more.end());
    std::stable_sort(frame_faults_.begin(), frame_faults_.end(), [&](const auto& a, const auto& b) {
      return region_index(a.region) < region_index(b.region);
    });
  }
  for (const auto& f : frame_faults_) {
    ++faults_;
    if (f.frozen) ++frozen_;
  }
  if (safe_path_) {
    // Once per failing region (a wrong and frozen region has two faults, one safe look).
    for (std::size_t i = 0; i < table_.regions.size(); ++i) {
      const auto& name = table_.regions[i].name;
      if (std::any_of(frame_faults_.begin(), frame_faults_.end(), [&](const auto& f) { return f.region == name; }))
        redraw_safe(renderer, i, expected_[i]);
    }
  }
  return frame_faults_;
}

std::size_t IntegrityMonitor::region_index(const std::string& name) const {
  for (std::size_t i = 0; i < table_.regions.size(); ++i)
    if (table_.regions[i].name == name) return i;
  return table_.regions.size();
}

void IntegrityMonitor::redraw_safe(engine::Renderer& renderer, std::size_t region,
                                   const engine::RegionExpectation& expected) {
  const bridge::SafetyRegion& r = table_.regions[region];
  if (r.kind == bridge::SafetyKind::Readout) return;  // no safe look for a text: reported only
  std::optional<glm::vec4> colour;
  // A telltale that must be lit: its region filled with the lit look's colour; one that must be
  // dark, and any needle, the static layer (the dial without the item).
  if (r.kind == bridge::SafetyKind::Telltale && expected.lit) {
    for (const auto& look : r.telltale.looks) {
      if (!look.lit) continue;
      colour = glm::vec4(float(platform::srgb_to_linear(look.mean[0] / 255.0)),
                         float(platform::srgb_to_linear(look.mean[1] / 255.0)),
                         float(platform::srgb_to_linear(look.mean[2] / 255.0)), 1.0f);
      break;
    }
  }
  renderer.redraw_safe(boxes_[region], colour);
  ++safe_redraws_;
}

}  // namespace meter::runner
