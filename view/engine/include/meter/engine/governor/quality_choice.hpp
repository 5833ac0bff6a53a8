// The vocabulary shared by the frame-rate governor (governor/, pure), the renderer that draws at a
// chosen quality, and the runner that measures the frames: which cheaper ways of drawing a scene
// exist, which one a frame uses, and how much each draw unit has to shade in this frame.
//
// A draw unit is what the renderer submits as one draw: a single draw of the package, or a merged
// group (mesh concatenation), whose members share one program and change quality together.
// Level 0 of every ladder is the scene as converted (full quality); higher indices are cheaper.
#pragma once

#include <string>
#include <vector>

#include "meter/bridge/program.hpp"

namespace meter::engine::governor {

// One draw unit's choice: indices into its UnitLadder's shadings and lods.
struct UnitLevel {
  int shading = 0;
  int lod = 0;
  bool operator==(const UnitLevel&) const = default;
};

// The frame-wide rungs: MSAA samples, and the resolution scale (the frame is drawn at
// scale x size and upscaled to the output size when it is resolved).
struct GlobalLevel {
  int msaa = 4;
  float scale = 1.0f;
  bool operator==(const GlobalLevel&) const = default;
};

// What one frame is drawn with. units[i] is for Renderer::draw_units()[i]; an empty list means
// every unit at level 0.
struct QualityChoice {
  GlobalLevel global;
  std::vector<UnitLevel> units;
  bool operator==(const QualityChoice&) const = default;
};

// What the renderer can vary for one draw unit, fixed when the scene is loaded.
struct UnitLadder {
  std::string name;    // the unit's node name (a merged group: the group's name)
  bool safety = false; // a telltale or an item the integrity monitor checks: never simplified
  std::vector<bridge::ShadingModel> shadings;  // [0] = the model it was converted with
  std::vector<float> lod_errors;               // [0] = 0 (the full mesh); simplifier error per level
  std::vector<float> lod_triangle_fractions;   // [0] = 1
};

// This frame's work as planned, before it is drawn: what the governor predicts from.
struct FrameLoad {
  bool drawn = false;                // false: nothing can have changed, the frame is skipped
  bool full_frame = false;           // a full redraw (not limited to damaged regions)
  bool read_back = false;            // the frame is also resolved and read back whole (a dump):
                                     // a cost of its own, the same at every quality
  double redrawn_pixels = 0.0;       // output pixels inside this frame's damaged regions
  std::vector<double> unit_pixels;   // per draw unit: its screen pixels inside those regions at
                                     // scale 1 (0 = not drawn this frame)
};

}  // namespace meter::engine::governor
