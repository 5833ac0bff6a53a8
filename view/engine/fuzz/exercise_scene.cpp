#include "exercise_scene.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/evaluation/scene_evaluator.hpp"
#include "meter/engine/frame_plan/draw_units.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/protocol/signal_table.hpp"

namespace meter::engine::fuzz {
namespace {

// Text ink as a fixed box per glyph: the evaluator only needs some extent.
class BoxMeasure : public TextMeasure {
 public:
  platform::PixelRegion ink(const TextItem& text, int x, int y) override {
    const int w = static_cast<int>(std::min<std::size_t>(text.text.size(), 256)) * text.size_px / 2;
    return {x, y - text.size_px, w, text.size_px};
  }
};

}  // namespace

void exercise_scene(const Scene& scene, std::span<const std::uint8_t> values) {
  BindingEvaluator bindings(scene);
  SceneEvaluator evaluator(scene);
  BoxMeasure measure;
  protocol::SignalTable table;
  std::size_t at = 0;
  auto next_byte = [&] { return values.empty() ? std::uint8_t{0} : values[at++ % values.size()]; };
  constexpr double kValues[] = {0.0, 1.0, -1.0, 0.5, 50.0, 126.0, 8000.0, -273.15, 1e9, 1e-9};
  // The package's draw levels at a level picked from the values, planned as the renderer plans.
  const DrawClasses classes = classify_draws(scene, true, evaluator.camera_node());
  const DrawUnits units = make_draw_units(scene, classes, true);
  governor::QualityChoice choice;
  for (const auto& l : units.ladders)
    choice.units.push_back({int(next_byte() % l.shadings.size()), int(next_byte() % l.lod_errors.size())});
  choice = checked_choice(units, choice, choice.global.msaa);
  DrawnFrame drawn;
  for (int step = 0; step < 4; ++step) {
    for (const auto& info : protocol::catalog()) {
      const std::uint8_t b = next_byte();
      const auto status = static_cast<protocol::SignalStatus>(b % 4);
      table.set(info.id, kValues[(b / 4) % std::size(kValues)], status);
    }
    bindings.update(table, step != 2, step == 0 ? -1.0 : 0.016);
    evaluator.apply(bindings.outputs());
    evaluator.update_world();
    const int w = std::clamp(scene.config.size[0], 1, 4096), h = std::clamp(scene.config.size[1], 1, 4096);
    FrameState now = evaluator.evaluate(w, h, measure);
    apply_levels(scene, units, choice, now);
    PlanSettings settings;
    settings.width = w, settings.height = h;
    const FramePlan plan = plan_frame(scene, classes, now, drawn, DrawnFrame{}, settings);
    (void)frame_load(scene, classes, units, now, plan, w, h, 1.0f);
    drawn = drawn_frame(std::move(now));
  }
}

}  // namespace meter::engine::fuzz
