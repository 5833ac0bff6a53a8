// What the two displays share (--output wayland, --output drm): an OpenGL ES 3 context on a
// window-system EGL platform with a window surface on its native window, the exact frame copy into
// it, buffer age and the swap with damage where the driver offers them; and the GpuBackend side of
// a display, answered from that context.
#pragma once

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <memory>
#include <optional>
#include <span>
#include <string>

#include "meter/platform/display.hpp"
#include "meter/platform/frame_blit.hpp"

namespace meter::platform::detail {

class EglWindow {
 public:
  struct Platform {
    const char* name;        // "wayland", "drm": the messages' prefix, renderer_info's platform
    EGLenum platform;        // EGL_PLATFORM_WAYLAND_KHR, EGL_PLATFORM_GBM_KHR
    const char* extension;   // the client extension offering it
    const char* packages;    // what to install when it is missing
  };
  // Initialises the platform's display on `native_display`, takes an 8-bit RGB window config
  // (`visual` != 0: the one whose EGL_NATIVE_VISUAL_ID it is; else one without alpha where there is
  // one), the window surface on `native_window`, the context; makes it current and fills the GL
  // table. Throws BackendError naming the step.
  EglWindow(const Platform& platform, void* native_display, void* native_window, EGLint visual = 0);
  ~EglWindow();
  EglWindow(const EglWindow&) = delete;
  EglWindow& operator=(const EglWindow&) = delete;

  const Gl& gl() const { return gl_; }
  std::string renderer_info() const;
  void make_current();
  // EGL_EXT_buffer_age of the back buffer (0: unknown contents, or no buffer age).
  int buffer_age() const;
  bool has_buffer_age() const { return buffer_age_; }
  bool has_swap_with_damage() const { return swap_with_damage_ != nullptr; }
  FrameBlit& blit() { return *blit_; }
  // Swaps; with `rects` (x, y, w, h in GL window coordinates, 4 each) as the damage where the driver
  // takes it. Returns false with the EGL error's name in `error`.
  bool swap(std::span<const EGLint> rects, std::string& error);

 private:
  EGLConfig choose_config(EGLint visual) const;
  void release() noexcept;

  Platform platform_;
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  EGLSurface surface_ = EGL_NO_SURFACE;
  std::string version_;
  bool buffer_age_ = false;
  PFNEGLSWAPBUFFERSWITHDAMAGEKHRPROC swap_with_damage_ = nullptr;
  Gl gl_;
  std::optional<FrameBlit> blit_;
};

}  // namespace meter::platform::detail
