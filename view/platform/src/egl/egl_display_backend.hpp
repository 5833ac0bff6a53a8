// What the two displays (--output wayland, --output drm) share above their EGL window: the
// GpuBackend answered from its context, and the copy of a frame into the window's back buffer:
// the frame's damage moved to where the frame sits on the surface (centred, black around it),
// repainted by the buffer's age, read back for the integrity monitor, remembered for the show.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "egl/egl_window.hpp"
#include "meter/platform/display.hpp"
#include "meter/platform/display_damage.hpp"

namespace meter::platform::detail {

// The EglWindow is made by the derived class once its native window exists (and released by it
// before that window goes); place() is called once the surface's size is known.
class EglDisplayBackend : public DisplayBackend {
 public:
  BackendKind kind() const override { return BackendKind::Egl; }
  std::string_view name() const override { return egl_platform_; }
  const Gl& gl() const override { return egl_->gl(); }
  std::string renderer_info() const override { return egl_->renderer_info(); }
  void make_current() override { egl_->make_current(); }
  void copy_more(const RenderTarget& frame, std::span<const PixelRegion> boxes) override;
  std::vector<Image> read_shown(std::span<const PixelRegion> boxes) override;
  std::uint64_t pixels_copied() const override { return copied_; }

 protected:
  explicit EglDisplayBackend(const char* platform) : egl_platform_(platform) {}
  // A `frame_w` x `frame_h` frame centred on a `surface_w` x `surface_h` surface.
  void place(int surface_w, int surface_h, int frame_w, int frame_h);
  // Copies the frame's `damage` (frame GL window coordinates) and what the back buffer lacks by its
  // age; a buffer repainted whole is cleared black around the frame first.
  void copy_frame(const RenderTarget& frame, std::span<const PixelRegion> damage);
  // The damage of the copies since the last show (surface GL window coordinates), recorded as
  // presented for the buffer ages to come.
  std::vector<PixelRegion> take_shown_damage();
  std::string placement() const;  // "the WxH frame at (x, y)"

  const char* egl_platform_;
  std::unique_ptr<EglWindow> egl_;
  int surface_w_ = 0, surface_h_ = 0, frame_w_ = 0, frame_h_ = 0;
  int origin_x_ = 0, origin_y_ = 0;  // the frame's top-left corner on the surface
  int gl_origin_y_ = 0;              // its bottom edge, from the surface's bottom (GL window coordinates)

 private:
  std::vector<PixelRegion> moved(std::span<const PixelRegion> boxes) const;

  std::optional<DamageHistory> history_;
  std::vector<PixelRegion> damage_;  // since the last show, surface coordinates
  std::uint64_t copied_ = 0;
};

}  // namespace meter::platform::detail
