// --output drm[:/dev/dri/cardN]: meter-view scans out through KMS without a compositor. An
// OpenGL ES 3 context on Mesa's GBM platform (EGL_PLATFORM_GBM_KHR) draws into a GBM surface of the
// connector's mode size; present() copies the resolved frame 1:1 into its back buffer, centred when
// the mode is larger than the frame (black around it; a smaller mode is refused: the frame would be
// cut), locks it as the front buffer and flips the primary plane to it on the next vblank
// (kms_output.cpp). Double buffered: one buffer on screen, at most one flip queued; the next
// present waits for that flip's vblank event first (the pacing), then releases the buffer it
// replaced.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <gbm.h>

#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "backends.hpp"
#include "drm/kms_output.hpp"
#include "egl/egl_names.hpp"
#include "meter/platform/display_damage.hpp"
#include "meter/platform/frame_blit.hpp"

namespace meter::platform::detail {
namespace {

void destroy_fb_data(gbm_bo*, void* data);

struct BufferFb {
  KmsOutput* kms;
  std::uint32_t fb;
};

void destroy_fb_data(gbm_bo*, void* data) {
  auto* b = static_cast<BufferFb*>(data);
  b->kms->remove_framebuffer(b->fb);
  delete b;
}

std::string card_of(const std::string& target) {
  if (target == "drm") return "/dev/dri/card0";
  if (target.rfind("drm:", 0) == 0 && target.size() > 4) return target.substr(4);
  throw BackendError("--output: expected drm or drm:/dev/dri/cardN, got '" + target + "'");
}

class DrmDisplay final : public DisplayBackend {
 public:
  explicit DrmDisplay(const DisplayOptions& options)
      : kms_(card_of(options.target), options.frame_wait_ms), frame_w_(options.width), frame_h_(options.height),
        damage_(kms_.width(), kms_.height()) {
    if (kms_.width() < frame_w_ || kms_.height() < frame_h_)
      throw BackendError("drm: " + kms_.info() + ": the mode is smaller than the " + std::to_string(frame_w_) + "x" +
                         std::to_string(frame_h_) + " frame (refused: it would be cut; give the panel a larger mode)");
    origin_x_ = (kms_.width() - frame_w_) / 2;
    origin_y_ = (kms_.height() - frame_h_) / 2;
    try {
      open_egl();
      blit_.emplace(gl_);
    } catch (...) {
      release();
      throw;
    }
  }
  ~DrmDisplay() override { release(); }

  BackendKind kind() const override { return BackendKind::Egl; }
  std::string_view name() const override { return "drm"; }
  const Gl& gl() const override { return gl_; }
  std::string renderer_info() const override {
    return "egl: " + gl_.info.version + " | " + gl_.info.renderer + " | " + gl_.info.glsl_version + " | EGL " +
           egl_version_ + " gbm display";
  }
  void make_current() override {
    if (!eglMakeCurrent(egl_, surface_, surface_, context_))
      throw BackendError("drm: eglMakeCurrent on the GBM surface failed (" + egl_error_name(eglGetError()) + ")");
  }

  void present(const RenderTarget& frame, std::span<const PixelRegion> damage, std::uint64_t frame_number) override {
    if (!kms_.wait_for_flip()) return;  // the last flip never completed: a stall, counted; this frame is not shown
    if (shown_bo_ && queued_bo_) {
      gbm_surface_release_buffer(gbm_surface_, shown_bo_);
      shown_bo_ = nullptr;
    }
    if (queued_bo_) shown_bo_ = std::exchange(queued_bo_, nullptr);
    // Damage in the mode's pixels: the frame's boxes moved to where it is centred.
    std::vector<PixelRegion> moved;
    for (const auto& r : damage) moved.push_back({r.x + origin_x_, r.y + origin_y_, r.width, r.height});
    EGLint age = 0;
    if (buffer_age_ && !eglQuerySurface(egl_, surface_, EGL_BUFFER_AGE_EXT, &age)) age = 0;
    std::vector<PixelRegion> repaint = damage_.repaint(age, moved);
    const bool whole = repaint.size() == 1 && repaint[0] == PixelRegion{0, 0, kms_.width(), kms_.height()};
    if (whole) {
      gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
      gl_.Disable(GL_SCISSOR_TEST);
      gl_.ClearColor(0, 0, 0, 1);
      gl_.Clear(GL_COLOR_BUFFER_BIT);
      repaint = {};  // the whole frame box
    }
    // GL window coordinates are bottom-up: the frame's box sits at origin_y_ from the bottom too
    // (centred), so x, y carry over; FrameBlit takes the top-left corner.
    blit_->draw(frame, origin_x_, origin_y_, kms_.height(), repaint);
    copied_ += static_cast<std::uint64_t>(whole ? std::int64_t(frame_w_) * frame_h_ : area(repaint));
    if (!eglSwapBuffers(egl_, surface_))
      throw DisplayLost("drm: eglSwapBuffers failed (" + egl_error_name(eglGetError()) + ")");
    gbm_bo* bo = gbm_surface_lock_front_buffer(gbm_surface_);
    if (!bo) throw BackendError("drm: gbm_surface_lock_front_buffer failed: no free scanout buffer");
    auto* data = static_cast<BufferFb*>(gbm_bo_get_user_data(bo));
    if (!data) {
      data = new BufferFb{&kms_, kms_.framebuffer(gbm_bo_get_handle(bo).u32, gbm_bo_get_stride(bo))};
      gbm_bo_set_user_data(bo, data, destroy_fb_data);
    }
    // FB_DAMAGE_CLIPS are top-left origin in the framebuffer.
    std::vector<PixelRegion> clips;
    for (const auto& r : moved) {
      const PixelRegion c = clip(r, kms_.width(), kms_.height());
      if (!c.empty()) clips.push_back({c.x, kms_.height() - c.y - c.height, c.width, c.height});
    }
    kms_.flip(data->fb, clips, frame_number);
    damage_.presented(moved);
    if (!shown_bo_) shown_bo_ = bo;  // the modeset shows it at once
    else queued_bo_ = bo;
  }

  std::vector<PresentedFrame> take_presented(int wait_ms) override { return kms_.take_presented(wait_ms); }
  std::uint64_t stalls() const override { return kms_.stalls(); }
  std::uint64_t pixels_copied() const override { return copied_; }
  std::string display_info() const override {
    return kms_.info() + "; the " + std::to_string(frame_w_) + "x" + std::to_string(frame_h_) + " frame at (" +
           std::to_string(origin_x_) + ", " + std::to_string(origin_y_) + "), double buffered, " +
           (buffer_age_ ? "buffer age" : "no buffer age: full copies");
  }

 private:
  void open_egl() {
    gbm_ = gbm_create_device(kms_.fd());
    if (!gbm_) throw BackendError("drm: gbm_create_device failed on " + kms_.info() + "; install libgbm1");
    gbm_surface_ = gbm_surface_create(gbm_, std::uint32_t(kms_.width()), std::uint32_t(kms_.height()), GBM_FORMAT_XRGB8888,
                                      GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING);
    if (!gbm_surface_) throw BackendError("drm: gbm_surface_create " + std::to_string(kms_.width()) + "x" + std::to_string(kms_.height()) + " XRGB8888 failed");
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display || !has_token(client_ext, "EGL_KHR_platform_gbm"))
      throw BackendError("drm: EGL_KHR_platform_gbm is not offered; install libegl-mesa0 and libgbm1");
    egl_ = get_platform_display(EGL_PLATFORM_GBM_KHR, gbm_, nullptr);
    EGLint major = 0, minor = 0;
    if (egl_ == EGL_NO_DISPLAY || !eglInitialize(egl_, &major, &minor))
      throw BackendError("drm: eglInitialize on the GBM device failed (" + egl_error_name(eglGetError()) + ")");
    egl_version_ = std::to_string(major) + "." + std::to_string(minor);
    if (!eglBindAPI(EGL_OPENGL_ES_API)) throw BackendError("drm: eglBindAPI(EGL_OPENGL_ES_API) failed");
    const EGLint want[] = {EGL_SURFACE_TYPE, EGL_WINDOW_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_RED_SIZE, 8,
                           EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
    EGLint n = 0;
    eglChooseConfig(egl_, want, nullptr, 0, &n);
    std::vector<EGLConfig> configs(std::size_t(n > 0 ? n : 0));
    if (n > 0) eglChooseConfig(egl_, want, configs.data(), n, &n);
    EGLConfig config = nullptr;
    for (EGLConfig c : configs) {
      EGLint visual = 0;
      eglGetConfigAttrib(egl_, c, EGL_NATIVE_VISUAL_ID, &visual);
      if (visual == GBM_FORMAT_XRGB8888) { config = c; break; }
    }
    if (!config) throw BackendError("drm: no EGL config renders XRGB8888 into GBM buffers (" + std::to_string(n) + " offered)");
    auto create_surface = reinterpret_cast<PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC>(eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT"));
    surface_ = create_surface ? create_surface(egl_, config, gbm_surface_, nullptr) : EGL_NO_SURFACE;
    if (surface_ == EGL_NO_SURFACE) throw BackendError("drm: cannot make an EGL surface on the GBM surface (" + egl_error_name(eglGetError()) + ")");
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
    context_ = eglCreateContext(egl_, config, EGL_NO_CONTEXT, context_attribs);
    if (context_ == EGL_NO_CONTEXT) throw BackendError("drm: eglCreateContext for OpenGL ES 3 failed (" + egl_error_name(eglGetError()) + ")");
    make_current();
    buffer_age_ = has_token(eglQueryString(egl_, EGL_EXTENSIONS), "EGL_EXT_buffer_age");
    gl_ = load_gl(&egl_get_proc, "drm", /*is_gles=*/true);
  }

  void release() noexcept {
    blit_.reset();
    if (egl_ != EGL_NO_DISPLAY) {
      eglMakeCurrent(egl_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      if (context_ != EGL_NO_CONTEXT) eglDestroyContext(egl_, std::exchange(context_, EGL_NO_CONTEXT));
      if (surface_ != EGL_NO_SURFACE) eglDestroySurface(egl_, std::exchange(surface_, EGL_NO_SURFACE));
      eglTerminate(std::exchange(egl_, EGL_NO_DISPLAY));
    }
    if (gbm_surface_) gbm_surface_destroy(std::exchange(gbm_surface_, nullptr));
    if (gbm_) gbm_device_destroy(std::exchange(gbm_, nullptr));
  }

  KmsOutput kms_;
  int frame_w_, frame_h_, origin_x_ = 0, origin_y_ = 0;
  DamageHistory damage_;
  gbm_device* gbm_ = nullptr;
  gbm_surface* gbm_surface_ = nullptr;
  gbm_bo* shown_bo_ = nullptr;
  gbm_bo* queued_bo_ = nullptr;
  EGLDisplay egl_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  EGLSurface surface_ = EGL_NO_SURFACE;
  std::string egl_version_;
  bool buffer_age_ = false;
  Gl gl_;
  std::optional<FrameBlit> blit_;
  std::uint64_t copied_ = 0;
};

}  // namespace

std::unique_ptr<DisplayBackend> create_drm_display(const DisplayOptions& options) {
  return std::make_unique<DrmDisplay>(options);
}

}  // namespace meter::platform::detail
