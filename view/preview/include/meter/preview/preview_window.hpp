// The preview's on-screen window behind one small interface: a GL context the engine renders with
// (an OpenGL ES 3 context through EGL, the API of the offscreen EGL backend, so the same generated
// programs run and give the same pixels), events, presentation and readback of what is shown.
#pragma once

#include <memory>
#include <string>

#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"

namespace meter::preview {

struct WindowSize {
  int width = 0, height = 0;
};

class PreviewWindow {
 public:
  virtual ~PreviewWindow() = default;
  PreviewWindow(const PreviewWindow&) = delete;
  PreviewWindow& operator=(const PreviewWindow&) = delete;

  // The window's context as a GpuBackend: the engine's Renderer draws with it into its own target.
  virtual platform::GpuBackend& gpu() = 0;
  // The default framebuffer's size in pixels.
  virtual WindowSize framebuffer_size() const = 0;
  // Asks for a new client-area size (a reloaded scene of another size); takes effect on the next
  // events poll.
  virtual void resize(WindowSize size) = 0;
  // Handles pending window events, waiting at most `timeout_s` for one (0 = do not wait).
  virtual void poll_events(double timeout_s) = 0;
  virtual bool close_requested() const = 0;
  // True once after any input, focus, expose or resize event since the last call: the window's
  // UI may look different and should be drawn again.
  virtual bool take_activity() = 0;
  // Reads a box of the default framebuffer's back buffer (the frame about to be presented), box
  // origin top-left, as a top-down RGBA8 image. Throws platform::GlError on a GL error.
  virtual platform::Image read_back(int x, int y, int width, int height) = 0;
  // Shows the back buffer (buffer swap).
  virtual void present() = 0;
  // The toolkit's window handle, for the UI layer's platform binding.
  virtual void* native_handle() = 0;

 protected:
  PreviewWindow() = default;
};

// A GLFW window (X11 with Debian's GLFW) with an OpenGL ES 3 context created through EGL, swap interval 0
// (frames are paced by the preview loop, not by the display). Throws platform::BackendError naming
// what failed (no display, no EGL/GLES 3 context) and the package or variable that fixes it.
std::unique_ptr<PreviewWindow> create_glfw_window(WindowSize size, const std::string& title);

}  // namespace meter::preview
