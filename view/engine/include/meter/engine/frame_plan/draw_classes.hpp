// Static-layer membership: which draws can look different from one frame to the next, and
// whether keeping the ones that cannot in a static layer pays off. Decided once from the scene's
// description (animation channels, bindings, skins, morph targets, camera, lights).
#pragma once

#include <vector>

#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

struct DrawClasses {
  // Per draw: the merged group it is drawn in (index into Scene::groups), -1 = drawn on its own.
  // All -1 when groups are not drawn merged.
  std::vector<int> group;
  // Per draw: can change (its node or an ancestor has an animation channel or a visibility/morph
  // binding or a script output, its material a colour/emissive binding or script output, it is
  // skinned or has morph targets). A merged
  // group's representative: true when any member can change. False: static-layer material.
  std::vector<char> changeable;
  // The layer has content (a static opaque draw) and outlives a frame: the camera and every light
  // stay put (an animated camera, or no camera, where the view frames the bounds of moving draws
  // too, would redraw it every frame).
  bool layer_pays = false;
  // A light casts shadows and a draw that casts into its map (opaque) can move, appear or change
  // shape: its shadow may fall on any draw anywhere, so a frame where something changed is drawn
  // whole and there is no static layer (a static receiver's shading is not static then).
  bool shadows_move = false;

  bool representative(std::size_t draw, const Scene& scene) const {
    return group[draw] >= 0 && scene.groups[static_cast<std::size_t>(group[draw])].draws.front() == static_cast<int>(draw);
  }
};

// `merged`: the scene's merged groups are drawn as one draw each (RendererOptions::concatenate).
// `camera_node`: the node whose camera the view uses (find_camera_node), -1 = none.
DrawClasses classify_draws(const Scene& scene, bool merged, int camera_node);

}  // namespace meter::engine
