#include "meter/engine/renderer.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

#include "gl/draw_submission.hpp"
#include "gl/gpu_scene.hpp"
#include "gl/scene_resolve.hpp"
#include "gl/shadow_maps.hpp"
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
  quality_.global.msaa = std::max(1, options.msaa);
  make_targets();
  if (options_.uber_shader) options_.concatenate = false;  // the uber-shader has no vertex-alpha input
  gpu_ = std::make_unique<GpuScene>(gl_, scene, options_.uber_shader, options_.concatenate, options_.programs,
                                    options_.program_binaries);
  submission_ = std::make_unique<DrawSubmission>(gl_, scene, *gpu_, evaluator_.light_nodes());
  // The uber-shader baseline has no shadow lookups: it gets no maps either.
  if (!options_.uber_shader) {
    auto maps = std::make_unique<ShadowMaps>(gl_, scene, evaluator_.light_nodes());
    if (!maps->empty()) shadows_ = std::move(maps);
    submission_->use_shadow_maps(shadows_.get());
  }
  text_ = std::make_unique<TextDrawing>(backend, scene, scene.config.size[1], draw_height_);
  text_height_ = draw_height_;
  classes_ = classify_draws(scene, options_.concatenate, evaluator_.camera_node());
  units_ = make_draw_units(scene, classes_, options_.uber_shader == nullptr);
  quality_.units.assign(units_.ladders.size(), governor::UnitLevel{});
  stats_.animation_samples = evaluator_.animation_samples();
}

Renderer::~Renderer() {
  backend_.make_current();
  if (drawn_fence_) gl_.DeleteSync(drawn_fence_);
  text_.reset();
  text_by_height_.clear();
  submission_.reset();
  shadows_.reset();
  gpu_.reset();
}

std::size_t Renderer::programs_linked() const { return gpu_->programs_linked(); }
double Renderer::program_link_ms() const { return gpu_->program_link_ms(); }

std::string Renderer::backend_info() const { return backend_.renderer_info(); }

void Renderer::apply(const BindingOutputs& outputs) {
  evaluator_.apply(outputs);
  stats_.animation_samples = evaluator_.animation_samples();
  dirty_ = true;
}

glm::vec2 Renderer::project(int node) const {
  return evaluator_.project(node, evaluator_.view_projection(width_, height_), width_, height_);
}

void Renderer::execute(const FramePlan& plan, const FrameState& now) {
  gpu_->prepare(now);
  gpu_->update_groups(now, stats_);
  gpu_->update_skinned(now, stats_);
  if (shadows_) {
    gpu_->prepare_depth(now);
    // Every visible opaque draw casts (EEVEE: any opaque material); blended ones do not.
    auto casters = [&] {
      std::vector<int> list = draw_list(scene_, classes_, now, DrawSet::Everything, nullptr, draw_width_, draw_height_);
      std::erase_if(list, [&](int d) { return scene_.programs[static_cast<std::size_t>(scene_.draws[static_cast<std::size_t>(d)].program)].program.blend; });
      return list;
    };
    shadows_->update(now, casters, *submission_, stats_);
  }
  if (plan.layer_build) {
    if (!layer_) {
      platform::RenderTargetOptions rt;
      rt.width = draw_width_, rt.height = draw_height_, rt.samples = target_->samples(), rt.depth = target_->depth();
      rt.resolve = target_->resolve_filter();  // same colour storage: the layer copy is texel for texel
      rt.sample_format = target_->sample_format();
      rt.box_resolve_by_blit = !target_->resolves_by_shader();
      rt.programs = options_.programs;
      layer_ = std::make_unique<platform::RenderTarget>(backend_, rt);
    }
    submission_->submit(*layer_, *plan.layer_build, now, stats_);
    layer_drawn_ = drawn_frame(now);
    ++stats_.layer_builds;
  }
  const platform::PixelRegion all{0, 0, draw_width_, draw_height_};
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
    // Reads of a few boxes (the integrity monitor's) leave the rest pending over frames: a box
    // already pending is not added again (a moving needle redraws the same box every frame), and
    // the list is bounded as resolve_pending would bound it (past 16, all).
    for (const auto& r : plan.regions) {
      if (std::any_of(unresolved_.begin(), unresolved_.end(), [&](const auto& p) { return contains(p, r); })) continue;
      std::erase_if(unresolved_, [&](const auto& p) { return contains(r, p); });
      unresolved_.push_back(r);
    }
    if (unresolved_.size() > 16) unresolved_ = {all};
  }
}

void Renderer::resolve_pending() {
  if (unresolved_.empty()) return;
  // Many small resolves cost more than one full one; past 16, resolve everything.
  if (unresolved_.size() > 16) unresolved_ = {platform::PixelRegion{0, 0, draw_width_, draw_height_}};
  target_->resolve(unresolved_);
  unresolved_.clear();
  if (!output_) return;
  // A frame drawn smaller than the output: upscaled (linear filter) over the whole output.
  if (gl_.info.needs_framebuffer_srgb_enable) gl_.Enable(GL_FRAMEBUFFER_SRGB);
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, target_->resolved_framebuffer());
  gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, output_->resolved_framebuffer());
  gl_.BlitFramebuffer(0, 0, draw_width_, draw_height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_LINEAR);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, target_->draw_framebuffer());
  platform::check_gl(gl_, scene_.source_name + ": upscaling a frame drawn at scale " + std::to_string(quality_.global.scale));
}

platform::RenderTarget& Renderer::output_target() { return output_ ? *output_ : *target_; }

FrameTiming Renderer::render(bool force, bool read_back) {
  plan(force, read_back);
  return draw_ending(std::nullopt, FrameEnd::Finish);
}

std::int64_t Renderer::wait_drawn() {
  if (!drawn_fence_) return 0;
  const auto t0 = Clock::now();
  const GLenum r = gl_.ClientWaitSync(drawn_fence_, GL_SYNC_FLUSH_COMMANDS_BIT, GL_TIMEOUT_IGNORED);
  gl_.DeleteSync(std::exchange(drawn_fence_, nullptr));
  if (r == GL_WAIT_FAILED) throw platform::GlError(scene_.source_name + ": waiting for a drawn frame (glClientWaitSync failed)");
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
}

bool Renderer::drawn_done(std::chrono::nanoseconds wait) {
  if (!drawn_fence_) return true;
  const GLenum r = gl_.ClientWaitSync(drawn_fence_, 0, static_cast<GLuint64>(std::max<std::int64_t>(0, wait.count())));
  if (r == GL_WAIT_FAILED) throw platform::GlError(scene_.source_name + ": asking whether a frame is drawn (glClientWaitSync failed)");
  return r != GL_TIMEOUT_EXPIRED;
}

const governor::FrameLoad& Renderer::plan(bool force, bool read_back) {
  planned_ = PlannedFrame{};
  planned_.read = read_back;
  ++stats_.frames;
  auto t0 = Clock::now();
  if (evaluator_.update_world()) ++stats_.world_updates;
  planned_.timing.update_ms = ms_since(t0);
  planned_.force = force || std::exchange(redraw_all_, false);
  if (!dirty_ && !planned_.force && !global_changed_) {
    // Nothing to evaluate: the governor still sees the (empty) load and may change the quality,
    // which then draws what the change damages.
    planned_.idle = true;
    last_load_ = governor::FrameLoad{};
    last_load_.unit_pixels.assign(units_.ladders.size(), 0.0);
    last_load_.read_back = read_back;
    return last_load_;
  }
  const auto plan_began = Clock::now();
  // What every draw and text looks like now: compared with the last drawn frame, then remembered.
  planned_.plan = plan_at_quality(planned_.force, read_back, planned_.now);
  planned_.timing.plan_ms = ms_since(plan_began);
  return last_load_;
}

// A skipped frame still answers a read with the frame that stands.
FrameTiming Renderer::skip(bool read_back, FrameTiming t) {
  ++stats_.skipped;
  watched_.clear();
  if (read_back) {
    auto t2 = Clock::now();
    read();
    t.gpu_readback_ms = ms_since(t2);
  }
  return t;
}

FrameTiming Renderer::draw(const std::optional<governor::QualityChoice>& choice) { return draw_ending(choice, frame_end_); }

FrameTiming Renderer::draw_ending(const std::optional<governor::QualityChoice>& choice, FrameEnd end) {
  PlannedFrame& f = planned_;
  wait_drawn();  // one frame in flight at most: its caller completes it first, or it is waited for here
  FrameTiming& t = f.timing;
  const auto replan_began = Clock::now();
  // A safe-path redraw after this frame was planned (the overlapped pipeline checks the frame
  // before once this one is planned): drawn in full, as a frame planned after it would be.
  const bool redraw_all = std::exchange(redraw_all_, false);
  if (f.idle) {
    if (choice) set_quality(*choice);
    if (!dirty_ && !global_changed_ && !redraw_all) return skip(f.read, t);
    f.force = f.force || redraw_all;
    f.plan = plan_at_quality(f.force, f.read, f.now);
    t.plan_ms += ms_since(replan_began);
  } else if (const bool requality = choice && !(checked_choice(units_, *choice, quality_.global.msaa) == quality_);
             requality || redraw_all) {
    // The choice is planned, not asked about again.
    if (requality) set_quality(*choice);
    f.force = f.force || redraw_all;
    f.plan = plan_at_quality(f.force, f.read, f.now);
    t.plan_ms += ms_since(replan_began);
  }
  const auto submit_began = Clock::now();
  const FramePlan& plan = f.plan;
  dirty_ = false;
  if (!plan.draw) {
    t.submit_ms = t.plan_ms;
    return skip(f.read, t);
  }
  if (fault_) execute_faulty(plan, f.now);
  else execute(plan, f.now);
  note_written(plan);
  // A fenced frame is not waited for here: resolving the integrity monitor's boxes with it would
  // wait for its execution at once (the resolve samples what it draws). Its reads resolve them.
  if (end == FrameEnd::Fence && !f.read) watched_.clear(), clean_.clear();
  else resolve_watched(plan);
  if (plan.full) {
    t.redrawn_fraction = 1.0;
  } else {
    long long pixels = 0;
    for (const auto& r : plan.regions) pixels += area(r);
    t.redrawn_fraction = double(pixels) / (double(draw_width_) * double(draw_height_));
    t.regions = static_cast<int>(plan.regions.size());
    ++stats_.partial_frames;
  }
  drawn_ = drawn_frame(std::move(f.now));
  t.submit_ms = t.plan_ms + ms_since(submit_began);
  auto t2 = Clock::now();
  if (end == FrameEnd::Fence && !f.read) {
    drawn_fence_ = gl_.FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    gl_.Flush();  // the frame starts executing now, not at the next wait
  } else {
    gl_.Finish();
    if (f.read) read();
  }
  t.gpu_readback_ms = ms_since(t2);
  platform::check_gl(gl_, scene_.source_name + ": drawing a frame");
  t.drawn = true;
  ++stats_.drawn;
  stats_.redrawn_fraction_sum += t.redrawn_fraction;
  return t;
}

GLuint Renderer::resolved_framebuffer() {
  resolve_pending();
  return output_target().resolved_framebuffer();
}

const platform::Image& Renderer::read() {
  resolve_pending();
  image_ = output_target().read_resolved();
  return image_;
}

const platform::RenderTarget& Renderer::resolved_target() {
  resolve_pending();
  return output_target();
}

}  // namespace meter::engine
