// The Renderer's quality levels (set_quality, the frame planned at a quality, the global rungs' targets):
// see renderer.hpp and docs/engine.md, "Quality levels".
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/scene_resolve.hpp"
#include "gl/text_drawing.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/gl_api.hpp"

namespace meter::engine {

void Renderer::make_targets() {
  const float scale = quality_.global.scale;
  draw_width_ = std::max(1, static_cast<int>(std::lround(double(width_) * double(scale))));
  draw_height_ = std::max(1, static_cast<int>(std::lround(double(height_) * double(scale))));
  clean_.clear();  // the integrity monitor's resolved boxes are of the target being left
  // The rung being left keeps its targets and what they hold.
  if (target_) {
    rung_targets_.push_back({targets_level_,
                             RungTargets{std::move(target_), std::move(layer_), std::move(output_), std::move(drawn_),
                                         std::move(layer_drawn_), std::move(unresolved_)}});
  }
  targets_level_ = quality_.global;
  const auto kept = std::find_if(rung_targets_.begin(), rung_targets_.end(),
                                 [&](const auto& r) { return r.first == quality_.global; });
  if (kept != rung_targets_.end()) {  // visited before: its frame and static layer are what they were
    RungTargets& r = kept->second;
    target_ = std::move(r.target), layer_ = std::move(r.layer), output_ = std::move(r.output);
    drawn_ = std::move(r.drawn), layer_drawn_ = std::move(r.layer_drawn), unresolved_ = std::move(r.unresolved);
    rung_targets_.erase(kept);
  }
  // Only the rungs left last keep theirs; older ones release them (memory: at most two rungs'
  // targets). A return to a released rung makes them anew and draws its frame and static layer in
  // full: the image a kept rung would show.
  if (rung_targets_.size() > kKeptRungs)
    rung_targets_.erase(rung_targets_.begin(), rung_targets_.end() - std::ptrdiff_t(kKeptRungs));
  if (target_) return;
  platform::RenderTargetOptions rt;
  rt.width = draw_width_;
  rt.height = draw_height_;
  rt.samples = quality_.global.msaa;
  rt.depth = platform::DepthFormat::Depth24;
  rt.resolve = scene_resolve_filter(scene_.config);
  rt.sample_format = scene_sample_format(scene_.config);
  rt.box_resolve_by_blit = options_.box_resolve_by_blit;
  rt.programs = options_.programs;
  target_ = std::make_unique<platform::RenderTarget>(backend_, rt);
  if (draw_width_ != width_ || draw_height_ != height_) {
    platform::RenderTargetOptions out;
    out.width = width_, out.height = height_, out.samples = 1, out.depth = platform::DepthFormat::None;
    output_ = std::make_unique<platform::RenderTarget>(backend_, out);
  }
  // Nothing drawn into the new targets yet: the next frame is a full one, the layer is built.
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

void Renderer::forget_drawn(bool layers) {
  drawn_ = DrawnFrame{};
  if (layers) layer_drawn_ = DrawnFrame{};
  for (auto& [level, r] : rung_targets_) {
    r.drawn = DrawnFrame{};
    if (layers) r.layer_drawn = DrawnFrame{};
  }
  global_changed_ = true;
}

int Renderer::warm_up(std::span<const governor::QualityChoice> choices) {
  if (choices.empty()) return 0;
  const governor::QualityChoice quality = quality_;
  const RendererStats stats = stats_;
  platform::Image image = image_;
  std::vector<platform::PixelRegion> watched = std::exchange(watched_, {});
  const std::optional<FaultInjection> fault = std::exchange(fault_, std::nullopt);
  const bool redraw_all = redraw_all_;
  // Each frame unforced, as the governor's frames are: the first at each rung makes its targets (or
  // forgets what they hold) and builds its static layer; the others redraw what the levels damage.
  forget_drawn(true);
  // The held rung's choices last (each rung's in their order): its targets are then the current
  // ones, not among the rungs released on the way.
  std::vector<governor::QualityChoice> order(choices.begin(), choices.end());
  std::stable_partition(order.begin(), order.end(), [&](const auto& c) { return !(c.global == quality.global); });
  int frames = 0;
  for (const governor::QualityChoice& c : order) {
    set_quality(c);
    dirty_ = true;
    if (render(false, true).drawn) ++frames;
  }
  set_quality(quality);
  // The held rung's targets and the rung's drawn before it are kept with what they hold, as after
  // any frame: each rung's last warm-up frame drew the current outputs at full quality, so a frame
  // at a kept rung redraws only what differs from that (nothing, at full quality with unchanged
  // outputs); the other rungs' targets were made once and released (the programs and the driver's
  // shader variants for their MSAA stay made).
  global_changed_ = true;
  dirty_ = true;
  redraw_all_ = redraw_all;
  stats_ = stats;
  image_ = std::move(image);
  watched_ = std::move(watched);
  fault_ = fault;
  clean_.clear();
  written_all();
  return frames;
}

PlanSettings Renderer::plan_settings(bool force) const {
  PlanSettings settings;
  settings.width = draw_width_, settings.height = draw_height_, settings.force = force;
  settings.partial_redraw = options_.partial_redraw;
  settings.static_layer = options_.static_layer && gl_.info.has_copy_image;
  return settings;
}

FramePlan Renderer::plan_at_quality(bool force, bool read_back, FrameState& now) {
  if (global_changed_) {
    make_targets();
    if (draw_height_ != text_height_) {  // text sizes follow the draw height (an MSAA rung keeps it)
      text_by_height_[text_height_] = std::move(text_);
      auto it = text_by_height_.find(draw_height_);
      if (it != text_by_height_.end()) {
        text_ = std::move(it->second);
        text_by_height_.erase(it);
      } else {
        text_ = std::make_unique<TextDrawing>(backend_, scene_, scene_.config.size[1], draw_height_);
      }
      text_height_ = draw_height_;
    }
    written_all();  // every pixel is drawn anew
    global_changed_ = false;
  }
  now = evaluator_.evaluate(draw_width_, draw_height_, *text_);
  if (subpixel_offset_ != glm::vec2(0.0f)) {
    // A clip-space translation by 2 d / size moves every vertex d pixels after the divide by w.
    const glm::vec3 ndc(2.0f * subpixel_offset_.x / float(draw_width_), 2.0f * subpixel_offset_.y / float(draw_height_), 0.0f);
    now.view_projection = glm::translate(glm::mat4(1.0f), ndc) * now.view_projection;
  }
  apply_levels(scene_, units_, quality_, now);
  FramePlan plan = plan_frame(scene_, classes_, now, drawn_, layer_drawn_, plan_settings(force));
  last_load_ = frame_load(scene_, classes_, units_, now, plan, draw_width_, draw_height_, quality_.global.scale);
  last_load_.read_back = read_back;
  return plan;
}

void Renderer::set_subpixel_offset(glm::vec2 pixels) {
  if (!std::isfinite(pixels.x) || !std::isfinite(pixels.y))
    throw std::invalid_argument("Renderer::set_subpixel_offset: the offset must be finite");
  if (pixels == subpixel_offset_) return;
  subpixel_offset_ = pixels;
  redraw_all_ = true;  // every pixel samples the scene elsewhere
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
