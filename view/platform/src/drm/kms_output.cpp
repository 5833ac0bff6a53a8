#include "drm/kms_output.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <utility>

namespace meter::platform::detail {
namespace {

std::int64_t kms_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void page_flip_done(int, unsigned sequence, unsigned sec, unsigned usec, void* data) {
  static_cast<KmsOutput*>(data)->on_flip(sequence, sec, usec);
}

// A device that went away (unplugged, driver unbound) answers ENODEV; anything else is a refusal.
[[noreturn]] void refused(const std::string& what, int error) {
  if (error == ENODEV || error == EIO) throw DisplayLost(what + ": " + std::strerror(error) + " (the device went away)");
  throw BackendError(what + ": " + std::strerror(error));
}

}  // namespace

KmsOutput::KmsOutput(const std::string& card, int frame_wait_ms, const std::string& modeset)
    : card_(card), frame_wait_ms_(frame_wait_ms) {
  if (modeset != "auto" && modeset != "atomic" && modeset != "legacy")
    throw BackendError("drm: modesetting '" + modeset + "': expected auto, atomic or legacy");
  try {
    find_output(card, modeset);
  } catch (...) {
    release();
    throw;
  }
}

KmsOutput::~KmsOutput() { release(); }

void KmsOutput::release() noexcept {
  if (fd_ < 0) return;
  if (flip_pending_) dispatch(frame_wait_ms_);
  if (mode_blob_) drmModeDestroyPropertyBlob(fd_, mode_blob_);
  close(std::exchange(fd_, -1));
}

void KmsOutput::find_output(const std::string& card, const std::string& modeset) {
  fd_ = open(card.c_str(), O_RDWR | O_CLOEXEC);
  if (fd_ < 0) throw BackendError("drm: cannot open " + card + ": " + std::strerror(errno));
  if (!drmIsMaster(fd_))
    throw BackendError("drm: " + card + " is driven by another process (this one is not its DRM master): one view per card");
  drmSetClientCap(fd_, DRM_CLIENT_CAP_UNIVERSAL_PLANES, 1);
  if (modeset == "legacy") {
    why_legacy_ = "asked for: --drm-modeset legacy";
  } else if (drmSetClientCap(fd_, DRM_CLIENT_CAP_ATOMIC, 1) == 0) {
    atomic_ = true;
  } else {
    why_legacy_ = std::string("the driver refused DRM_CLIENT_CAP_ATOMIC (") + std::strerror(errno) + ")";
    if (modeset == "atomic") throw BackendError("drm: " + card + ": " + why_legacy_ + " and --drm-modeset atomic asks for it");
  }
  drmModeRes* res = drmModeGetResources(fd_);
  if (!res) throw BackendError("drm: " + card + " is not a KMS device (drmModeGetResources: " + std::strerror(errno) + ")");
  std::string tried;
  for (int i = 0; i < res->count_connectors && !connector_; ++i) {
    drmModeConnector* c = drmModeGetConnector(fd_, res->connectors[i]);
    if (!c) continue;
    const std::string name = std::string(drmModeGetConnectorTypeName(c->connector_type) ? drmModeGetConnectorTypeName(c->connector_type) : "connector") + "-" + std::to_string(c->connector_type_id);
    tried += " " + name + (c->connection == DRM_MODE_CONNECTED ? (c->count_modes ? " (connected)" : " (connected, no modes)") : " (not connected)");
    if (c->connection == DRM_MODE_CONNECTED && c->count_modes > 0) {
      int pick = 0;
      for (int m = 0; m < c->count_modes; ++m)
        if (c->modes[m].type & DRM_MODE_TYPE_PREFERRED) { pick = m; break; }
      const drmModeModeInfo& mode = c->modes[pick];
      mode_.assign(reinterpret_cast<const std::uint8_t*>(&mode), reinterpret_cast<const std::uint8_t*>(&mode) + sizeof mode);
      width_ = mode.hdisplay, height_ = mode.vdisplay, refresh_mhz_ = mode.vrefresh * 1000;
      // The CRTC: the one its encoder drives now, else the first any of its encoders can drive.
      for (int e = 0; e < c->count_encoders && crtc_index_ < 0; ++e) {
        drmModeEncoder* enc = drmModeGetEncoder(fd_, c->encoders[e]);
        if (!enc) continue;
        for (int k = 0; k < res->count_crtcs; ++k)
          if ((enc->crtc_id && res->crtcs[k] == enc->crtc_id) || (!enc->crtc_id && (enc->possible_crtcs & (1u << k)))) {
            crtc_index_ = k;
            break;
          }
        drmModeFreeEncoder(enc);
      }
      if (crtc_index_ >= 0) {
        connector_ = c->connector_id;
        crtc_ = res->crtcs[crtc_index_];
        connector_name_ = name;
      }
    }
    drmModeFreeConnector(c);
  }
  drmModeFreeResources(res);
  if (!connector_) throw BackendError("drm: " + card + " has no connected connector with a mode and a CRTC; tried:" + (tried.empty() ? " none" : tried));
  find_plane();
  if (atomic_ && !plane_) throw BackendError("drm: " + card + ": no primary plane for the CRTC of " + connector_name_);
  if (atomic_) read_properties();
}

// The CRTC's primary plane and the names of its properties (a client without the atomic cap is
// shown fewer: FB_ID, SRC_*, FB_DAMAGE_CLIPS are atomic-only).
void KmsOutput::find_plane() {
  drmModePlaneRes* planes = drmModeGetPlaneResources(fd_);
  for (std::uint32_t i = 0; planes && i < planes->count_planes && !plane_; ++i) {
    drmModePlane* p = drmModeGetPlane(fd_, planes->planes[i]);
    if (!p) continue;
    if (p->possible_crtcs & (1u << crtc_index_)) {
      drmModeObjectProperties* props = drmModeObjectGetProperties(fd_, p->plane_id, DRM_MODE_OBJECT_PLANE);
      std::string names;
      for (std::uint32_t k = 0; props && k < props->count_props; ++k) {
        drmModePropertyRes* pr = drmModeGetProperty(fd_, props->props[k]);
        if (!pr) continue;
        names += std::string(names.empty() ? "" : " ") + pr->name;
        if (std::strcmp(pr->name, "type") == 0 && props->prop_values[k] == DRM_PLANE_TYPE_PRIMARY) plane_ = p->plane_id;
        drmModeFreeProperty(pr);
      }
      drmModeFreeObjectProperties(props);
      if (plane_) plane_properties_ = names;
    }
    drmModeFreePlane(p);
  }
  if (planes) drmModeFreePlaneResources(planes);
}

// Property ids by name; 0 when `required` is false and the object lacks it.
std::uint32_t KmsOutput::property(std::uint32_t object, std::uint32_t type, const char* name, bool required) const {
  drmModeObjectProperties* props = drmModeObjectGetProperties(fd_, object, type);
  std::uint32_t id = 0;
  for (std::uint32_t k = 0; props && k < props->count_props && !id; ++k) {
    drmModePropertyRes* pr = drmModeGetProperty(fd_, props->props[k]);
    if (pr && std::strcmp(pr->name, name) == 0) id = pr->prop_id;
    drmModeFreeProperty(pr);
  }
  drmModeFreeObjectProperties(props);
  if (!id && required) throw BackendError("drm: " + card_ + ": KMS object " + std::to_string(object) + " has no property " + name);
  return id;
}

void KmsOutput::read_properties() {
  p_crtc_id_ = property(connector_, DRM_MODE_OBJECT_CONNECTOR, "CRTC_ID");
  p_mode_id_ = property(crtc_, DRM_MODE_OBJECT_CRTC, "MODE_ID");
  p_active_ = property(crtc_, DRM_MODE_OBJECT_CRTC, "ACTIVE");
  p_fb_id_ = property(plane_, DRM_MODE_OBJECT_PLANE, "FB_ID");
  p_plane_crtc_ = property(plane_, DRM_MODE_OBJECT_PLANE, "CRTC_ID");
  const char* src[4] = {"SRC_X", "SRC_Y", "SRC_W", "SRC_H"};
  const char* dst[4] = {"CRTC_X", "CRTC_Y", "CRTC_W", "CRTC_H"};
  for (int i = 0; i < 4; ++i) {
    p_src_[i] = property(plane_, DRM_MODE_OBJECT_PLANE, src[i]);
    p_dst_[i] = property(plane_, DRM_MODE_OBJECT_PLANE, dst[i]);
  }
  p_damage_ = property(plane_, DRM_MODE_OBJECT_PLANE, "FB_DAMAGE_CLIPS", false);
  if (drmModeCreatePropertyBlob(fd_, mode_.data(), mode_.size(), &mode_blob_) != 0)
    refused("drm: " + card_ + ": cannot make the mode blob", errno);
}

std::uint32_t KmsOutput::framebuffer(std::uint32_t handle, std::uint32_t stride) {
  const std::uint32_t handles[4] = {handle}, pitches[4] = {stride}, offsets[4] = {};
  std::uint32_t fb = 0;
  if (drmModeAddFB2(fd_, std::uint32_t(width_), std::uint32_t(height_), 0x34325258 /* XR24 */, handles, pitches, offsets, &fb, 0) != 0)
    refused("drm: " + card_ + ": drmModeAddFB2 " + std::to_string(width_) + "x" + std::to_string(height_) + " XRGB8888", errno);
  return fb;
}

void KmsOutput::remove_framebuffer(std::uint32_t fb) { drmModeRmFB(fd_, fb); }

void KmsOutput::modeset(std::uint32_t fb) {
  const std::string mode = std::to_string(width_) + "x" + std::to_string(height_) + "@" + std::to_string(refresh_mhz_ / 1000);
  if (!atomic_) {
    std::uint32_t connector = connector_;
    auto* info = reinterpret_cast<drmModeModeInfo*>(mode_.data());
    if (drmModeSetCrtc(fd_, crtc_, fb, 0, 0, &connector, 1, info) != 0)
      refused("drm: " + card_ + ": legacy drmModeSetCrtc of " + mode + " on " + connector_name_ + " refused", errno);
    return;
  }
  drmModeAtomicReq* req = drmModeAtomicAlloc();
  drmModeAtomicAddProperty(req, connector_, p_crtc_id_, crtc_);
  drmModeAtomicAddProperty(req, crtc_, p_mode_id_, mode_blob_);
  drmModeAtomicAddProperty(req, crtc_, p_active_, 1);
  drmModeAtomicAddProperty(req, plane_, p_fb_id_, fb);
  drmModeAtomicAddProperty(req, plane_, p_plane_crtc_, crtc_);
  const std::uint64_t src[4] = {0, 0, std::uint64_t(width_) << 16, std::uint64_t(height_) << 16};
  const std::uint64_t dst[4] = {0, 0, std::uint64_t(width_), std::uint64_t(height_)};
  for (int i = 0; i < 4; ++i) {
    drmModeAtomicAddProperty(req, plane_, p_src_[i], src[i]);
    drmModeAtomicAddProperty(req, plane_, p_dst_[i], dst[i]);
  }
  const int rc = drmModeAtomicCommit(fd_, req, DRM_MODE_ATOMIC_ALLOW_MODESET, nullptr);
  const int error = errno;
  drmModeAtomicFree(req);
  if (rc != 0) refused("drm: " + card_ + ": atomic modeset of " + mode + " on " + connector_name_ + " (CRTC " + std::to_string(crtc_) + ", primary plane " + std::to_string(plane_) + ") refused", error);
}

void KmsOutput::flip(std::uint32_t fb, std::span<const PixelRegion> damage, std::uint64_t frame) {
  if (!mode_set_) {
    modeset(fb);  // shown from the modeset on, no event: its time is the commit's
    mode_set_ = true;
    PresentedFrame shown;
    shown.frame = frame;
    shown.presented_ns = kms_now_ns();
    shown.refresh_ns = refresh_mhz_ ? std::uint32_t(1e12 / refresh_mhz_) : 0;
    presented_.push_back(shown);
    return;
  }
  int rc = 0;
  if (atomic_) {
    drmModeAtomicReq* req = drmModeAtomicAlloc();
    drmModeAtomicAddProperty(req, plane_, p_fb_id_, fb);
    std::uint32_t blob = 0;
    if (p_damage_ && !damage.empty()) {
      std::vector<drm_mode_rect> clips;
      for (const auto& r : damage) clips.push_back({r.x, r.y, r.x + r.width, r.y + r.height});
      if (drmModeCreatePropertyBlob(fd_, clips.data(), clips.size() * sizeof(drm_mode_rect), &blob) == 0)
        drmModeAtomicAddProperty(req, plane_, p_damage_, blob);
    }
    rc = drmModeAtomicCommit(fd_, req, DRM_MODE_PAGE_FLIP_EVENT | DRM_MODE_ATOMIC_NONBLOCK, this);
    const int error = errno;
    drmModeAtomicFree(req);
    if (blob) drmModeDestroyPropertyBlob(fd_, blob);
    errno = error;
  } else {
    rc = drmModePageFlip(fd_, crtc_, fb, DRM_MODE_PAGE_FLIP_EVENT, this);
  }
  if (rc != 0) refused("drm: " + card_ + ": page flip on " + connector_name_ + " refused", errno);
  flip_pending_ = true;
  pending_frames_.push_back(frame);
}

void KmsOutput::on_flip(std::uint32_t sequence, std::uint32_t sec, std::uint32_t usec) {
  flip_pending_ = false;
  if (pending_frames_.empty()) return;
  PresentedFrame shown;
  shown.frame = pending_frames_.front();
  pending_frames_.pop_front();
  shown.presented_ns = std::int64_t(sec) * 1'000'000'000 + std::int64_t(usec) * 1000;
  last_flip_ns_ = shown.presented_ns;
  shown.sequence = sequence;
  shown.refresh_ns = refresh_mhz_ ? std::uint32_t(1e12 / refresh_mhz_) : 0;
  shown.flags = 1;  // vsync: a page flip completes on vblank
  presented_.push_back(shown);
}

bool KmsOutput::dispatch(int timeout_ms) {
  pollfd p{fd_, POLLIN, 0};
  const int n = poll(&p, 1, timeout_ms);
  if (n < 0 && errno != EINTR) refused("drm: " + card_ + ": waiting for a page flip", errno);
  if (n <= 0) return false;
  if (p.revents & (POLLERR | POLLHUP | POLLNVAL)) throw DisplayLost("drm: " + card_ + ": the device went away while waiting for a page flip");
  drmEventContext ctx{};
  ctx.version = 2;
  ctx.page_flip_handler = page_flip_done;
  if (drmHandleEvent(fd_, &ctx) != 0) refused("drm: " + card_ + ": reading page-flip events", errno);
  return true;
}

bool KmsOutput::wait_for_flip() {
  const std::int64_t began = kms_now_ns();
  while (flip_pending_) {
    const int left = frame_wait_ms_ - int((kms_now_ns() - began) / 1'000'000);
    if (left <= 0 || !dispatch(left)) {
      check_device("while waiting for a page flip");  // a removed device may send no event
      ++stalls_;  // no vblank came: a frozen display
      return false;
    }
  }
  return true;
}

void KmsOutput::check_device(const char* doing) const {
  drm_mode_crtc state{};
  state.crtc_id = crtc_;
  if (drmIoctl(fd_, DRM_IOCTL_MODE_GETCRTC, &state) == 0) return;
  const int error = errno;
  if (error == ENODEV || error == EIO)
    throw DisplayLost("drm: " + card_ + " (" + connector_name_ + ", CRTC " + std::to_string(crtc_) + "): the device went away " +
                      doing + " (DRM_IOCTL_MODE_GETCRTC: " + std::strerror(error) + ")");
}

std::vector<PresentedFrame> KmsOutput::take_presented(int wait_ms) {
  if (flip_pending_) {
    if (wait_ms > 0) {
      const int saved = frame_wait_ms_;
      frame_wait_ms_ = wait_ms;
      wait_for_flip();
      frame_wait_ms_ = saved;
    } else {
      dispatch(0);
    }
  } else if (wait_ms > 0) {
    check_device("while the frame was held");  // nothing pending: only an ioctl tells
  }
  return std::exchange(presented_, {});
}

std::string KmsOutput::info() const {
  return "drm " + card_ + ": " + connector_name_ + " " + std::to_string(width_) + "x" + std::to_string(height_) + "@" +
         std::to_string(refresh_mhz_ / 1000) + ", CRTC " + std::to_string(crtc_) +
         (atomic_ ? ", atomic, primary plane " + std::to_string(plane_) + (p_damage_ ? ", FB_DAMAGE_CLIPS" : ", no FB_DAMAGE_CLIPS")
                  : ", legacy drmModeSetCrtc + drmModePageFlip (" + why_legacy_ + ")") +
         (plane_ ? ", plane properties: " + plane_properties_ : std::string());
}

}  // namespace meter::platform::detail
