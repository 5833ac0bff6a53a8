// GPU backends behind one interface: EGL (OpenGL ES 3.x, surfaceless) and OSMesa (software GL).
//
// Neither backend has a window: all rendering goes into RenderTarget framebuffer objects, so the
// same code path runs on both and a program written in GLSL ES 3.00 ("#version 300 es") gives the
// same pixels on both (OSMesa's desktop core profile compiles ES 3.00 through ARB_ES3_compatibility).
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "meter/platform/gl_api.hpp"

namespace meter::platform {

enum class BackendKind { Egl, OSMesa };

// "egl" / "osmesa".
std::string_view to_string(BackendKind kind);
// Accepts "egl", "osmesa" (case-insensitive); nullopt otherwise.
std::optional<BackendKind> parse_backend_kind(std::string_view text);

struct BackendOptions {
  // EGL: which display to open.
  //  - empty (default): Mesa surfaceless platform (EGL_PLATFORM_SURFACELESS_MESA), falling back to
  //    the first EGL device (EGL_EXT_platform_device) if surfaceless is not offered;
  //  - "surfaceless": only the surfaceless platform;
  //  - "device" or "device:N": EGL device number N (default 0).
  std::string egl_display;
  // Requested context version. EGL asks for OpenGL ES major.minor (3.0 minimum);
  // OSMesa asks for a desktop core profile of this version (default 4.5; 3.3 is the minimum
  // that runs GLSL ES 3.00 through ES3 compatibility on Mesa).
  int egl_gles_minor = 0;
  int osmesa_major = 4;
  int osmesa_minor = 5;
  // Ask for a debug context (KHR_debug output is not wired; this only changes driver validation).
  bool debug = false;
};

// Thrown when a backend cannot be created: the message names what failed and, when the cause is a
// missing library or driver, the Debian package that provides it.
class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A GL context that is current on the creating thread for the backend's whole lifetime.
// Not copyable; destroy it on the thread that created it. Only one backend per thread is current
// at a time: call make_current() before using a backend after creating another one.
class GpuBackend {
 public:
  virtual ~GpuBackend() = default;
  GpuBackend(const GpuBackend&) = delete;
  GpuBackend& operator=(const GpuBackend&) = delete;

  virtual BackendKind kind() const = 0;
  // "egl" / "osmesa".
  virtual std::string_view name() const = 0;
  // The function table bound to this backend's context (see gl_api.hpp for why).
  virtual const Gl& gl() const = 0;
  // One line for logs and reports: API + version, renderer, GLSL version, display/platform used.
  virtual std::string renderer_info() const = 0;
  // Makes this backend's context current on the calling thread again.
  virtual void make_current() = 0;

 protected:
  GpuBackend() = default;
};

// Creates the backend and makes its context current. Throws BackendError with a clear reason.
std::unique_ptr<GpuBackend> create_backend(BackendKind kind, const BackendOptions& options = {});

}  // namespace meter::platform
