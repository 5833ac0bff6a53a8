#include "egl/egl_window.hpp"

#include <utility>
#include <vector>

#include "egl/egl_names.hpp"

namespace meter::platform::detail {

EglWindow::EglWindow(const Platform& platform, void* native_display, void* native_window, EGLint visual)
    : platform_(platform) {
  const std::string name = platform_.name;
  try {
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_display || !has_token(client_ext, platform_.extension))
      throw BackendError(name + ": " + platform_.extension + " is not offered; install " + platform_.packages);
    display_ = get_display(platform_.platform, native_display, nullptr);
    EGLint major = 0, minor = 0;
    if (display_ == EGL_NO_DISPLAY || !eglInitialize(display_, &major, &minor))
      throw BackendError(name + ": eglInitialize failed (" + egl_error_name(eglGetError()) + ")");
    version_ = std::to_string(major) + "." + std::to_string(minor);
    if (!eglBindAPI(EGL_OPENGL_ES_API)) throw BackendError(name + ": eglBindAPI(EGL_OPENGL_ES_API) failed");
    const EGLConfig config = choose_config(visual);
    auto create_surface = reinterpret_cast<PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC>(
        eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT"));
    surface_ = create_surface ? create_surface(display_, config, native_window, nullptr) : EGL_NO_SURFACE;
    if (surface_ == EGL_NO_SURFACE)
      throw BackendError(name + ": cannot make the EGL window surface (" + egl_error_name(eglGetError()) + ")");
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, context_attribs);
    if (context_ == EGL_NO_CONTEXT)
      throw BackendError(name + ": eglCreateContext for OpenGL ES 3 failed (" + egl_error_name(eglGetError()) + ")");
    make_current();
    eglSwapInterval(display_, 0);  // paced by the display's own events (frame callbacks, page flips)
    const char* ext = eglQueryString(display_, EGL_EXTENSIONS);
    buffer_age_ = has_token(ext, "EGL_EXT_buffer_age");
    const char* swap = has_token(ext, "EGL_KHR_swap_buffers_with_damage")   ? "eglSwapBuffersWithDamageKHR"
                       : has_token(ext, "EGL_EXT_swap_buffers_with_damage") ? "eglSwapBuffersWithDamageEXT"
                                                                             : nullptr;
    if (swap) swap_with_damage_ = reinterpret_cast<PFNEGLSWAPBUFFERSWITHDAMAGEKHRPROC>(eglGetProcAddress(swap));
    gl_ = load_gl(&egl_get_proc, platform_.name, /*is_gles=*/true);
    blit_.emplace(gl_);
  } catch (...) {
    release();
    throw;
  }
}

EglWindow::~EglWindow() { release(); }

EGLConfig EglWindow::choose_config(EGLint visual) const {
  const EGLint want[] = {EGL_SURFACE_TYPE, EGL_WINDOW_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_RED_SIZE, 8,
                         EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
  EGLint n = 0;
  eglChooseConfig(display_, want, nullptr, 0, &n);
  std::vector<EGLConfig> configs(static_cast<std::size_t>(n > 0 ? n : 0));
  if (n > 0) eglChooseConfig(display_, want, configs.data(), n, &n);
  std::optional<EGLConfig> fallback;
  for (EGLConfig c : configs) {
    EGLint r = 0, g = 0, b = 0, a = 0, v = 0;
    eglGetConfigAttrib(display_, c, EGL_RED_SIZE, &r);
    eglGetConfigAttrib(display_, c, EGL_GREEN_SIZE, &g);
    eglGetConfigAttrib(display_, c, EGL_BLUE_SIZE, &b);
    eglGetConfigAttrib(display_, c, EGL_ALPHA_SIZE, &a);
    eglGetConfigAttrib(display_, c, EGL_NATIVE_VISUAL_ID, &v);
    if (r != 8 || g != 8 || b != 8) continue;
    if (visual ? v == visual : a == 0) return c;
    if (!visual && !fallback) fallback = c;
  }
  if (fallback) return *fallback;
  throw BackendError(std::string(platform_.name) + ": no EGL config with 8-bit RGB" +
                     (visual ? " of the scanout format" : "") + ", a window surface and OpenGL ES 3 (" +
                     std::to_string(n) + " offered)");
}

std::string EglWindow::renderer_info() const {
  return "egl: " + gl_.info.version + " | " + gl_.info.renderer + " | " + gl_.info.glsl_version + " | EGL " + version_ +
         " " + platform_.name + " display";
}

void EglWindow::make_current() {
  if (!eglMakeCurrent(display_, surface_, surface_, context_))
    throw BackendError(std::string(platform_.name) + ": eglMakeCurrent on the window surface failed (" +
                       egl_error_name(eglGetError()) + ")");
}

int EglWindow::buffer_age() const {
  EGLint age = 0;
  if (!buffer_age_ || !eglQuerySurface(display_, surface_, EGL_BUFFER_AGE_EXT, &age)) return 0;
  return age;
}

bool EglWindow::swap(std::span<const EGLint> rects, std::string& error) {
  const bool ok = swap_with_damage_ && !rects.empty()
                      ? swap_with_damage_(display_, surface_, const_cast<EGLint*>(rects.data()), EGLint(rects.size() / 4))
                      : eglSwapBuffers(display_, surface_);
  if (!ok) error = egl_error_name(eglGetError());
  return ok;
}

void EglWindow::release() noexcept {
  blit_.reset();
  if (display_ == EGL_NO_DISPLAY) return;
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, std::exchange(context_, EGL_NO_CONTEXT));
  if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, std::exchange(surface_, EGL_NO_SURFACE));
  // Terminated: this EGLDisplay belongs to the window system's connection, which goes next.
  eglTerminate(std::exchange(display_, EGL_NO_DISPLAY));
}

}  // namespace meter::platform::detail
