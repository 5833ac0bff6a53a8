// The KMS side of meter-view's --output drm: the card, its first connected connector, the mode,
// the CRTC and its primary plane; atomic modesetting (legacy SetCrtc / PageFlip where the driver
// refuses atomic or the caller asks for it, and then said), page flips on vblank with
// FB_DAMAGE_CLIPS, the flip events as presentation feedback; a device that went away (unplugged,
// its driver unbound) noticed on the next flip, after a flip that did not come, and while a frame is
// held. No EGL or GBM here (drm_display.cpp).
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "meter/platform/display.hpp"

namespace meter::platform::detail {

class KmsOutput {
 public:
  // Opens `card`, takes the first connected connector and its preferred mode (else the first),
  // a CRTC its encoders can drive and that CRTC's primary plane; `modeset` is auto, atomic or
  // legacy (DisplayOptions::drm_modeset). Throws BackendError naming the card and what was tried
  // (no connector, no mode, no CRTC, no plane, another process is DRM master, atomic refused).
  KmsOutput(const std::string& card, int frame_wait_ms, const std::string& modeset);
  ~KmsOutput();
  KmsOutput(const KmsOutput&) = delete;
  KmsOutput& operator=(const KmsOutput&) = delete;

  int fd() const { return fd_; }
  const std::string& card() const { return card_; }
  int width() const { return width_; }
  int height() const { return height_; }
  bool atomic() const { return atomic_; }
  std::string info() const;

  // A framebuffer for a scanout buffer (handle, stride), made once per buffer.
  std::uint32_t framebuffer(std::uint32_t handle, std::uint32_t stride);
  void remove_framebuffer(std::uint32_t fb);
  // Shows `fb` from the next vblank: the first call sets the mode (ALLOW_MODESET), later ones flip
  // the primary plane with `damage` (top-left origin, mode pixels) as FB_DAMAGE_CLIPS. A refused
  // commit throws BackendError (the mode) or DisplayLost (the device gone).
  void flip(std::uint32_t fb, std::span<const PixelRegion> damage, std::uint64_t frame);
  // Waits for the flip queued last (at most frame_wait_ms; a later one counts as a stall).
  // Returns true when no flip is pending any more.
  bool wait_for_flip();
  // The flip events come in; with `wait_ms` > 0 and no flip pending (a frame held), the device is
  // asked whether it is still there (check_device).
  std::vector<PresentedFrame> take_presented(int wait_ms);
  // Throws DisplayLost naming the card and `doing` when the device went away (a KMS ioctl answers
  // ENODEV or EIO): a removed device's fd stays open, and only an ioctl tells that it is gone.
  void check_device(const char* doing) const;  // `doing`: a literal, no string built per frame
  std::uint64_t stalls() const { return stalls_; }
  // The vblank time of the last page flip event (CLOCK_MONOTONIC ns; 0: none yet).
  std::int64_t last_flip_ns() const { return last_flip_ns_; }

  // The page-flip event handler calls this.
  void on_flip(std::uint32_t sequence, std::uint32_t sec, std::uint32_t usec);

 private:
  void find_output(const std::string& card, const std::string& modeset);
  void find_plane();
  void read_properties();
  std::uint32_t property(std::uint32_t object, std::uint32_t type, const char* name, bool required = true) const;
  void modeset(std::uint32_t fb);
  bool dispatch(int timeout_ms);
  void release() noexcept;

  std::string card_;
  int frame_wait_ms_;
  int fd_ = -1;
  bool atomic_ = false;
  std::string why_legacy_;
  std::string plane_properties_;  // the primary plane's property names, as the driver shows them
  std::uint32_t connector_ = 0, crtc_ = 0, plane_ = 0, mode_blob_ = 0;
  int crtc_index_ = -1;
  std::string connector_name_;
  std::vector<std::uint8_t> mode_;  // drmModeModeInfo bytes
  int width_ = 0, height_ = 0;
  std::uint32_t refresh_mhz_ = 0;
  bool mode_set_ = false;
  std::uint32_t p_crtc_id_ = 0, p_mode_id_ = 0, p_active_ = 0;  // connector CRTC_ID, crtc MODE_ID/ACTIVE
  std::uint32_t p_fb_id_ = 0, p_plane_crtc_ = 0, p_src_[4] = {}, p_dst_[4] = {}, p_damage_ = 0;
  bool flip_pending_ = false;
  std::int64_t last_flip_ns_ = 0;
  std::deque<std::uint64_t> pending_frames_;
  std::vector<PresentedFrame> presented_;
  std::uint64_t stalls_ = 0;
};

}  // namespace meter::platform::detail
