// Internal to meter_engine: the render target's MSAA resolve for a scene, from its config's
// "resolve" (bridge::ResolveConfig; docs/scene-config.md), and the samples' storage. The width is in pixels of the drawn
// target, as Blender's Filter Size is in pixels of its render at any resolution.
#pragma once

#include "meter/bridge/scene.hpp"
#include "meter/platform/render_target.hpp"
#include "meter/platform/resolve_filter.hpp"

namespace meter::engine {

inline platform::ResolveFilter scene_resolve_filter(const bridge::SceneConfig& config) {
  platform::ResolveFilter f;
  if (config.resolve.filter == bridge::ResolveConfig::Filter::BlackmanHarris) f.kind = platform::ResolveFilter::Kind::BlackmanHarris;
  f.width_px = config.resolve.width_px;
  return f;
}

inline platform::SampleFormat scene_sample_format(const bridge::SceneConfig& config) {
  return config.resolve.sample_format == bridge::ResolveConfig::SampleFormat::Rgba16f ? platform::SampleFormat::Rgba16f
                                                                                       : platform::SampleFormat::Srgb8;
}

}  // namespace meter::engine
