#include "scene_shots.hpp"

#include <algorithm>
#include <cstdlib>

#include "meter/protocol/signal_table.hpp"

namespace meter::convert {
namespace {

engine::RendererOptions shot_options(int msaa) {
  engine::RendererOptions o;
  o.msaa = msaa;  // width, height 0: the scene config's size
  return o;
}

engine::BindingOutputs no_signal_outputs(const Scene& scene) {
  engine::BindingEvaluator ev(scene);
  ev.update(protocol::SignalTable{}, true, -1.0);
  return ev.outputs();
}

}  // namespace

SceneShots::SceneShots(const Scene& scene, platform::GpuBackend& backend, int msaa)
    : renderer_(backend, scene, shot_options(msaa)), base_(no_signal_outputs(scene)) {}

const platform::Image& SceneShots::shot(const engine::BindingOutputs& outputs) {
  renderer_.apply(outputs);
  renderer_.render(false, true);  // only the damaged regions: the same pixels as a full redraw
  return renderer_.last_image();
}

int pixel_difference(const platform::Image& a, const platform::Image& b, int x, int y) {
  const std::uint8_t* p = a.pixel(x, y);
  const std::uint8_t* q = b.pixel(x, y);
  return std::max({std::abs(p[0] - q[0]), std::abs(p[1] - q[1]), std::abs(p[2] - q[2])});
}

bridge::PixelRect mask_bounds(const std::vector<std::uint8_t>& mask, int width, int height) {
  int x0 = width, y0 = height, x1 = -1, y1 = -1;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (mask[std::size_t(y) * std::size_t(width) + std::size_t(x)] == 0) continue;
      x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
    }
  if (x1 < 0) return {};
  return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

bridge::PixelRect grow(const bridge::PixelRect& r, int margin, int width, int height) {
  const int x0 = std::max(0, r.x - margin), y0 = std::max(0, r.y - margin);
  const int x1 = std::min(width, r.x + r.width + margin), y1 = std::min(height, r.y + r.height + margin);
  return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

}  // namespace meter::convert
