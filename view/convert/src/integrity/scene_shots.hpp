// The renders display integrity is measured from: the runtime Renderer at the scene config's
// size, fed binding outputs built by hand (a lamp forced on, a needle hidden, one text replaced)
// on top of the outputs the bindings give with no signal at all (every failsafe applied).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "meter/bridge/integrity.hpp"
#include "meter/convert/integrity.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/image.hpp"

namespace meter::convert {

class SceneShots {
 public:
  SceneShots(const Scene& scene, platform::GpuBackend& backend, int msaa);
  const engine::BindingOutputs& base() const { return base_; }
  // The frame for `outputs` (read back, top-down RGBA).
  const platform::Image& shot(const engine::BindingOutputs& outputs);
  // A node's projected world origin (pixels, origin top-left) in the last shot's pose.
  glm::vec2 project(int node) const { return renderer_.project(node); }
  int width() const { return renderer_.width(); }
  int height() const { return renderer_.height(); }

 private:
  engine::Renderer renderer_;
  engine::BindingOutputs base_;
};

// Largest channel difference (R, G, B) between two images at a pixel.
int pixel_difference(const platform::Image& a, const platform::Image& b, int x, int y);

// Bounding box of the non-zero entries of a full-frame mask (width x height); empty when none.
bridge::PixelRect mask_bounds(const std::vector<std::uint8_t>& mask, int width, int height);
bridge::PixelRect grow(const bridge::PixelRect& r, int margin, int width, int height);

// Per kind; each appends its regions to `out` and what it could not measure to `out.skipped`.
void measure_telltales(const Scene& scene, SceneShots& shots, IntegrityMeasurement& out);
void measure_readouts(const Scene& scene, SceneShots& shots, IntegrityMeasurement& out);
// Needles last: their annulus avoids every pixel the telltales and readouts already measured.
// `aliased` renders without MSAA (the dial's print must not pass for the needle at any count).
void measure_needles(const Scene& scene, SceneShots& shots, SceneShots& aliased, const IntegrityOptions& options,
                     IntegrityMeasurement& out);

}  // namespace meter::convert
