// Internal to meter_engine: the render target's MSAA resolve for a scene, from its config's
// "resolve" (bridge::ResolveConfig; docs/scene-config.md). The width is in pixels of the drawn
// target, as Blender's Filter Size is in pixels of its render at any resolution.
#pragma once

#include "meter/bridge/scene.hpp"
#include "meter/platform/resolve_filter.hpp"

namespace meter::engine {

inline platform::ResolveFilter scene_resolve_filter(const bridge::SceneConfig& config) {
  platform::ResolveFilter f;
  if (config.resolve.filter == bridge::ResolveConfig::Filter::BlackmanHarris) f.kind = platform::ResolveFilter::Kind::BlackmanHarris;
  f.width_px = config.resolve.width_px;
  return f;
}

}  // namespace meter::engine
