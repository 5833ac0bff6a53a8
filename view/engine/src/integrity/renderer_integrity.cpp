// The Renderer's integrity side: region readback, the safe-path redraw and the injected faults'
// GL execution (meter/engine/integrity/fault_injection.hpp).
#include <algorithm>
#include <cmath>
#include <utility>

#include "gl/text_drawing.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/gl_api.hpp"

namespace meter::engine {

std::vector<platform::Image> Renderer::read_regions(std::span<const platform::PixelRegion> regions) {
  if (regions.empty()) return {};
  if (output_) {
    // Drawn at a smaller scale: the regions are in upscaled output pixels, so what is pending is
    // resolved and upscaled as a whole.
    resolve_pending();
    return output_->read_resolved_regions(regions);
  }
  // Only the boxes read that were drawn since the last resolve are resolved (on llvmpipe an sRGB
  // MSAA resolve costs per pixel as much as drawing it), and not those render() resolved with the
  // frame when nothing was drawn after: the rest of the single-sample image is current already,
  // and what else is pending stays so for the next full read (resolving a box twice gives the
  // same pixels).
  if (target_->samples() > 1) {
    const bool clean_valid = clean_after_ == draws_;
    std::vector<platform::PixelRegion> due;
    for (const auto& box : regions) {
      const bool drawn = std::any_of(unresolved_.begin(), unresolved_.end(), [&](const auto& p) { return overlap(box, p); });
      const bool clean = clean_valid && std::any_of(clean_.begin(), clean_.end(), [&](const auto& c) { return contains(c, box); });
      if (drawn && !clean) due.push_back(box);
    }
    if (!due.empty()) target_->resolve(due);
  }
  return target_->read_resolved_regions(regions);
}

void Renderer::resolve_with_frame(std::vector<platform::PixelRegion> boxes) { watched_ = std::move(boxes); }

void Renderer::resolve_watched(const FramePlan& plan) {
  std::vector<platform::PixelRegion> watched = std::exchange(watched_, {});
  clean_.clear();
  // At a scale below 1 the reads upscale what is pending as a whole (read_regions).
  if (watched.empty() || target_->samples() <= 1 || output_) return;
  for (const auto& box : watched) {
    const bool drawn = plan.full || std::any_of(plan.regions.begin(), plan.regions.end(), [&](const auto& r) { return overlap(box, r); });
    if (drawn) clean_.push_back(box);
  }
  if (!clean_.empty()) target_->resolve(clean_);
  clean_after_ = draws_;
}

std::vector<platform::PixelRegion> Renderer::take_written(WrittenReader reader) {
  const std::size_t r = std::size_t(reader);
  if (!std::exchange(written_kept_[r], true)) return {platform::PixelRegion{0, 0, width_, height_}};
  // A wide resolve filter carries a change up to its margin beyond the box it was drawn in.
  std::vector<platform::PixelRegion> out = std::exchange(written_[r], {});
  // The margin is in drawn pixels; below scale 1 it spans more output pixels.
  const float scale = quality_.global.scale;
  if (const int m = int(std::ceil(float(target_->resolve_margin_px()) / scale)); m > 0)
    for (auto& r : out) {
      r = platform::clip(r, width_, height_);  // first: the growth cannot overflow
      if (!r.empty()) r = platform::clip({r.x - m, r.y - m, r.width + 2 * m, r.height + 2 * m}, width_, height_);
    }
  return out;
}

void Renderer::note_written(const FramePlan& plan) {
  ++draws_;
  for (std::size_t i = 0; i < written_.size(); ++i) {
    if (!written_kept_[i]) continue;
    auto& written = written_[i];
    // Many boxes (nobody took them for a while): the whole target, as a bound on the list.
    if (plan.full || written.size() > 64) written = {platform::PixelRegion{0, 0, width_, height_}};
    if (!plan.full)
      for (const auto& r : plan.regions) written.push_back(to_output(r));
  }
}

void Renderer::written_all() {
  for (std::size_t i = 0; i < written_.size(); ++i)
    if (written_kept_[i]) written_[i] = {platform::PixelRegion{0, 0, width_, height_}};
}

void Renderer::note_written(const platform::PixelRegion& drawn, const platform::PixelRegion& output) {
  ++draws_;
  unresolved_.push_back(drawn);
  for (std::size_t i = 0; i < written_.size(); ++i)
    if (written_kept_[i]) written_[i].push_back(output);
}

void Renderer::fill(const platform::PixelRegion& output_region, const glm::vec4& linear_colour) {
  // `output_region` is in output pixels; the target may be drawn at a smaller scale.
  const platform::PixelRegion region = to_drawn(output_region);
  target_->bind();
  gl_.Enable(GL_SCISSOR_TEST);
  gl_.Scissor(region.x, region.y, region.width, region.height);
  gl_.ClearColor(linear_colour.r, linear_colour.g, linear_colour.b, linear_colour.a);
  gl_.Clear(GL_COLOR_BUFFER_BIT);
  gl_.Disable(GL_SCISSOR_TEST);
  note_written(region, output_region);
}

void Renderer::redraw_safe(const platform::PixelRegion& region, const std::optional<glm::vec4>& linear_colour) {
  if (linear_colour) {
    fill(region, *linear_colour);
  } else if (layer_ && layer_drawn_.valid) {
    const platform::PixelRegion drawn = to_drawn(region);
    target_->copy_from(*layer_, std::span<const platform::PixelRegion>(&drawn, 1));
    note_written(drawn, region);
  } else {
    const auto& cc = scene_.config.clear_color;
    fill(region, glm::vec4(float(cc[0]), float(cc[1]), float(cc[2]), float(cc[3])));
  }
  platform::check_gl(gl_, scene_.source_name + ": safe-path redraw");
  redraw_all_ = true;
}

void Renderer::inject(std::optional<FaultInjection> fault) {
  fault_ = std::move(fault);
  held_world_ = evaluator_.world();
}

void Renderer::execute_faulty(const FramePlan& plan, const FrameState& now) {
  const FaultInjection& f = *fault_;
  // A stuck output: no command reaches the GPU, the target presents the last image again.
  if (f.kind == FaultKind::StuckFrame) return;
  execute(faulty_plan(scene_, classes_, f, plan), faulty_frame(scene_, f, now, held_world_));
  if (f.kind == FaultKind::CoverDraw) fill(f.box, glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
  if (f.kind == FaultKind::CoverText) {
    TextState cover;
    cover.item.text = "88";
    cover.item.size_px = 48;
    cover.item.align = TextAlign::Center;
    cover.x = f.box.x + f.box.width / 2;
    cover.y = height_ - f.box.y - f.box.height / 4;  // baseline near the box's bottom, origin top-left
    target_->bind();
    gl_.Enable(GL_SCISSOR_TEST);
    gl_.Scissor(f.box.x, f.box.y, f.box.width, f.box.height);
    text_->draw(*target_, {cover});
    gl_.Disable(GL_SCISSOR_TEST);
    note_written(f.box, to_output(f.box));  // the cover is drawn in the target's pixels
  }
}

}  // namespace meter::engine
