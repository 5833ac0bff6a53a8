// OSMesa: Mesa's software rasteriser (llvmpipe) without any display. We ask for a desktop core
// profile (4.5 here) because Mesa's core profile offers ARB_ES3_compatibility, which compiles the
// same "#version 300 es" programs the EGL/GLES backend runs. The context is made current on a tiny
// dummy colour buffer; real rendering goes to RenderTarget FBOs.
#include <GL/osmesa.h>

#include <array>
#include <string>
#include <vector>

#include "backends.hpp"

namespace meter::platform::detail {
namespace {

constexpr int kDummySize = 4;

void* osmesa_get_proc(const char* name) {
  return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
}

class OSMesaBackend final : public GpuBackend {
 public:
  explicit OSMesaBackend(const BackendOptions& options) : dummy_(4 * kDummySize * kDummySize, 0) {
    if (options.osmesa_major < 3 || (options.osmesa_major == 3 && options.osmesa_minor < 3)) {
      throw BackendError("osmesa: requested GL " + std::to_string(options.osmesa_major) + "." +
                         std::to_string(options.osmesa_minor) +
                         " core; need at least 3.3 to run GLSL ES 3.00 programs");
    }
    const std::array<int, 13> attribs = {OSMESA_FORMAT, OSMESA_RGBA,
                                         OSMESA_DEPTH_BITS, 0,
                                         OSMESA_STENCIL_BITS, 0,
                                         OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                                         OSMESA_CONTEXT_MAJOR_VERSION, options.osmesa_major,
                                         OSMESA_CONTEXT_MINOR_VERSION, options.osmesa_minor,
                                         0};
    context_ = OSMesaCreateContextAttribs(attribs.data(), nullptr);
    if (!context_) {
      throw BackendError("osmesa: OSMesaCreateContextAttribs failed for an OpenGL " +
                         std::to_string(options.osmesa_major) + "." +
                         std::to_string(options.osmesa_minor) +
                         " core profile context (is Mesa's OSMesa installed? Debian package "
                         "libosmesa6; the requested version may also exceed what llvmpipe offers)");
    }
    try {
      make_current();
      gl_ = load_gl(&osmesa_get_proc, "osmesa", /*is_gles=*/false);
    } catch (...) {
      OSMesaDestroyContext(context_);
      throw;
    }
  }

  ~OSMesaBackend() override {
    if (OSMesaGetCurrentContext() == context_) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    OSMesaDestroyContext(context_);
  }

  BackendKind kind() const override { return BackendKind::OSMesa; }
  std::string_view name() const override { return "osmesa"; }
  const Gl& gl() const override { return gl_; }
  std::string renderer_info() const override {
    return "osmesa: OpenGL " + gl_.info.version + " | " + gl_.info.renderer + " | GLSL " +
           gl_.info.glsl_version + " | OSMesa " + std::to_string(OSMESA_MAJOR_VERSION) + "." +
           std::to_string(OSMESA_MINOR_VERSION);
  }
  void make_current() override {
    if (!OSMesaMakeCurrent(context_, dummy_.data(), GL_UNSIGNED_BYTE, kDummySize, kDummySize)) {
      throw BackendError("osmesa: OSMesaMakeCurrent failed");
    }
  }

 private:
  OSMesaContext context_ = nullptr;
  std::vector<unsigned char> dummy_;
  Gl gl_;
};

}  // namespace

std::unique_ptr<GpuBackend> create_osmesa_backend(const BackendOptions& options) {
  return std::make_unique<OSMesaBackend>(options);
}

}  // namespace meter::platform::detail
