// The runtime renderer: GPU resources for a Scene (created through the platform Gl table), pose
// evaluation driven by BindingOutputs, sorted draws, text overlay.
//
// What is computed when:
//   construction  programs compiled, buffers/VAOs/textures uploaded, uniform locations looked up;
//   apply()       only animations whose time changed are re-sampled; world matrices recomputed only
//                 when some node moved; a frame is marked dirty only when an output differs;
//   render()      skipped when nothing changed since the last drawn frame; otherwise redraws the
//                 damaged regions (or everything): opaque static draws, then opaque changeable ones
//                 (each front-to-back), then blended back-to-front, then texts. Under a partial
//                 redraw the static part comes from the static layer (RendererOptions).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/animation.hpp"
#include "meter/engine/bindings.hpp"
#include "meter/engine/scene.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/render_target.hpp"
#include "meter/platform/text.hpp"

namespace meter::engine {

struct RendererOptions {
  int width = 0, height = 0;  // 0 = the scene config's size
  int msaa = 4;
  std::string font_file;      // empty = METER_FONT_FILE
  // Draw the package's merged groups as one draw each (issue #10). Off: every member is drawn on
  // its own, exactly as without groups (the reference for equivalence tests and benchmarks).
  bool concatenate = true;
  // Redraw only the screen regions whose pixels can have changed since the last drawn frame (a
  // moving needle, a telltale switching, a text changing), each scissored; the rest of the target
  // keeps the last frame, as a production cluster's partial update does. The result is the same
  // image as a full redraw (tests/partial_redraw_test.cpp proves it pixel for pixel). Off: every
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
  // Benchmark baseline only (bench/view): when set, every draw goes through this ONE uber-shader
  // (shadergen::generate_uber(), made by the caller: the runtime does not link the generator)
  // with runtime switches set per draw from its generated program's features, as an engine
  // without a shader generator would. It has no Flat/Gouraud (drawn per pixel as Blinn-Phong),
  // morph targets, environment map or vertex alpha, so concatenation is off in this mode and the
  // image is close to, not always equal to, the generated programs'. Must outlive the renderer.
  const bridge::Program* uber_shader = nullptr;
};

struct FrameTiming {
  double update_ms = 0.0;        // bindings -> pose -> world matrices
  double submit_ms = 0.0;        // CPU time issuing GL calls
  double gpu_readback_ms = 0.0;  // glFinish (+ resolve and readback when the frame is read)
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
  std::uint64_t partial_frames = 0;     // drawn frames limited to damaged regions
  std::uint64_t layer_builds = 0;       // static layer (re)drawn (RendererOptions::static_layer)
  double redrawn_fraction_sum = 0.0;    // sum over drawn frames of FrameTiming::redrawn_fraction
};

class Renderer {
 public:
  // Throws SceneError / platform::GlError with a clear message (e.g. a program that fails to
  // compile on this backend names the program and the driver log).
  Renderer(platform::GpuBackend& backend, const Scene& scene, const RendererOptions& options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Applies binding outputs to the pose/overrides. Marks the frame dirty when anything changed.
  void apply(const BindingOutputs& outputs);
  bool dirty() const { return dirty_; }

  // Draws when dirty (or `force`), then waits for the GPU; with `read` also resolves and reads the
  // frame into last_image(). Returns the frame's timing; FrameTiming::drawn says whether it drew.
  FrameTiming render(bool force = false, bool read = false);
  const platform::Image& last_image() const { return image_; }
  // Resolves and reads the current contents of the target (the last drawn frame).
  const platform::Image& read();

  const RendererStats& stats() const { return stats_; }
  int width() const { return width_; }
  int height() const { return height_; }
  std::string backend_info() const;
  // Pixel position (origin top-left) of a node's world origin, for text anchors and tests.
  glm::vec2 project(int node) const;

 private:
  struct GpuProgram;
  struct GpuDraw;
  struct GpuGroup;
  void build();
  void build_groups();
  void update_groups();
  void update_world();
  // Which draws a pass submits. Everything: the scene as is. StaticOpaque: the static layer's
  // content. OverStatic: what is drawn over a copy of the static layer (draws that can change, and
  // every blended draw). Within the opaque draws, static ones always come first, then the ones that
  // can change, so every path writes each sample in the same order (the same image, bit for bit).
  enum class DrawSet { Everything, StaticOpaque, OverStatic };
  void draw_scene(platform::RenderTarget& target, const platform::PixelRegion* scissor, DrawSet set);
  // Fills light_nodes_, light_first_, light_count_.
  void order_lights();
  // Marks the draws that can look different from one frame to the next (GpuDraw::changeable) and
  // decides whether a static layer can pay off (layer_pays_).
  void classify_draws();
  void draw_text();
  // What each draw looked like when last drawn; a change means its old and new screen boxes are
  // damaged. `deform` holds joint matrices / morph weights (their bounds are not the primitive's).
  struct DrawnDraw {
    bool visible = false;
    glm::mat4 world{0.0f};
    glm::vec4 base{0.0f};
    glm::vec3 emissive{0.0f};
    std::vector<float> deform;
    bool operator==(const DrawnDraw&) const = default;
  };
  struct DrawnText {
    TextItem item;
    platform::PixelRegion box;  // inked pixels, padded, GL window coordinates
    bool operator==(const DrawnText&) const = default;
  };
  DrawnDraw drawn_state(std::size_t draw) const;
  std::vector<DrawnText> visible_texts();
  platform::TextRenderer& text_renderer(int size_px);
  // Pixel box (GL window coordinates, padded) of a primitive's bounds; nullopt when a corner is
  // at or behind the eye (no finite box).
  std::optional<platform::PixelRegion> screen_box(const Primitive& prim, const glm::mat4& world, const glm::mat4& vp) const;
  // True when nothing `d` draws (every visible member, for a merged group) can touch `scissor`.
  bool outside(const GpuDraw& d, const platform::PixelRegion& scissor, const glm::mat4& vp) const;
  // The current state of every draw and drawable text, computed once per drawn frame: compared
  // by damage(), then kept by remember_drawn().
  struct Snapshot {
    std::vector<DrawnDraw> draws;  // per draw
    std::vector<DrawnText> texts;  // drawable texts
  };
  Snapshot snapshot();
  // Regions to redraw (disjoint), or nullopt when the whole target must be redrawn.
  std::optional<std::vector<platform::PixelRegion>> damage(const glm::mat4& vp, const Snapshot& now);
  void remember_drawn(const glm::mat4& vp, Snapshot now);
  std::vector<std::pair<int, glm::mat4>> light_worlds() const;
  // True when the static layer holds what the static draws look like now under `vp`.
  bool layer_current(const glm::mat4& vp, const Snapshot& now) const;
  void build_layer(const glm::mat4& vp, const Snapshot& now);
  void resolve_pending();
  glm::mat4 view_projection(glm::vec3* eye) const;

  platform::GpuBackend& backend_;
  const platform::Gl& gl_;
  const Scene& scene_;
  RendererOptions options_;
  int width_ = 0, height_ = 0;
  std::unique_ptr<platform::RenderTarget> target_;
  std::vector<std::unique_ptr<GpuProgram>> programs_;
  std::vector<std::unique_ptr<GpuDraw>> draws_;
  std::vector<std::unique_ptr<GpuGroup>> groups_;
  std::vector<int> draw_group_;  // per draw: merged group index, -1 = drawn on its own
  std::vector<GLuint> textures_;
  GLuint white_texture_ = 0;
  std::vector<GLuint> buffers_;
  std::map<int, std::unique_ptr<platform::TextRenderer>> text_;
  Pose pose_;
  std::vector<glm::mat4> world_;
  std::vector<char> visible_;
  std::vector<double> anim_time_;
  BindingOutputs outputs_;
  bool have_outputs_ = false;
  bool dirty_ = true;
  bool world_dirty_ = true;
  int camera_node_ = -1;
  // Light nodes in shadergen's order (the index light uniforms use); first index and count of each
  // light type (directional, point, spot) in it.
  std::vector<int> light_nodes_;
  int light_first_[3] = {0, 0, 0}, light_count_[3] = {0, 0, 0};
  platform::Image image_;
  RendererStats stats_;
  // Partial redraw bookkeeping (see RendererOptions::partial_redraw).
  bool drawn_valid_ = false;
  glm::mat4 drawn_vp_{0.0f};
  std::vector<DrawnDraw> drawn_draws_;
  std::vector<DrawnText> drawn_texts_;
  std::vector<std::pair<int, glm::mat4>> drawn_lights_;  // light node, its world matrix
  std::vector<platform::PixelRegion> unresolved_;         // drawn since the last MSAA resolve
  // Static layer (see RendererOptions::static_layer): created at the first unforced full frame.
  std::unique_ptr<platform::RenderTarget> layer_;
  bool layer_pays_ = false;  // static opaque draws under a fixed camera and fixed lights
  bool layer_valid_ = false;
  glm::mat4 layer_vp_{0.0f};
  std::vector<DrawnDraw> layer_draws_;                   // per draw, as drawn into the layer
  std::vector<std::pair<int, glm::mat4>> layer_lights_;
};

}  // namespace meter::engine
