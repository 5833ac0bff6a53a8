// The Renderer's quality levels (set_quality, the chooser's re-plan, the global rungs' targets):
// see renderer.hpp and docs/engine.md, "Quality levels".
#include <algorithm>
#include <cmath>

#include "gl/scene_resolve.hpp"
#include "gl/text_drawing.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/gl_api.hpp"

namespace meter::engine {

void Renderer::make_targets() {
  const float scale = quality_.global.scale;
  draw_width_ = std::max(1, static_cast<int>(std::lround(double(width_) * double(scale))));
  draw_height_ = std::max(1, static_cast<int>(std::lround(double(height_) * double(scale))));
  platform::RenderTargetOptions rt;
  rt.width = draw_width_;
  rt.height = draw_height_;
  rt.samples = quality_.global.msaa;
  rt.depth = platform::DepthFormat::Depth24;
  rt.resolve = scene_resolve_filter(scene_.config);
  target_.reset();
  layer_.reset();
  output_.reset();
  target_ = std::make_unique<platform::RenderTarget>(backend_, rt);
  if (draw_width_ != width_ || draw_height_ != height_) {
    platform::RenderTargetOptions out;
    out.width = width_, out.height = height_, out.samples = 1, out.depth = platform::DepthFormat::None;
    output_ = std::make_unique<platform::RenderTarget>(backend_, out);
  }
  // Nothing drawn into the new targets yet: the next frame is a full one, the layer is rebuilt.
  drawn_ = DrawnFrame{};
  layer_drawn_ = DrawnFrame{};
  unresolved_ = {platform::PixelRegion{0, 0, draw_width_, draw_height_}};
}

void Renderer::set_quality(const governor::QualityChoice& choice) {
  governor::QualityChoice c = checked_choice(units_, choice, quality_.global.msaa);
  for (std::size_t i = 0; i < c.units.size(); ++i)
    if (units_.ladders[i].safety && !(c.units[i] == governor::UnitLevel{}))
      throw std::invalid_argument("quality: unit " + std::to_string(i) + " (\"" + units_.ladders[i].name +
                                  "\") is a safety item and stays at level 0");
  if (c == quality_) return;
  if (!(c.global == quality_.global)) global_changed_ = true;
  quality_ = std::move(c);
  dirty_ = true;
}

PlanSettings Renderer::plan_settings(bool force) const {
  PlanSettings settings;
  settings.width = draw_width_, settings.height = draw_height_, settings.force = force;
  settings.partial_redraw = options_.partial_redraw;
  settings.static_layer = options_.static_layer && gl_.info.has_copy_image;
  return settings;
}

FramePlan Renderer::plan_at_quality(bool force, FrameState& now, const LevelChooser* choose) {
  for (int round = 0;; ++round) {
    if (global_changed_) {
      make_targets();
      if (draw_height_ != text_height_) {  // text sizes follow the draw height (an MSAA rung keeps it)
        text_by_height_[text_height_] = std::move(text_);
        auto it = text_by_height_.find(draw_height_);
        if (it != text_by_height_.end()) {
          text_ = std::move(it->second);
          text_by_height_.erase(it);
        } else {
          text_ = std::make_unique<TextDrawing>(backend_, options_.font_file, scene_.config.size[1], draw_height_);
        }
        text_height_ = draw_height_;
      }
      written_ = {platform::PixelRegion{0, 0, width_, height_}};  // every pixel is drawn anew
      global_changed_ = false;
    }
    now = evaluator_.evaluate(draw_width_, draw_height_, *text_);
    apply_levels(scene_, units_, quality_, now);
    FramePlan plan = plan_frame(scene_, classes_, now, drawn_, layer_drawn_, plan_settings(force));
    last_load_ = frame_load(scene_, classes_, units_, now, plan, draw_width_, draw_height_, quality_.global.scale);
    // The chooser is asked once per frame; its choice is planned, not asked about again.
    if (round > 0 || !choose || !*choose) return plan;
    const std::optional<governor::QualityChoice> c = (*choose)(last_load_);
    if (!c || checked_choice(units_, *c, quality_.global.msaa) == quality_) return plan;
    set_quality(*c);
  }
}

namespace {
// `r` on a from_w x from_h target as a box on a to_w x to_h one, rounded outwards so it always
// covers what it stands for.
platform::PixelRegion rescale(const platform::PixelRegion& r, int from_w, int from_h, int to_w, int to_h) {
  const double sx = double(to_w) / from_w, sy = double(to_h) / from_h;
  const int x0 = static_cast<int>(std::floor(r.x * sx)), y0 = static_cast<int>(std::floor(r.y * sy));
  const int x1 = static_cast<int>(std::ceil((r.x + r.width) * sx)), y1 = static_cast<int>(std::ceil((r.y + r.height) * sy));
  return platform::clip({x0, y0, x1 - x0, y1 - y0}, to_w, to_h);
}
}  // namespace

// Boxes in the drawn target's pixels <-> the output's (equal at scale 1).
platform::PixelRegion Renderer::to_output(const platform::PixelRegion& r) const {
  return output_ ? rescale(r, draw_width_, draw_height_, width_, height_) : r;
}

platform::PixelRegion Renderer::to_drawn(const platform::PixelRegion& r) const {
  return output_ ? rescale(r, width_, height_, draw_width_, draw_height_) : r;
}

}  // namespace meter::engine
