#include "meter/view/integrity_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "meter/platform/render_target.hpp"

namespace meter::view {

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

std::vector<IntegrityFault> judge_frame(const bridge::IntegrityTable& table,
                                        const std::vector<engine::RegionExpectation>& expected,
                                        const std::vector<platform::Image>& pixels, std::vector<RegionMemory>& memory) {
  std::vector<IntegrityFault> faults;
  memory.resize(table.regions.size());
  for (std::size_t i = 0; i < table.regions.size(); ++i) {
    const bridge::SafetyRegion& r = table.regions[i];
    const engine::RegionExpectation& e = expected.at(i);
    if (!e.known || i >= pixels.size() || pixels[i].empty()) continue;
    const engine::RgbaView v = view_of(pixels[i], r.rect);
    std::optional<engine::Verdict> verdict;
    if (r.kind == bridge::SafetyKind::Telltale) verdict = engine::check_telltale(r, v, e.lit);
    if (r.kind == bridge::SafetyKind::Needle) verdict = engine::check_needle(r, v, e.angle_deg);
    if (verdict && !verdict->ok)
      faults.push_back({r.name, r.kind, false, verdict->expected, verdict->seen, verdict->difference});
    // Frozen: the pixels equal the ones of an earlier frame whose expectation differed in look.
    RegionMemory& m = memory[i];
    if (!m.valid || m.pixels != pixels[i].rgba) {
      m = {true, pixels[i].rgba, e};
    } else if (look_changed(r, m.expected, e)) {
      const double change = r.kind == bridge::SafetyKind::Needle ? std::abs(e.angle_deg - m.expected.angle_deg) : 1.0;
      faults.push_back({r.name, r.kind, true, look_text(r, e) + " (was " + look_text(r, m.expected) + ")",
                        "the same pixels", change});
      // Judged against the look these pixels had when they last changed until they change again.
    }
  }
  return faults;
}

IntegrityMonitor::IntegrityMonitor(const engine::Scene& scene, int width, int height, bool enabled, bool safe_path)
    : scene_(scene), table_(scene.integrity), safe_path_(safe_path), height_(height) {
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
  for (const auto& r : table_.regions)
    boxes_.push_back(platform::PixelRegion{r.rect.x, height - r.rect.y - r.rect.height, r.rect.width, r.rect.height});
  memory_.resize(table_.regions.size());
  read_at_.resize(table_.regions.size());
  read_expected_.resize(table_.regions.size());
}

namespace {

bool overlaps(const platform::PixelRegion& a, const platform::PixelRegion& b) {
  return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

bool same_expectation(const engine::RegionExpectation& a, const engine::RegionExpectation& b) {
  return a.known == b.known && a.lit == b.lit && a.angle_deg == b.angle_deg && a.text == b.text;
}

}  // namespace

const std::vector<IntegrityFault>& IntegrityMonitor::check(engine::Renderer& renderer,
                                                           const engine::BindingEvaluator& evaluator) {
  frame_faults_.clear();
  if (!on_) return frame_faults_;
  ++frame_;
  const std::vector<engine::RegionExpectation> expected = engine::expected_states(table_, scene_, evaluator);
  const std::vector<platform::PixelRegion> written = renderer.take_written();
  // A region is read when its pixels can differ from the ones read last (the renderer drew into
  // it, or was asked to show it differently), or when it was last read kRefreshFrames ago.
  std::vector<std::size_t> read;
  std::vector<platform::PixelRegion> boxes;
  for (std::size_t i = 0; i < table_.regions.size(); ++i) {
    bool need = !read_at_[i] || frame_ - *read_at_[i] >= kRefreshFrames || !same_expectation(read_expected_[i], expected[i]);
    for (std::size_t w = 0; !need && w < written.size(); ++w) need = overlaps(boxes_[i], written[w]);
    if (!need) continue;
    read.push_back(i);
    boxes.push_back(boxes_[i]);
    read_at_[i] = frame_;
    read_expected_[i] = expected[i];
  }
  if (read.empty()) return frame_faults_;
  ++frames_checked_;
  regions_read_ += read.size();
  std::vector<platform::Image> got = renderer.read_regions(boxes);
  std::vector<platform::Image> pixels(table_.regions.size());
  for (std::size_t k = 0; k < read.size(); ++k) pixels[read[k]] = std::move(got[k]);
  frame_faults_ = judge_frame(table_, expected, pixels, memory_);
  for (const auto& f : frame_faults_) {
    ++faults_;
    if (f.frozen) ++frozen_;
  }
  if (safe_path_) {
    // Once per failing region (a wrong and frozen region has two faults, one safe look).
    for (std::size_t i = 0; i < table_.regions.size(); ++i) {
      const auto& name = table_.regions[i].name;
      if (std::any_of(frame_faults_.begin(), frame_faults_.end(), [&](const auto& f) { return f.region == name; }))
        redraw_safe(renderer, i, expected[i]);
    }
  }
  return frame_faults_;
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

}  // namespace meter::view
