#include "gl/text_drawing.hpp"

#include <algorithm>
#include <cmath>

namespace meter::engine {

namespace {
platform::Align to_platform(TextAlign a) {
  return a == TextAlign::Left ? platform::Align::Left : a == TextAlign::Center ? platform::Align::Center : platform::Align::Right;
}
}  // namespace

TextDrawing::TextDrawing(platform::GpuBackend& backend, const Scene& scene, int design_height, int target_height)
    : backend_(backend), scene_(scene),
      design_height_(design_height > 0 ? design_height : target_height), target_height_(target_height) {}

platform::TextRenderer& TextDrawing::renderer(int size_px) {
  // Text sizes are designed at the scene config's size; a target of another size (--size, the
  // half-size frames of the vcan tests) scales them with its height, so the layout keeps its
  // proportions instead of readouts running into each other.
  const double scaled = double(size_px) * double(target_height_) / double(design_height_);
  const int size = std::clamp(static_cast<int>(std::lround(scaled)), 4, 256);
  auto it = sizes_.find(size);
  if (it == sizes_.end()) {
    // The package's font only (its FONT chunk): the view opens no font file.
    const SceneFont& font = scene_.font;
    if (!font.present())
      throw platform::TextError("scene '" + scene_.source_name + "' draws text but carries no font (the package's FONT "
                                "chunk, embedded by meter-convert)");
    const platform::FontData data{font.name + " (embedded in the scene package)", font.data};
    it = sizes_.emplace(size, std::make_unique<platform::TextRenderer>(backend_, data, size)).first;
  }
  return *it->second;
}

platform::PixelRegion TextDrawing::ink(const TextItem& t, int x, int y) {
  platform::TextRenderer& tr = renderer(t.size_px);
  platform::Rect r;
  try {
    r = tr.measure(t.text, x, y, to_platform(t.align));
  } catch (const platform::TextError&) {
    r = tr.measure("?", x, y, to_platform(t.align));
  }
  return {r.x, r.y, r.width, r.height};
}

void TextDrawing::draw(platform::RenderTarget& target, const std::vector<TextState>& texts) {
  for (const auto& s : texts) {
    const TextItem& t = s.item;
    platform::TextRenderer& tr = renderer(t.size_px);
    const platform::Color color{t.color.r, t.color.g, t.color.b, t.color.a};
    try {
      tr.draw(target, t.text, s.x, s.y, to_platform(t.align), color);
    } catch (const platform::TextError&) {
      // Invalid UTF-8 from a signal: draw the placeholder rather than nothing.
      tr.draw(target, "?", s.x, s.y, to_platform(t.align), color);
    }
  }
}

}  // namespace meter::engine
