// --output drm[:/dev/dri/cardN]: meter-view scans out through KMS without a compositor. An
// OpenGL ES 3 context on Mesa's GBM platform (EGL_PLATFORM_GBM_KHR) draws into a GBM surface of the
// connector's mode size; copy() copies the resolved frame 1:1 into its back buffer, centred when
// the mode is larger than the frame (black around it; a smaller mode is refused: the frame would be
// cut; egl_display_backend.cpp), show() locks it as the front buffer and flips the primary plane to
// it on the next vblank (kms_output.cpp). Double buffered: one buffer on screen, at most one flip queued; the next
// copy waits for that flip's vblank event first (the pacing), then releases the buffer it
// replaced.
#include <gbm.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "backends.hpp"
#include "drm/kms_output.hpp"
#include "meter/platform/display_damage.hpp"
#include "egl/egl_display_backend.hpp"

namespace meter::platform::detail {
namespace {

const EglWindow::Platform kGbmEgl{"drm", EGL_PLATFORM_GBM_KHR, "EGL_KHR_platform_gbm", "libegl-mesa0 and libgbm1"};

// The KMS framebuffer of a GBM buffer, made once and removed with the buffer.
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

class DrmDisplay final : public EglDisplayBackend {
 public:
  explicit DrmDisplay(const DisplayOptions& options)
      : EglDisplayBackend("drm"), kms_(card_of(options.target), options.frame_wait_ms, options.drm_modeset) {
    if (kms_.width() < options.width || kms_.height() < options.height)
      throw BackendError("drm: " + kms_.info() + ": the mode is smaller than the " + std::to_string(options.width) + "x" +
                         std::to_string(options.height) + " frame (refused: it would be cut; give the panel a larger mode)");
    place(kms_.width(), kms_.height(), options.width, options.height);
    try {
      gbm_ = gbm_create_device(kms_.fd());
      if (!gbm_) throw BackendError("drm: gbm_create_device failed on " + kms_.info() + "; install libgbm1");
      surface_ = gbm_surface_create(gbm_, std::uint32_t(kms_.width()), std::uint32_t(kms_.height()), GBM_FORMAT_XRGB8888,
                                    GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING);
      if (!surface_)
        throw BackendError("drm: gbm_surface_create " + std::to_string(kms_.width()) + "x" + std::to_string(kms_.height()) +
                           " XRGB8888 failed");
      egl_ = std::make_unique<EglWindow>(kGbmEgl, gbm_, surface_, GBM_FORMAT_XRGB8888);
    } catch (...) {
      release();
      throw;
    }
  }
  ~DrmDisplay() override { release(); }

  bool copy(const RenderTarget& frame, std::span<const PixelRegion> damage) override {
    if (!kms_.wait_for_flip()) {
      // The last flip never completed: a stall (counted); this frame is not shown, and its damage
      // goes with the next one that is.
      carried_.insert(carried_.end(), damage.begin(), damage.end());
      return false;
    }
    if (shown_bo_ && queued_bo_) gbm_surface_release_buffer(surface_, std::exchange(shown_bo_, nullptr));
    if (queued_bo_) shown_bo_ = std::exchange(queued_bo_, nullptr);
    // Mesa's GBM driver crashes (SIGSEGV in the draw) when it needs a new back buffer from a
    // device that was removed: asked first, a removal ends the view with DisplayLost instead (one
    // ioctl a frame; a removal between this and the draw still reaches Mesa).
    kms_.check_device("before the frame was drawn into its buffer");
    carried_.insert(carried_.end(), damage.begin(), damage.end());
    copy_frame(frame, std::exchange(carried_, {}));
    return true;
  }

  void show(std::uint64_t frame_number) override {
    const std::vector<PixelRegion> damage = take_shown_damage();
    std::string error;
    if (!egl_->swap({}, error)) throw DisplayLost("drm: " + kms_.card() + ": eglSwapBuffers failed (" + error + ")");
    gbm_bo* bo = gbm_surface_lock_front_buffer(surface_);
    if (!bo) {
      kms_.check_device("taking the drawn buffer for scanout");
      throw BackendError("drm: " + kms_.card() + ": gbm_surface_lock_front_buffer failed: no free scanout buffer");
    }
    auto* data = static_cast<BufferFb*>(gbm_bo_get_user_data(bo));
    if (!data) {
      data = new BufferFb{&kms_, kms_.framebuffer(gbm_bo_get_handle(bo).u32, gbm_bo_get_stride(bo))};
      gbm_bo_set_user_data(bo, data, destroy_fb_data);
    }
    kms_.flip(data->fb, top_left_origin(damage, surface_h_), frame_number);  // FB_DAMAGE_CLIPS: origin top-left
    (shown_bo_ ? queued_bo_ : shown_bo_) = bo;  // the first (the modeset) is on screen at once
  }

  std::vector<PresentedFrame> take_presented(int wait_ms) override { return kms_.take_presented(wait_ms); }
  std::uint64_t stalls() const override { return kms_.stalls(); }
  std::int64_t last_latch_ns() const override { return kms_.last_flip_ns(); }
  std::string display_info() const override {
    return kms_.info() + "; " + placement() + ", double buffered, " +
           (egl_->has_buffer_age() ? "buffer age" : "no buffer age: full copies");
  }

 private:
  void release() noexcept {
    egl_.reset();
    if (surface_) gbm_surface_destroy(std::exchange(surface_, nullptr));
    if (gbm_) gbm_device_destroy(std::exchange(gbm_, nullptr));
  }

  KmsOutput kms_;
  gbm_device* gbm_ = nullptr;
  gbm_surface* surface_ = nullptr;
  gbm_bo* shown_bo_ = nullptr;
  gbm_bo* queued_bo_ = nullptr;
  std::vector<PixelRegion> carried_;  // damage of frames a stall kept off the screen
};

}  // namespace

std::unique_ptr<DisplayBackend> create_drm_display(const DisplayOptions& options) {
  return std::make_unique<DrmDisplay>(options);
}

}  // namespace meter::platform::detail
