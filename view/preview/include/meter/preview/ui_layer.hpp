// Dear ImGui on the preview window (its GLFW and OpenGL 3 / GLSL ES 3.00 backends): one UI frame
// per window frame, drawn over the default framebuffer after the scene.
#pragma once

#include "meter/preview/preview_window.hpp"

namespace meter::preview {

class UiLayer {
 public:
  // Binds ImGui to the window (its context must be current). Throws platform::BackendError.
  explicit UiLayer(PreviewWindow& window);
  ~UiLayer();
  UiLayer(const UiLayer&) = delete;
  UiLayer& operator=(const UiLayer&) = delete;

  void begin_frame();
  // Draws the frame's UI into the default framebuffer. ImGui's desktop-GL backend queries state
  // an OpenGL ES context does not have (polygon mode); the GL errors that leaves are drained here,
  // so the engine's own error checks see only the engine's errors.
  void end_frame();

 private:
  PreviewWindow& window_;
};

}  // namespace meter::preview
