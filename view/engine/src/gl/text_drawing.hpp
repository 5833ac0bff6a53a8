// Texts over the scene: one glyph atlas per pixel size (platform::TextRenderer), measured for the
// frame plan (TextMeasure) and drawn after each pass, in the font the scene package carries.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "meter/engine/evaluation/scene_evaluator.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/text.hpp"

namespace meter::engine {

class TextDrawing final : public TextMeasure {
 public:
  // `design_height`: the height text sizes are designed at (the scene config's); a target of
  // another height scales them. `scene` (its font, its name) outlives this; a text drawn from a
  // scene without a font throws platform::TextError naming the scene.
  TextDrawing(platform::GpuBackend& backend, const Scene& scene, int design_height, int target_height);

  platform::PixelRegion ink(const TextItem& text, int x, int y) override;
  void draw(platform::RenderTarget& target, const std::vector<TextState>& texts);

 private:
  platform::TextRenderer& renderer(int size_px);

  platform::GpuBackend& backend_;
  const Scene& scene_;
  int design_height_, target_height_;
  std::map<int, std::unique_ptr<platform::TextRenderer>> sizes_;
};

}  // namespace meter::engine
