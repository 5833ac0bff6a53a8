// The frame plan: from the frame last drawn and the frame evaluated now, what to redraw (damaged
// regions or the whole target), which passes run (static layer build, layer copy, draws over the
// static layer) and the draws of each pass in submission order. Pure: no GL.
//
// Draw order, in every pass: opaque/mask draws front-to-back (early depth reject), the static ones
// (that the layer holds) before the changeable ones, then blended draws back-to-front (correct
// over), then texts. Every path writes each sample in the same order: a partial redraw, with or
// without the static layer, gives the full redraw's image bit for bit.
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "meter/engine/evaluation/frame_state.hpp"
#include "meter/engine/frame_plan/draw_classes.hpp"
#include "meter/engine/frame_plan/screen_regions.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

// What the target (or the static layer) holds: the frame as it was drawn into it.
struct DrawnFrame {
  bool valid = false;
  glm::mat4 view_projection{0.0f};
  std::vector<DrawState> draws;
  std::vector<TextState> texts;
  std::vector<std::pair<int, glm::mat4>> lights;
};

// Which draws a pass submits. Everything: the scene as is. StaticOpaque: the static layer's
// content. OverStatic: what is drawn over a copy of the static layer (draws that can change, and
// every blended draw).
enum class DrawSet { Everything, StaticOpaque, OverStatic };

struct Pass {
  DrawSet set = DrawSet::Everything;
  std::optional<PixelRegion> scissor;  // none: the whole target
  std::vector<int> draws;              // Scene::draws indices, in submission order
};

struct PlanSettings {
  int width = 0, height = 0;
  bool force = false;           // drawn from scratch, whatever changed (no static layer)
  bool partial_redraw = true;   // RendererOptions::partial_redraw
  bool static_layer = false;    // RendererOptions::static_layer, and the backend can copy layers
};

struct FramePlan {
  bool draw = false;                   // false: no pixel can have changed, the frame stands
  bool full = false;                   // the whole target is redrawn (else `regions`)
  std::vector<PixelRegion> regions;    // damaged regions, disjoint (partial frames)
  std::optional<Pass> layer_build;     // the static layer is redrawn first (whole layer)
  bool copy_layer = false;             // the target's regions (or all of it) start as the layer
  std::vector<Pass> passes;            // drawn into the target, each followed by the texts
};

// Regions whose pixels can differ between `drawn` and `now` (disjoint, clipped), or nullopt when
// the whole target must be redrawn: nothing drawn yet, the camera or a light moved, skinned or
// morphed geometry changed, a box has a corner behind the eye, or the damage exceeds half.
std::optional<std::vector<PixelRegion>> damage(const Scene& scene, const FrameState& now, const DrawnFrame& drawn,
                                               int width, int height);

// True when `layer` holds what the static draws look like in `now`. Static by the scene's
// description; checked anyway, so a misjudged draw costs a rebuild, never a stale pixel.
bool layer_current(const DrawClasses& classes, const FrameState& now, const DrawnFrame& layer);

// The draws of one pass in submission order. A merged group is drawn once, at its
// representative's place, when a member is visible; a draw whose screen box misses the scissor
// is left out (it cannot change a pixel of the pass).
std::vector<int> draw_list(const Scene& scene, const DrawClasses& classes, const FrameState& now, DrawSet set,
                           const PixelRegion* scissor, int width, int height);

FramePlan plan_frame(const Scene& scene, const DrawClasses& classes, const FrameState& now, const DrawnFrame& drawn,
                     const DrawnFrame& layer, const PlanSettings& settings);

// The record of a frame drawn from `now` (into the target, or the static layer); the second form
// takes the frame's draws and texts over instead of copying them.
DrawnFrame drawn_frame(const FrameState& now);
DrawnFrame drawn_frame(FrameState&& now);

}  // namespace meter::engine
