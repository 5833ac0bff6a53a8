// The Renderer's integrity side: region readback, the safe-path redraw and the injected faults'
// GL execution (meter/engine/integrity/fault_injection.hpp).
#include <utility>

#include "gl/text_drawing.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/gl_api.hpp"

namespace meter::engine {

std::vector<platform::Image> Renderer::read_regions(std::span<const platform::PixelRegion> regions) {
  if (regions.empty()) return {};
  // Only what was drawn since the last resolve is resolved (on llvmpipe an sRGB MSAA resolve costs
  // per pixel as much as drawing it): the rest of the single-sample image is current already.
  resolve_pending();
  return output_target().read_resolved_regions(regions);
}

std::vector<platform::PixelRegion> Renderer::take_written() { return std::exchange(written_, {}); }

void Renderer::note_written(const FramePlan& plan) {
  // Many boxes (nobody took them for a while): the whole target, as a bound on the list.
  if (plan.full || written_.size() > 64) written_ = {platform::PixelRegion{0, 0, width_, height_}};
  if (!plan.full)
    for (const auto& r : plan.regions) written_.push_back(to_output(r));
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
  unresolved_.push_back(region);
  written_.push_back(output_region);
}

void Renderer::redraw_safe(const platform::PixelRegion& region, const std::optional<glm::vec4>& linear_colour) {
  if (linear_colour) {
    fill(region, *linear_colour);
  } else if (layer_ && layer_drawn_.valid) {
    const platform::PixelRegion drawn = to_drawn(region);
    target_->copy_from(*layer_, std::span<const platform::PixelRegion>(&drawn, 1));
    unresolved_.push_back(drawn);
    written_.push_back(region);
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
    unresolved_.push_back(f.box);
    written_.push_back(f.box);
  }
}

}  // namespace meter::engine
