// The runtime renderer: a thin coordinator over three parts.
//   scene evaluation (evaluation/scene_evaluator.hpp, pure): binding outputs -> pose, visibility,
//                 material parameters, world matrices, view-projection, drawable texts;
//   frame plan    (frame_plan/frame_plan.hpp, pure): the last drawn and the evaluated frame ->
//                 damaged regions, passes, draw lists, static-layer membership;
//   GL execution  (src/gl/): GPU resources, the plan's passes, the static layer, texts, resolve
//                 and readback.
//
// What is computed when:
//   apply()       only animations whose time changed are re-sampled; the outputs are kept;
//   render()      world matrices recomputed only when some node moved; the frame evaluated and
//                 compared with the last drawn one, once: skipped when no pixel can have changed;
//                 otherwise redraws the damaged regions (or everything): opaque static draws, then
//                 opaque changeable ones (each front-to-back), then blended back-to-front, then
//                 texts. Under a partial redraw the static part comes from the static layer
//                 (RendererOptions).
//   set_quality() each draw unit's level (a cheaper shading / LOD the package carries) and the
//                 frame-wide MSAA and scale, drawn from the next render(); see "Quality levels".
#pragma once

#include <array>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/evaluation/scene_evaluator.hpp"
#include "meter/engine/frame_plan/draw_units.hpp"
#include "meter/engine/frame_plan/frame_plan.hpp"
#include "meter/engine/governor/quality_choice.hpp"
#include "meter/engine/integrity/fault_injection.hpp"
#include "meter/engine/vocabulary.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::engine {

class ProgramBinaryCache;  // meter/engine/gl/program_binary_cache.hpp

struct RendererOptions {
  int width = 0, height = 0;  // 0 = the scene config's size
  int msaa = 4;
  // Draw the package's merged groups as one draw each (mesh concatenation). Off: every member is drawn on
  // its own, exactly as without groups (the reference for equivalence tests and benchmarks).
  bool concatenate = true;
  // Redraw only the screen regions whose pixels can have changed since the last drawn frame (a
  // moving needle, a telltale switching, a text changing), each scissored; the rest of the target
  // keeps the last frame, as a production cluster's partial update does. The result is the same
  // image as a full redraw (view/engine/tests/partial_redraw_test.cpp proves it pixel for pixel). Off: every
  // drawn frame is a full redraw (the reference for tests and benchmarks).
  bool partial_redraw = true;
  // With partial_redraw: keep the opaque draws that nothing in the scene can change (no animation
  // channel, visibility/colour/morph binding, skin or morph targets on them or their ancestors) in
  // a second target, drawn once, with their depth. A redrawn region then starts as a copy of that
  // layer (colour and depth of every sample, glCopyImageSubData) and only the draws that can change,
  // the blended ones and the texts are drawn over it: the dial face under a moving needle is not
  // shaded again every frame. Costs one more target of the same size and samples (about 20 MB at
  // 1280x480 MSAA 4). Used only where glCopyImageSubData exists (GLES 3.2 / GL 4.3 / copy_image).
  bool static_layer = true;
  // Benchmark baseline only (bench/view): resolve the box with glBlitFramebuffer, as before the
  // shader pass (platform::RenderTargetOptions::box_resolve_by_blit). The same image.
  bool box_resolve_by_blit = false;
  // Benchmark baseline only (bench/view): when set, every draw goes through this ONE uber-shader
  // (shadergen::generate_uber(), made by the caller: the runtime does not link the generator)
  // with runtime switches set per draw from its generated program's features, as an engine
  // without a shader generator would. It has no Flat/Gouraud (drawn per pixel as Blinn-Phong),
  // morph targets, environment map or vertex alpha, so concatenation is off in this mode and the
  // image is close to, not always equal to, the generated programs'. Must outlive the renderer.
  const bridge::Program* uber_shader = nullptr;
  // Programs shared with the renderers made before and after this one on the same context: a
  // renderer made again for an edited scene (meter-preview's reload) links only the programs whose
  // sources changed, and llvmpipe keeps the machine code it compiled for the others at their first
  // draw. Null: the renderer links its own. Must outlive the renderer.
  platform::ProgramCache* programs = nullptr;
  // Linked programs kept across runs as the driver's binaries (a view started again loads what it
  // linked last time; gl/program_binary_cache.hpp). Used when `programs` is null. Null: every
  // program compiled. Must outlive the renderer.
  ProgramBinaryCache* program_binaries = nullptr;
};

struct FrameTiming {
  double update_ms = 0.0;        // world matrices (bindings and pose sampling run in apply())
  double submit_ms = 0.0;        // CPU time issuing GL calls
  double plan_ms = 0.0;          // part of submit_ms: the frame evaluated (draw states, texts) and planned
  // glFinish (+ resolve and readback when the frame is read); under FrameEnd::Fence the fence and
  // flush, and the frame pipeline adds the wait for the frame when it completes it
  double gpu_readback_ms = 0.0;
  bool drawn = false;            // false: frame skipped (inputs unchanged)
  double redrawn_fraction = 0.0; // share of the target's pixels redrawn (1 = a full frame)
  int regions = 0;               // scissored regions drawn (0 = a full frame or nothing)
};

struct RendererStats {
  std::uint64_t frames = 0, drawn = 0, skipped = 0;
  std::uint64_t animation_samples = 0;  // animations re-sampled (only on time change)
  std::uint64_t world_updates = 0;      // world-matrix recomputations
  std::uint64_t draw_calls = 0;         // total submitted draws
  std::uint64_t member_transforms = 0;  // merged-group members re-transformed on the CPU
  std::uint64_t vertices_transformed = 0;
  std::uint64_t index_rebuilds = 0;     // merged index arrays rebuilt (visibility changed)
  double concat_cpu_ms = 0.0;           // CPU time in member transforms + uploads (all frames)
  std::uint64_t skinned_normal_updates = 0;  // skinned draws whose normals were recomputed (pose changed)
  std::uint64_t skinned_normals_kept = 0;    // vertices left at their rest normal (no deformed normal there)
  std::uint64_t partial_frames = 0;     // drawn frames limited to damaged regions
  std::uint64_t layer_builds = 0;       // static layer (re)drawn (RendererOptions::static_layer)
  std::uint64_t shadow_map_draws = 0;   // shadow maps drawn (a light's casters or the light moved)
  double redrawn_fraction_sum = 0.0;    // sum over drawn frames of FrameTiming::redrawn_fraction
};

class GpuScene;
class DrawSubmission;
class ShadowMaps;
class TextDrawing;

class Renderer {
 public:
  // Throws SceneError / platform::GlError with a clear message (e.g. a program that fails to
  // compile on this backend names the program and the driver log).
  Renderer(platform::GpuBackend& backend, const Scene& scene, const RendererOptions& options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Applies new binding outputs to the pose/overrides and marks the frame dirty. The caller applies
  // only outputs that changed (BindingEvaluator::update says so: changes are detected once, there).
  // render() then compares the evaluated frame with the last drawn one only to find where pixels
  // changed (the damaged regions), and skips a frame where none can have.
  void apply(const BindingOutputs& outputs);
  // True when changed outputs were applied since the last drawn or skipped frame.
  bool dirty() const { return dirty_; }

  // Draws when dirty (or `force`), then waits for the GPU; with `read` also resolves and reads the
  // frame into last_image(). Returns the frame's timing; FrameTiming::drawn says whether it drew.
  // The same as plan(force, read) then draw() with no choice.
  FrameTiming render(bool force = false, bool read = false);
  // A frame in two halves, with the frame-rate governor's choice between them as a plain input
  // (the frame pipeline, meter/engine/pipeline/frame_pipeline.hpp). plan(): the frame evaluated and
  // planned at the current quality; returns its planned load (last_load()): empty (drawn = false)
  // when nothing changed, so a choice made while the display is idle is still drawn at once.
  const governor::FrameLoad& plan(bool force = false, bool read = false);
  // draw(): `choice` (nullopt: keep the quality) applied, the frame planned again when it changed
  // the quality, then drawn (or skipped) and ended as set_frame_end() says. Once after each plan().
  FrameTiming draw(const std::optional<governor::QualityChoice>& choice = std::nullopt);
  // How draw() ends a frame. Finish (the default; render() always): it waits for the GPU, so its
  // timing holds the frame's whole cost. Fence: a fence after the frame's commands, flushed, and
  // draw() returns at once: the frame executes while the caller evaluates and plans the next one
  // (the overlapped frame pipeline). Its readers wait for it: wait_drawn() (a read through GL
  // waits by GL's own ordering too); the next draw() waits first, so one frame is in flight at most.
  enum class FrameEnd { Finish, Fence };
  void set_frame_end(FrameEnd end) { frame_end_ = end; }
  // The frame draw() fenced waited for; the nanoseconds waited (0: none pending, or done already).
  std::int64_t wait_drawn();
  // Whether the fenced frame has finished executing (true: none pending), waiting at most `wait`
  // for it (returning as soon as it finishes).
  bool drawn_done(std::chrono::nanoseconds wait = std::chrono::nanoseconds(0));
  const platform::Image& last_image() const { return image_; }
  // Resolves and reads the current contents of the target (the last drawn frame).
  const platform::Image& read();
  // Resolves the last drawn frame and returns the target holding it, for a caller that shows the
  // frame on the GPU without reading it back (a window samples its color_texture()).
  const platform::RenderTarget& resolved_target();
  // Resolves the last drawn frame and returns the single-sample RGBA8 framebuffer holding it
  // (width() x height()), for a caller reading it asynchronously (pixel-pack buffers).
  GLuint resolved_framebuffer();

  const RendererStats& stats() const { return stats_; }
  // Programs linked so far (at construction, and later for a level a frame first drew) and the
  // wall time the links took: the start-up's program share (bench/budget).
  std::size_t programs_linked() const;
  double program_link_ms() const;
  int width() const { return width_; }
  int height() const { return height_; }
  std::string backend_info() const;
  // Pixel position (origin top-left) of a node's world origin, for text anchors and tests.
  glm::vec2 project(int node) const;

  // The integrity monitor's side (docs/integrity.md). Reads back only `regions` of the last drawn
  // frame (GL window coordinates); of what was drawn since the last resolve, only the boxes read
  // are resolved first (the rest stays pending for a later read). An empty list reads and
  // resolves nothing.
  std::vector<platform::Image> read_regions(std::span<const platform::PixelRegion> regions);
  // The boxes (GL window coordinates) the monitor will read after the next render(): those the
  // frame draws into are resolved by render() before it waits for the frame, in the same GPU
  // flush, so the read_regions after it has nothing to resolve and waits for nothing. Used by one
  // render(); without it read_regions resolves what it reads itself (the same pixels).
  void resolve_with_frame(std::vector<platform::PixelRegion> boxes);
  // The target's boxes (GL window coordinates) drawn since the last call: each drawn frame's
  // regions (all of it for a full frame) as planned, safe-path redraws and injected covers. Only
  // these can hold pixels other than the ones read before. Each reader has its own list: the
  // integrity monitor's reads and a display's copies (meter/platform/display.hpp) take them apart.
  // A list is kept only for a reader that took it once (no list grows for a display or monitor
  // that is not there): a reader's first call gives the whole target.
  enum class WrittenReader { Monitor = 0, Display = 1 };
  std::vector<platform::PixelRegion> take_written(WrittenReader reader = WrittenReader::Monitor);
  // Safe path for an item whose check failed: `region` of the target becomes one solid colour
  // (linear RGBA), or without a colour the static layer's copy (the clear colour when there is no
  // layer). The next frame is drawn in full, so the item's own drawing comes back as soon as it is
  // right again.
  void redraw_safe(const platform::PixelRegion& region, const std::optional<glm::vec4>& linear_colour);
  // Test hook: from the next drawn frame on, the GL execution draws under `fault` (nullopt: none).
  // A StaleNeedle fault holds the world matrices of the last evaluated frame.
  void inject(std::optional<FaultInjection> fault);

  // Quality levels (the frame-rate governor's side; meter/engine/governor/quality_choice.hpp and
  // docs/engine.md "Quality levels").
  // One ladder per draw unit, fixed at construction. Order: Scene::draws order, one entry per draw
  // drawn on its own and one per merged group at its first member's (representative's) place
  // (with RendererOptions::concatenate off every draw is a unit). A safety unit has one shading and
  // one LOD; so has every unit of a package without levels.
  std::span<const governor::UnitLadder> draw_units() const { return units_.ladders; }
  // The Scene::draws indices unit `unit` draws (a merged group's members in its order).
  std::span<const int> unit_draws(std::size_t unit) const { return units_.members.at(unit); }
  // Takes effect at the next render(). Throws std::invalid_argument naming the unit and the level
  // when an index is out of its ladder, a safety unit is moved, units has neither 0 nor
  // draw_units().size() entries, msaa is not 1, 2 or 4, or scale is not in (0, 1]. Damages exactly
  // what changes: the boxes of the units whose level changed (a static-layer member's change
  // rebuilds the layer); a GlobalLevel change moves to that rung's targets (made and drawn in full
  // the first time; the rung left keeps them with its frame and layer, so a return to it redraws
  // what differs; a rung left before that releases them and is drawn in full again). The
  // output (last_image(), read(), read_regions()) keeps width() x height(): a frame drawn at a
  // scale < 1 is upscaled with a linear blit when it is resolved.
  void set_quality(const governor::QualityChoice& choice);
  const governor::QualityChoice& quality() const { return quality_; }
  // Draws and reads back one frame at each of `choices` (checked as set_quality checks them; the
  // first at each rung in full, its static layer built) and then puts back what was: the quality,
  // stats(), last_image(), the pending integrity boxes and the injected fault (off while warming
  // up). The held rung is drawn last, so its targets are kept with the frame last drawn there and
  // the next frame redraws what differs from that and looks as it would have without the call (the
  // rung drawn before it keeps its targets too; the others release theirs). What a level needs the
  // first time it is drawn (its programs compiled, the driver's shader variants for each MSAA rung,
  // text sizes) is so made before any frame is timed, not on the first frame that uses it. Returns
  // the frames drawn.
  int warm_up(std::span<const governor::QualityChoice> choices);
  // Moves the drawn image by `pixels` (x right, y up, in the drawn target's pixels) from the next
  // render() on, by translating the projection after it: the whole scene is sampled that far from
  // the pixel centres. A film that averages passes at jittered offsets (what EEVEE's temporal
  // anti-aliasing does, bench/fidelity/film_emulation.cpp) draws each pass through this. Texts are
  // placed at whole pixels and do not move. A changed offset redraws the next frame in full.
  void set_subpixel_offset(glm::vec2 pixels);
  // The planned load of the last frame render() evaluated (drawn or skipped; per unit in output
  // pixels, at scale 1: a caller predicting a scaled frame multiplies by scale^2).
  const governor::FrameLoad& last_load() const { return last_load_; }
  // The global rungs holding render targets now: the current one and at most the one left last
  // (memory: one set of targets and a static layer each, about 30 MiB at 1280x480 MSAA 4).
  std::size_t rungs_with_targets() const { return (target_ ? 1u : 0u) + rung_targets_.size(); }


 private:
  // Runs the plan's passes: the static layer build, the layer copy, each pass and its texts.
  void execute(const FramePlan& plan, const FrameState& now);
  void execute_faulty(const FramePlan& plan, const FrameState& now);
  void fill(const platform::PixelRegion& region, const glm::vec4& linear_colour);
  void note_written(const FramePlan& plan);
  // A safe-path or injected draw: `drawn` in the target's pixels, `output` in output pixels.
  void note_written(const platform::PixelRegion& drawn, const platform::PixelRegion& output);
  void resolve_watched(const FramePlan& plan);
  void resolve_pending();
  // Quality levels (renderer_quality.cpp): the targets for quality_.global (drawn at
  // draw_width_ x draw_height_; output_ holds the upscaled frame when that is smaller than the output),
  // made, or taken back from rung_targets_.
  void make_targets();
  // What every rung's targets hold forgotten: the next frame at each is drawn in full (with
  // `layers`, its static layer rebuilt too).
  void forget_drawn(bool layers);
  // The frame evaluated at the current quality and planned (its load in last_load_).
  FramePlan plan_at_quality(bool force, bool read_back, FrameState& now);
  FrameTiming skip(bool read_back, FrameTiming t);
  PlanSettings plan_settings(bool force) const;
  platform::PixelRegion to_output(const platform::PixelRegion& r) const;
  platform::PixelRegion to_drawn(const platform::PixelRegion& r) const;
  platform::RenderTarget& output_target();  // output_, or target_ at scale 1

  platform::GpuBackend& backend_;
  const platform::Gl& gl_;
  const Scene& scene_;
  RendererOptions options_;
  int width_ = 0, height_ = 0;
  std::unique_ptr<platform::RenderTarget> target_;
  SceneEvaluator evaluator_;
  DrawClasses classes_;
  std::unique_ptr<GpuScene> gpu_;
  std::unique_ptr<DrawSubmission> submission_;
  std::unique_ptr<ShadowMaps> shadows_;  // only when a light casts shadows in the scene
  std::unique_ptr<TextDrawing> text_;  // for draw_height_
  // The text drawing of every other draw height a rung has used: a rung change back reuses its
  // glyph atlases and programs instead of rasterising and compiling them again.
  std::map<int, std::unique_ptr<TextDrawing>> text_by_height_;
  int text_height_ = 0;
  bool dirty_ = true;
  // The frame between plan() and draw(): planned (or idle: nothing to evaluate), its timing so far.
  struct PlannedFrame {
    bool idle = false, force = false, read = false;
    FrameTiming timing;
    FramePlan plan;
    FrameState now;
  };
  PlannedFrame planned_;
  FrameEnd frame_end_ = FrameEnd::Finish;
  GLsync drawn_fence_ = nullptr;  // FrameEnd::Fence: the last drawn frame's, until waited for
  FrameTiming draw_ending(const std::optional<governor::QualityChoice>& choice, FrameEnd end);
  glm::vec2 subpixel_offset_{0.0f};  // see set_subpixel_offset()
  platform::Image image_;
  RendererStats stats_;
  // Partial redraw bookkeeping (see RendererOptions::partial_redraw).
  DrawnFrame drawn_;                                 // what the target holds
  std::vector<platform::PixelRegion> unresolved_;   // drawn since the last MSAA resolve
  // Static layer (see RendererOptions::static_layer): created at the first unforced full frame.
  std::unique_ptr<platform::RenderTarget> layer_;
  DrawnFrame layer_drawn_;                           // what the layer holds
  // Integrity: a safe-path redraw happened (the next frame is drawn in full); the injected fault.
  bool redraw_all_ = false;
  std::optional<FaultInjection> fault_;
  std::vector<glm::mat4> held_world_;
  std::array<std::vector<platform::PixelRegion>, 2> written_;  // per WrittenReader, see take_written()
  std::array<bool, 2> written_kept_{};                         // per WrittenReader: it took its list once
  void written_all();  // every reader's list: the whole target
  // Quality levels (see set_quality()).
  DrawUnits units_;
  governor::QualityChoice quality_;             // units always has draw_units().size() entries
  governor::FrameLoad last_load_;
  bool global_changed_ = false;                 // targets to recreate at the next render()
  int draw_width_ = 0, draw_height_ = 0;        // target_'s size: the output size times the scale
  std::unique_ptr<platform::RenderTarget> output_;  // scale < 1: the frame upscaled to the output size
  // The targets of the rung left last, with what they hold: a rung change back redraws what
  // differs from the frame drawn there last (the static layer too) instead of making new targets
  // and building the layer again (a governor stepping down and back up). Older rungs release
  // theirs: memory is two sets of targets, however many rungs the governor visits.
  struct RungTargets {
    std::unique_ptr<platform::RenderTarget> target, layer, output;
    DrawnFrame drawn, layer_drawn;
    std::vector<platform::PixelRegion> unresolved;
  };
  std::vector<std::pair<governor::GlobalLevel, RungTargets>> rung_targets_;
  static constexpr std::size_t kKeptRungs = 1;  // rungs left that keep their targets
  governor::GlobalLevel targets_level_;          // the rung target_ was made for
  std::uint64_t draws_ = 0;                      // counts what was drawn into the target
  std::vector<platform::PixelRegion> watched_;  // see resolve_with_frame()
  std::vector<platform::PixelRegion> clean_;    // resolved after draw number clean_after_
  std::uint64_t clean_after_ = 0;
};

}  // namespace meter::engine
