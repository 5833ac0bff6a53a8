#include "meter/engine/renderer.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

#include "gl/draw_submission.hpp"
#include "gl/gpu_scene.hpp"
#include "gl/scene_resolve.hpp"
#include "gl/text_drawing.hpp"
#include "meter/platform/gl_api.hpp"

namespace meter::engine {

using Clock = std::chrono::steady_clock;

namespace {
double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
}  // namespace

Renderer::Renderer(platform::GpuBackend& backend, const Scene& scene, const RendererOptions& options)
    : backend_(backend), gl_(backend.gl()), scene_(scene), options_(options), evaluator_(scene) {
  width_ = options.width > 0 ? options.width : scene.config.size[0];
  height_ = options.height > 0 ? options.height : scene.config.size[1];
  platform::RenderTargetOptions rt;
  rt.width = width_;
  rt.height = height_;
  rt.samples = std::max(1, options.msaa);
  rt.depth = platform::DepthFormat::Depth24;
  rt.resolve = scene_resolve_filter(scene.config);
  target_ = std::make_unique<platform::RenderTarget>(backend, rt);
  unresolved_ = {platform::PixelRegion{0, 0, width_, height_}};
  if (options_.uber_shader) options_.concatenate = false;  // the uber-shader has no vertex-alpha input
  gpu_ = std::make_unique<GpuScene>(gl_, scene, options_.uber_shader, options_.concatenate);
  submission_ = std::make_unique<DrawSubmission>(gl_, scene, *gpu_, evaluator_.light_nodes());
  text_ = std::make_unique<TextDrawing>(backend, options_.font_file, scene.config.size[1], height_);
  classes_ = classify_draws(scene, options_.concatenate, evaluator_.camera_node());
  stats_.animation_samples = evaluator_.animation_samples();
}

Renderer::~Renderer() {
  backend_.make_current();
  text_.reset();
  submission_.reset();
  gpu_.reset();
}

std::string Renderer::backend_info() const { return backend_.renderer_info(); }

void Renderer::apply(const BindingOutputs& outputs) {
  // Equal outputs draw the same frame: an idle display costs this comparison and nothing more.
  if (outputs == evaluator_.outputs()) return;
  evaluator_.apply(outputs);
  stats_.animation_samples = evaluator_.animation_samples();
  dirty_ = true;
}

glm::vec2 Renderer::project(int node) const {
  return evaluator_.project(node, evaluator_.view_projection(width_, height_), width_, height_);
}

void Renderer::execute(const FramePlan& plan, const FrameState& now) {
  gpu_->update_groups(now, stats_);
  if (plan.layer_build) {
    if (!layer_) {
      platform::RenderTargetOptions rt;
      rt.width = width_, rt.height = height_, rt.samples = target_->samples(), rt.depth = target_->depth();
      rt.resolve = target_->resolve_filter();  // same colour storage: the layer copy is texel for texel
      layer_ = std::make_unique<platform::RenderTarget>(backend_, rt);
    }
    submission_->submit(*layer_, *plan.layer_build, now, stats_);
    layer_drawn_ = drawn_frame(now);
    ++stats_.layer_builds;
  }
  const platform::PixelRegion all{0, 0, width_, height_};
  if (plan.copy_layer) {
    if (plan.full) target_->copy_from(*layer_, std::span<const platform::PixelRegion>(&all, 1));
    else target_->copy_from(*layer_, plan.regions);
  }
  for (const Pass& pass : plan.passes) {
    submission_->submit(*target_, pass, now, stats_);
    text_->draw(*target_, now.texts);
  }
  if (plan.full) {
    unresolved_ = {all};
  } else {
    gl_.Disable(GL_SCISSOR_TEST);
    unresolved_.insert(unresolved_.end(), plan.regions.begin(), plan.regions.end());
  }
}

void Renderer::resolve_pending() {
  // Many small resolves cost more than one full one; past 16, resolve everything.
  if (unresolved_.size() > 16) unresolved_ = {platform::PixelRegion{0, 0, width_, height_}};
  target_->resolve(unresolved_);
  unresolved_.clear();
}

FrameTiming Renderer::render(bool force, bool read_back) {
  FrameTiming t;
  ++stats_.frames;
  auto t0 = Clock::now();
  if (evaluator_.update_world()) ++stats_.world_updates;
  t.update_ms = ms_since(t0);
  // A skipped frame still answers a read with the frame that stands.
  auto skip = [&] {
    ++stats_.skipped;
    if (read_back) {
      auto t2 = Clock::now();
      read();
      t.gpu_readback_ms = ms_since(t2);
    }
    return t;
  };
  force = force || std::exchange(redraw_all_, false);
  if (!dirty_ && !force) return skip();
  auto t1 = Clock::now();
  // What every draw and text looks like now: compared with the last drawn frame, then remembered.
  FrameState now = evaluator_.evaluate(width_, height_, *text_);
  PlanSettings settings;
  settings.width = width_, settings.height = height_, settings.force = force;
  settings.partial_redraw = options_.partial_redraw;
  settings.static_layer = options_.static_layer && gl_.info.has_copy_image;
  const FramePlan plan = plan_frame(scene_, classes_, now, drawn_, layer_drawn_, settings);
  t.plan_ms = ms_since(t1);
  dirty_ = false;
  if (!plan.draw) {
    t.submit_ms = ms_since(t1);
    return skip();
  }
  if (fault_) execute_faulty(plan, now);
  else execute(plan, now);
  note_written(plan);
  if (plan.full) {
    t.redrawn_fraction = 1.0;
  } else {
    long long pixels = 0;
    for (const auto& r : plan.regions) pixels += area(r);
    t.redrawn_fraction = double(pixels) / (double(width_) * double(height_));
    t.regions = static_cast<int>(plan.regions.size());
    ++stats_.partial_frames;
  }
  drawn_ = drawn_frame(std::move(now));
  t.submit_ms = ms_since(t1);
  auto t2 = Clock::now();
  gl_.Finish();
  if (read_back) read();
  t.gpu_readback_ms = ms_since(t2);
  platform::check_gl(gl_, scene_.source_name + ": drawing a frame");
  t.drawn = true;
  ++stats_.drawn;
  stats_.redrawn_fraction_sum += t.redrawn_fraction;
  return t;
}

GLuint Renderer::resolved_framebuffer() {
  resolve_pending();
  return target_->resolved_framebuffer();
}

const platform::Image& Renderer::read() {
  resolve_pending();
  image_ = target_->read_resolved();
  return image_;
}

const platform::RenderTarget& Renderer::resolved_target() {
  resolve_pending();
  return *target_;
}

}  // namespace meter::engine
