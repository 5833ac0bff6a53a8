// EGL: an OpenGL ES 3.x context without any surface. Display choice: Mesa's surfaceless platform
// (no window system, no device node needed; llvmpipe here, a GPU driver where there is one) or an
// EGL device (EGL_EXT_platform_device). The context is made current with EGL_NO_SURFACE
// (EGL_KHR_surfaceless_context) and every frame is drawn into a RenderTarget FBO.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "backends.hpp"
#include "egl/egl_names.hpp"

namespace meter::platform::detail {
namespace {

constexpr const char* kPackages =
    "Debian packages libegl1 (glvnd loader) and libegl-mesa0 (Mesa EGL driver)";


struct DisplayChoice {
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string description;
};

DisplayChoice open_surfaceless(PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display,
                               const char* client_ext, std::string& why_not) {
  if (!has_token(client_ext, "EGL_MESA_platform_surfaceless")) {
    why_not += " surfaceless: EGL_MESA_platform_surfaceless not offered;";
    return {};
  }
  EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (d == EGL_NO_DISPLAY) {
    why_not += " surfaceless: eglGetPlatformDisplayEXT failed (" + egl_error_name(eglGetError()) + ");";
    return {};
  }
  return {d, "surfaceless"};
}

DisplayChoice open_device(PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display,
                          const char* client_ext, int index, std::string& why_not) {
  if (!has_token(client_ext, "EGL_EXT_platform_device")) {
    why_not += " device: EGL_EXT_platform_device not offered;";
    return {};
  }
  auto query_devices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  if (!query_devices) {
    why_not += " device: eglQueryDevicesEXT missing;";
    return {};
  }
  EGLint count = 0;
  if (!query_devices(0, nullptr, &count) || count <= 0) {
    why_not += " device: no EGL devices;";
    return {};
  }
  std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
  query_devices(count, devices.data(), &count);
  if (index < 0 || index >= count) {
    why_not += " device: index " + std::to_string(index) + " out of range (" +
               std::to_string(count) + " device(s));";
    return {};
  }
  EGLDisplay d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[static_cast<std::size_t>(index)], nullptr);
  if (d == EGL_NO_DISPLAY) {
    why_not += " device " + std::to_string(index) + ": eglGetPlatformDisplayEXT failed (" +
               egl_error_name(eglGetError()) + ");";
    return {};
  }
  std::string desc = "device " + std::to_string(index);
  auto query_string =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (query_string) {
    const char* exts = query_string(devices[static_cast<std::size_t>(index)], EGL_EXTENSIONS);
    if (has_token(exts, "EGL_MESA_device_software")) desc += " (software)";
  }
  return {d, desc};
}

class EglBackend final : public GpuBackend {
 public:
  explicit EglBackend(const BackendOptions& options) {
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client_ext) {
      throw BackendError(std::string("egl: no EGL client extensions (EGL 1.5 / "
                                     "EGL_EXT_client_extensions needed); install ") + kPackages);
    }
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display || !has_token(client_ext, "EGL_EXT_platform_base")) {
      throw BackendError(std::string("egl: EGL_EXT_platform_base (eglGetPlatformDisplayEXT) not "
                                     "available; install ") + kPackages);
    }

    const std::string& want = options.egl_display;
    std::string why_not;
    DisplayChoice choice;
    if (want.empty() || want == "surfaceless") {
      choice = open_surfaceless(get_platform_display, client_ext, why_not);
      if (choice.display == EGL_NO_DISPLAY && want.empty())
        choice = open_device(get_platform_display, client_ext, 0, why_not);
    } else if (want == "device" || want.rfind("device:", 0) == 0) {
      int index = 0;
      if (want.size() > 7) {
        char* end = nullptr;
        const long v = std::strtol(want.c_str() + 7, &end, 10);
        if (*end != '\0' || v < 0 || v > 1000) {
          throw BackendError("egl: bad display option '" + want + "' (expected device:N, N >= 0)");
        }
        index = static_cast<int>(v);
      }
      choice = open_device(get_platform_display, client_ext, index, why_not);
    } else {
      throw BackendError("egl: unknown display option '" + want +
                         "' (expected empty, 'surfaceless', 'device' or 'device:N')");
    }
    if (choice.display == EGL_NO_DISPLAY) {
      throw BackendError("egl: no usable EGL display:" + why_not + " install " + kPackages);
    }
    display_ = choice.display;
    display_desc_ = choice.description;

    EGLint major = 0, minor = 0;
    if (!eglInitialize(display_, &major, &minor)) {
      throw BackendError("egl: eglInitialize on the " + display_desc_ + " display failed (" +
                         egl_error_name(eglGetError()) + "); is the Mesa EGL driver installed? " +
                         kPackages);
    }
    egl_version_ = std::to_string(major) + "." + std::to_string(minor);
    try {
      create_context(options);
      make_current();
      gl_ = load_gl(&egl_get_proc, "egl", /*is_gles=*/true);
    } catch (...) {
      release();
      throw;
    }
  }

  ~EglBackend() override { release(); }

  BackendKind kind() const override { return BackendKind::Egl; }
  std::string_view name() const override { return "egl"; }
  const Gl& gl() const override { return gl_; }
  std::string renderer_info() const override {
    return "egl: " + gl_.info.version + " | " + gl_.info.renderer + " | " + gl_.info.glsl_version +
           " | EGL " + egl_version_ + " " + display_desc_ + " display";
  }
  void make_current() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      throw BackendError("egl: eglMakeCurrent without a surface failed (" +
                         egl_error_name(eglGetError()) +
                         "); the driver needs EGL_KHR_surfaceless_context");
    }
  }

 private:
  void create_context(const BackendOptions& options) {
    const char* display_ext = eglQueryString(display_, EGL_EXTENSIONS);
    if (!has_token(display_ext, "EGL_KHR_surfaceless_context")) {
      throw BackendError("egl: the " + display_desc_ +
                         " display lacks EGL_KHR_surfaceless_context (needed to render into FBOs "
                         "without a surface)");
    }
    if (!eglBindAPI(EGL_OPENGL_ES_API)) {
      throw BackendError("egl: eglBindAPI(EGL_OPENGL_ES_API) failed (" +
                         egl_error_name(eglGetError()) + "); install libgles2 and " + kPackages);
    }
    // No surface is ever created, so the config only matters for drivers without
    // EGL_KHR_no_config_context; ask for any GLES3-capable one there.
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!has_token(display_ext, "EGL_KHR_no_config_context")) {
      const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_SURFACE_TYPE,
                                       EGL_DONT_CARE, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(display_, config_attribs, &config, 1, &n) || n < 1) {
        throw BackendError("egl: no EGL config supports OpenGL ES 3 on the " + display_desc_ +
                           " display");
      }
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3,
                                      EGL_CONTEXT_MINOR_VERSION, options.egl_gles_minor,
                                      EGL_CONTEXT_OPENGL_DEBUG, options.debug ? EGL_TRUE : EGL_FALSE,
                                      EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, context_attribs);
    if (context_ == EGL_NO_CONTEXT) {
      throw BackendError("egl: eglCreateContext for OpenGL ES 3." +
                         std::to_string(options.egl_gles_minor) + " failed (" +
                         egl_error_name(eglGetError()) + ") on the " + display_desc_ + " display");
    }
  }

  void release() noexcept {
    if (display_ == EGL_NO_DISPLAY) return;
    if (context_ != EGL_NO_CONTEXT) {
      if (eglGetCurrentContext() == context_)
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display_, context_);
      context_ = EGL_NO_CONTEXT;
    }
    // The display is deliberately never eglTerminate()d: eglGetPlatformDisplayEXT hands every
    // backend in the process the same EGLDisplay, re-initialising it costs ~20 ms, and terminating
    // unloads the Mesa driver while it still owns allocations (LeakSanitizer then reports them
    // from an unknown module, where no suppression can name the driver). One initialised display
    // per process is what the EGL spec intends; the OS reclaims it at exit.
    display_ = EGL_NO_DISPLAY;
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::string display_desc_;
  std::string egl_version_;
  Gl gl_;
};

}  // namespace

std::unique_ptr<GpuBackend> create_egl_backend(const BackendOptions& options) {
  return std::make_unique<EglBackend>(options);
}

}  // namespace meter::platform::detail
