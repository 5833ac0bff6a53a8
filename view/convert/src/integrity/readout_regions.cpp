// Readout regions: every text binding. The box is where any of its texts can put ink: the union,
// over sample texts (its failsafe text, its map entries, its format at 1 to 6 digits and
// negative), of the pixels that differ from a render without the text.
#include <cmath>

#include "scene_shots.hpp"

namespace meter::convert {
namespace {

// Pixels of a readout's box that may differ from the engine's reference render of the same text
// by more than kReadoutInkStep. Glyphs are rasterised on the CPU and placed at whole pixels, so
// the ink itself is exact; what differs is the scene behind it (MSAA edges of the dial print
// under a glyph's antialiased rim at another sample count, so the reference is drawn at the run's).
// Measured on scenes/cluster over both backends at MSAA 1, 2, 4 and 8 and the filter / precision /
// affine ladder points against an EGL reference at the same MSAA (IntegrityBounds,
// docs/integrity.md: 0 pixels); 4 leaves room for a driver's rounding while one changed digit of
// the smallest readout (22 px, trip 123.4 -> 123.9 km) moves 116 pixels.
constexpr int kReadoutTolerance = 4;

std::vector<std::string> sample_texts(const Binding& b) {
  std::vector<std::string> t;
  if (b.failsafe_text) t.push_back(*b.failsafe_text);
  if (b.failsafe_value) t.push_back(engine::binding_text(b, *b.failsafe_value));
  for (const auto& [v, text] : b.map) t.push_back(text);
  for (double v : {0.0, 8.8, 88.8, 888.8, 8888.8, 88888.8, 888888.8, -88.8}) t.push_back(engine::binding_text(b, v));
  return t;
}

engine::BindingOutputs with_text(const engine::BindingOutputs& base, const Binding& b, int node, const std::string* text) {
  auto o = base;
  std::erase_if(o.texts, [&](const engine::TextItem& t) { return t.node == node; });
  if (text) {
    o.texts.push_back({node, *text, static_cast<int>(std::lround(b.size_px)),
                       glm::vec4(b.color[0], b.color[1], b.color[2], b.color[3]), b.align});
  }
  return o;
}

}  // namespace

void measure_readouts(const Scene& scene, SceneShots& shots, IntegrityMeasurement& out) {
  const auto& bindings = scene.config.bindings;
  const int w = shots.width(), h = shots.height();
  for (std::size_t i = 0; i < bindings.size(); ++i) {
    const Binding& b = bindings[i];
    if (b.kind != BindingKind::Text) continue;
    const int node = scene.find_node(b.node);
    const platform::Image blank = shots.shot(with_text(shots.base(), b, node, nullptr));
    std::vector<std::uint8_t> mask(std::size_t(w) * std::size_t(h), 0);
    for (const auto& text : sample_texts(b)) {
      const platform::Image& img = shots.shot(with_text(shots.base(), b, node, &text));
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          if (pixel_difference(img, blank, x, y) > 0) mask[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1;
    }
    const auto box = mask_bounds(mask, w, h);
    if (box.empty()) {
      out.skipped.push_back(b.node + " (readout " + b.signal + "): its texts put no ink on the frame");
      continue;
    }
    bridge::SafetyRegion r;
    r.name = b.node;
    r.kind = bridge::SafetyKind::Readout;
    r.signal = b.signal;
    r.bindings = {int(i)};
    r.node = b.node;
    r.rect = grow(box, 2, w, h);
    const glm::vec2 anchor = shots.project(node);
    r.readout = {int(std::lround(anchor.x)), int(std::lround(anchor.y)), int(std::lround(b.size_px)), b.align, b.format,
                 kReadoutTolerance};
    out.table.regions.push_back(std::move(r));
  }
}

}  // namespace meter::convert
