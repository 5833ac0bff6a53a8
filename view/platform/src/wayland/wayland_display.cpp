// --output wayland: an OpenGL ES 3 context on the compositor's EGL platform
// (EGL_PLATFORM_WAYLAND_KHR) with a window surface on the xdg-shell toplevel (wayland_window.cpp).
// The renderer draws into its FBOs as offscreen; present() copies the resolved frame 1:1 into the
// back buffer (FrameBlit: the same 8-bit values the PNG dump writes), only the boxes the buffer
// lacks by its age (EGL_EXT_buffer_age), and swaps with this frame's damage
// (eglSwapBuffersWithDamage{KHR,EXT}) so the compositor repaints only what changed. Swap interval
// 0: the pacing is the surface's frame callback, waited for before the next copy.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <wayland-client.h>
#include <wayland-egl.h>

#include <memory>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "backends.hpp"
#include "egl/egl_names.hpp"
#include "meter/platform/display_damage.hpp"
#include "meter/platform/frame_blit.hpp"
#include "wayland/wayland_window.hpp"

namespace meter::platform::detail {
namespace {

// A config for an opaque window: 8-bit RGB, no alpha when there is one (the compositor then
// treats the buffer as opaque, XRGB8888), OpenGL ES 3 renderable.
EGLConfig opaque_window_config(EGLDisplay display) {
  const EGLint want[] = {EGL_SURFACE_TYPE, EGL_WINDOW_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT,
                         EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
  EGLint n = 0;
  eglChooseConfig(display, want, nullptr, 0, &n);
  std::vector<EGLConfig> configs(static_cast<std::size_t>(n > 0 ? n : 0));
  if (n > 0) eglChooseConfig(display, want, configs.data(), n, &n);
  std::optional<EGLConfig> with_alpha;
  for (EGLConfig c : configs) {
    EGLint r = 0, g = 0, b = 0, a = 0;
    eglGetConfigAttrib(display, c, EGL_RED_SIZE, &r);
    eglGetConfigAttrib(display, c, EGL_GREEN_SIZE, &g);
    eglGetConfigAttrib(display, c, EGL_BLUE_SIZE, &b);
    eglGetConfigAttrib(display, c, EGL_ALPHA_SIZE, &a);
    if (r != 8 || g != 8 || b != 8) continue;
    if (a == 0) return c;
    if (!with_alpha) with_alpha = c;
  }
  if (with_alpha) return *with_alpha;
  throw BackendError("wayland: no EGL config with 8-bit RGB, a window surface and OpenGL ES 3 (" +
                     std::to_string(n) + " config(s) offered)");
}

class WaylandDisplay final : public DisplayBackend {
 public:
  explicit WaylandDisplay(const DisplayOptions& options)
      : window_(socket_of(options.target), options.fullscreen, options.frame_wait_ms),
        width_(options.width), height_(options.height), damage_(options.width, options.height) {
    try {
      open_egl();
      blit_.emplace(gl_);
    } catch (...) {
      release();
      throw;
    }
  }
  ~WaylandDisplay() override { release(); }

  BackendKind kind() const override { return BackendKind::Egl; }
  std::string_view name() const override { return "wayland"; }
  const Gl& gl() const override { return gl_; }
  std::string renderer_info() const override {
    return "egl: " + gl_.info.version + " | " + gl_.info.renderer + " | " + gl_.info.glsl_version + " | EGL " +
           egl_version_ + " wayland display";
  }
  void make_current() override {
    if (!eglMakeCurrent(egl_, surface_, surface_, context_))
      throw BackendError("wayland: eglMakeCurrent on the window surface failed (" + egl_error_name(eglGetError()) + ")");
  }

  void present(const RenderTarget& frame, std::span<const PixelRegion> damage, std::uint64_t frame_number) override {
    window_.wait_for_frame();
    EGLint age = 0;
    if (buffer_age_ && !eglQuerySurface(egl_, surface_, EGL_BUFFER_AGE_EXT, &age)) age = 0;
    const std::vector<PixelRegion> repaint = damage_.repaint(age, damage);
    blit_->draw(frame, 0, 0, height_, repaint);
    copied_ += static_cast<std::uint64_t>(area(repaint));
    window_.before_commit(frame_number);
    std::vector<EGLint> rects;
    for (const auto& r : damage) {
      const PixelRegion c = clip(r, width_, height_);
      if (!c.empty()) rects.insert(rects.end(), {c.x, c.y, c.width, c.height});
    }
    // An empty damage list would mean "the whole surface" to EGL: one pixel-free frame is not
    // presented at all by the sink, so every call here has at least one box or a full frame.
    bool swapped = false;
    if (swap_with_damage_ && !rects.empty())
      swapped = swap_with_damage_(egl_, surface_, rects.data(), EGLint(rects.size() / 4));
    else
      swapped = eglSwapBuffers(egl_, surface_);
    if (!swapped) {
      window_.check_alive("swapping buffers");
      throw DisplayLost("wayland: eglSwapBuffers failed (" + egl_error_name(eglGetError()) + ")");
    }
    window_.check_alive("swapping buffers");
    damage_.presented(damage);
  }

  std::vector<PresentedFrame> take_presented(int wait_ms) override { return window_.take_presented(wait_ms); }
  std::uint64_t stalls() const override { return window_.stalls(); }
  std::uint64_t pixels_copied() const override { return copied_; }
  std::string display_info() const override {
    return window_.info() + ", " + std::to_string(width_) + "x" + std::to_string(height_) + " EGL window (" +
           (buffer_age_ ? "buffer age" : "no buffer age: full copies") + ", " +
           (swap_with_damage_ ? "swap with damage" : "swap without damage") + ")";
  }

 private:
  static std::string socket_of(const std::string& target) {
    if (target == "wayland") return {};
    if (target.rfind("wayland:", 0) == 0 && target.size() > 8) return target.substr(8);
    throw BackendError("--output: expected wayland or wayland:SOCKET, got '" + target + "'");
  }

  void open_egl() {
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display || !has_token(client_ext, "EGL_KHR_platform_wayland"))
      throw BackendError("wayland: EGL_KHR_platform_wayland is not offered; install libegl-mesa0 and libwayland-egl1");
    egl_ = get_platform_display(EGL_PLATFORM_WAYLAND_KHR, window_.display(), nullptr);
    EGLint major = 0, minor = 0;
    if (egl_ == EGL_NO_DISPLAY || !eglInitialize(egl_, &major, &minor))
      throw BackendError("wayland: eglInitialize on the Wayland display failed (" + egl_error_name(eglGetError()) + ")");
    egl_version_ = std::to_string(major) + "." + std::to_string(minor);
    if (!eglBindAPI(EGL_OPENGL_ES_API))
      throw BackendError("wayland: eglBindAPI(EGL_OPENGL_ES_API) failed (" + egl_error_name(eglGetError()) + ")");
    const EGLConfig config = opaque_window_config(egl_);
    egl_window_ = wl_egl_window_create(window_.surface(), width_, height_);
    if (!egl_window_) throw BackendError("wayland: wl_egl_window_create failed");
    auto create_surface = reinterpret_cast<PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC>(
        eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT"));
    if (!create_surface) throw BackendError("wayland: eglCreatePlatformWindowSurfaceEXT is missing");
    surface_ = create_surface(egl_, config, egl_window_, nullptr);
    if (surface_ == EGL_NO_SURFACE)
      throw BackendError("wayland: eglCreatePlatformWindowSurfaceEXT failed (" + egl_error_name(eglGetError()) + ")");
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
    context_ = eglCreateContext(egl_, config, EGL_NO_CONTEXT, context_attribs);
    if (context_ == EGL_NO_CONTEXT)
      throw BackendError("wayland: eglCreateContext for OpenGL ES 3 failed (" + egl_error_name(eglGetError()) + ")");
    make_current();
    eglSwapInterval(egl_, 0);  // paced by frame callbacks, not inside eglSwapBuffers
    const char* ext = eglQueryString(egl_, EGL_EXTENSIONS);
    buffer_age_ = has_token(ext, "EGL_EXT_buffer_age");
    const char* swap_name = has_token(ext, "EGL_KHR_swap_buffers_with_damage") ? "eglSwapBuffersWithDamageKHR"
                            : has_token(ext, "EGL_EXT_swap_buffers_with_damage") ? "eglSwapBuffersWithDamageEXT"
                                                                                  : nullptr;
    if (swap_name) swap_with_damage_ = reinterpret_cast<PFNEGLSWAPBUFFERSWITHDAMAGEKHRPROC>(eglGetProcAddress(swap_name));
    gl_ = load_gl(&egl_get_proc, "wayland", /*is_gles=*/true);
  }

  void release() noexcept {
    blit_.reset();
    if (egl_ != EGL_NO_DISPLAY) {
      eglMakeCurrent(egl_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      if (context_ != EGL_NO_CONTEXT) eglDestroyContext(egl_, std::exchange(context_, EGL_NO_CONTEXT));
      if (surface_ != EGL_NO_SURFACE) eglDestroySurface(egl_, std::exchange(surface_, EGL_NO_SURFACE));
      // Terminated: this EGLDisplay belongs to this wl_display, which the window disconnects next.
      eglTerminate(std::exchange(egl_, EGL_NO_DISPLAY));
    }
    if (egl_window_) wl_egl_window_destroy(std::exchange(egl_window_, nullptr));
  }

  WaylandWindow window_;
  int width_, height_;
  DamageHistory damage_;
  EGLDisplay egl_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  EGLSurface surface_ = EGL_NO_SURFACE;
  wl_egl_window* egl_window_ = nullptr;
  std::string egl_version_;
  bool buffer_age_ = false;
  PFNEGLSWAPBUFFERSWITHDAMAGEKHRPROC swap_with_damage_ = nullptr;
  Gl gl_;
  std::optional<FrameBlit> blit_;
  std::uint64_t copied_ = 0;
};

}  // namespace

std::unique_ptr<DisplayBackend> create_wayland_display(const DisplayOptions& options) {
  return std::make_unique<WaylandDisplay>(options);
}

}  // namespace meter::platform::detail
