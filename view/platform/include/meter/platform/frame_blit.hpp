// Shows the engine's frame in a window or on a display: the renderer's resolved colour texture
// drawn 1:1 into a box of the default framebuffer (meter-preview's window, meter-view's Wayland
// surface or KMS scanout buffer), without a CPU readback. The texture is sRGB (GL decodes it to
// linear when sampled), so the shader encodes back to sRGB and the window holds the same 8-bit
// values the offscreen render writes to its PNG.
#pragma once

#include <span>

#include "meter/platform/gl_api.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::platform {

class FrameBlit {
 public:
  // Compiles the copy program in the current context (GlError on failure).
  explicit FrameBlit(const Gl& gl);
  ~FrameBlit();
  FrameBlit(const FrameBlit&) = delete;
  FrameBlit& operator=(const FrameBlit&) = delete;

  // Draws `frame`'s colour texture into the default framebuffer at (x, y) from its top-left corner,
  // 1:1 pixels; `framebuffer_height` is the default framebuffer's height. With `only`, just those
  // boxes of the framebuffer (GL window coordinates) are written (a display's partial repaint).
  void draw(const RenderTarget& frame, int x, int y, int framebuffer_height,
            std::span<const PixelRegion> only = {});

 private:
  const Gl& gl_;
  GLuint program_ = 0;
  GLuint vao_ = 0;
  GLint origin_loc_ = -1, encode_loc_ = -1, frame_loc_ = -1;
};

}  // namespace meter::platform
