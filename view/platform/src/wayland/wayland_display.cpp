// --output wayland: an OpenGL ES 3 context on the compositor's EGL platform
// (EGL_PLATFORM_WAYLAND_KHR) with a window surface on the xdg-shell toplevel (wayland_window.cpp).
// The renderer draws into its FBOs as offscreen; copy() copies the resolved frame 1:1 into the
// back buffer (egl_display_backend.cpp: FrameBlit, the same 8-bit values the PNG dump writes), only
// the boxes the buffer lacks by its age (EGL_EXT_buffer_age); show() swaps with the frame's damage
// (eglSwapBuffersWithDamage{KHR,EXT}) so the compositor repaints only what changed. Swap interval
// 0: the pacing is the surface's frame callback: the live loop draws the next frame once it came
// (ready_for_frame), so the copy finds it there and the frame is committed as soon as it is drawn.
#include <wayland-client.h>
#include <wayland-egl.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "backends.hpp"
#include "egl/egl_display_backend.hpp"
#include "wayland/wayland_window.hpp"

namespace meter::platform::detail {
namespace {

const EglWindow::Platform kWaylandEgl{"wayland", EGL_PLATFORM_WAYLAND_KHR, "EGL_KHR_platform_wayland",
                                      "libegl-mesa0 and libwayland-egl1"};

std::string socket_of(const std::string& target) {
  if (target == "wayland") return {};
  if (target.rfind("wayland:", 0) == 0 && target.size() > 8) return target.substr(8);
  throw BackendError("--output: expected wayland or wayland:SOCKET, got '" + target + "'");
}

class WaylandDisplay final : public EglDisplayBackend {
 public:
  explicit WaylandDisplay(const DisplayOptions& options)
      : EglDisplayBackend("wayland"),
        window_(socket_of(options.target), options.fullscreen, options.frame_wait_ms) {
    place(options.width, options.height, options.width, options.height);  // the compositor centres the surface
    egl_window_ = wl_egl_window_create(window_.surface(), options.width, options.height);
    if (!egl_window_) throw BackendError("wayland: wl_egl_window_create failed");
    try {
      egl_ = std::make_unique<EglWindow>(kWaylandEgl, window_.display(), egl_window_);
    } catch (...) {
      wl_egl_window_destroy(egl_window_);
      throw;
    }
  }
  ~WaylandDisplay() override {
    egl_.reset();  // the surface before the native window it is on
    wl_egl_window_destroy(egl_window_);
  }

  bool copy(const RenderTarget& frame, std::span<const PixelRegion> damage) override {
    window_.wait_for_frame();
    copy_frame(frame, damage);
    return true;
  }

  bool ready_for_frame(int wait_ms) override { return window_.frame_ready(wait_ms); }
  std::int64_t last_latch_ns() const override { return window_.last_frame_done_ns(); }

  void show(std::uint64_t frame_number) override {
    window_.before_commit(frame_number);
    const std::vector<PixelRegion> damage = take_shown_damage();
    std::vector<EGLint> rects;
    for (const auto& r : damage) rects.insert(rects.end(), {r.x, r.y, r.width, r.height});
    std::string error;
    const bool swapped = egl_->swap(rects, error);
    window_.check_alive("swapping buffers");
    if (!swapped) throw DisplayLost("wayland: eglSwapBuffers failed (" + error + ")");
  }

  std::vector<PresentedFrame> take_presented(int wait_ms) override { return window_.take_presented(wait_ms); }
  std::uint64_t stalls() const override { return window_.stalls(); }
  std::string display_info() const override {
    return window_.info() + ", " + std::to_string(surface_w_) + "x" + std::to_string(surface_h_) + " EGL window (" +
           (egl_->has_buffer_age() ? "buffer age" : "no buffer age: full copies") + ", " +
           (egl_->has_swap_with_damage() ? "swap with damage" : "swap without damage") + ")";
  }

 private:
  WaylandWindow window_;
  wl_egl_window* egl_window_ = nullptr;
};

}  // namespace

std::unique_ptr<DisplayBackend> create_wayland_display(const DisplayOptions& options) {
  return std::make_unique<WaylandDisplay>(options);
}

}  // namespace meter::platform::detail
