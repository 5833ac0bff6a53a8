// A GL backend whose frames reach a display: a Wayland compositor's surface (xdg-shell toplevel)
// or a KMS CRTC. The renderer draws into its RenderTarget FBOs on this backend's context as on the
// offscreen backends; copy() copies the resolved frame 1:1 into the surface's back buffer (the
// boxes that changed since that buffer was last shown, by its buffer age), show() shows it.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::platform {

struct DisplayOptions {
  // "wayland" (the compositor of $WAYLAND_DISPLAY) or "wayland:NAME" (socket NAME in
  // $XDG_RUNTIME_DIR, or an absolute path).
  std::string target;
  int width = 0, height = 0;  // the frame's size: the surface's buffers are this size
  bool fullscreen = true;     // xdg_toplevel.set_fullscreen; a smaller frame is centred by the compositor
  int frame_wait_ms = 1000;   // a frame callback later than this counts as a stall (a frozen display)
  // KMS only: how the mode is set and frames are flipped. "auto": atomic where the driver takes
  // DRM_CLIENT_CAP_ATOMIC, else legacy; "atomic": refused where the driver refuses it; "legacy":
  // drmModeSetCrtc + drmModePageFlip, as on a driver without atomic modesetting.
  std::string drm_modeset = "auto";
};

// When a frame reached the screen, from the compositor's presentation feedback.
struct PresentedFrame {
  std::uint64_t frame = 0;        // the number present() was given
  bool discarded = false;         // replaced before it was shown (never on screen)
  std::int64_t presented_ns = 0;  // CLOCK_MONOTONIC: the time the frame turned into light
  std::uint32_t refresh_ns = 0;   // the output's refresh period (0: unknown)
  std::uint64_t sequence = 0;     // the output's refresh counter (vblank), when it has one
  std::uint32_t flags = 0;        // wp_presentation_feedback kinds: 1 vsync, 2 hw_clock, 4 hw_completion, 8 zero_copy
};

// The display went away (the compositor closed the connection or the window, the KMS device was
// removed): the process ends
// with its own exit code (ViewExit::DisplayLost).
class DisplayLost : public BackendError {
 public:
  using BackendError::BackendError;
};

class DisplayBackend : public GpuBackend {
 public:
  // A frame reaches the screen in three steps, so that what will be shown can be read back (the
  // integrity monitor) and repaired (its safe path) before it is: copy, read_shown / copy_more,
  // show. present() is the three without a read.
  //
  // Copies `frame` (the renderer's resolved target, frame-sized) into the back buffer: `damage`
  // (the boxes of the frame, GL window coordinates, written since the last copy) and what the
  // buffer lacks by its age. Waits first for the previous show's frame callback or page flip (the
  // pacing: at most one frame queued ahead of the screen; no wait after ready_for_frame() said
  // true). Returns false when no buffer can take the frame now (a page flip still pending after
  // the wait: a stall; its damage goes with the next copy). Throws DisplayLost when the display is
  // gone.
  virtual bool copy(const RenderTarget& frame, std::span<const PixelRegion> damage) = 0;
  // After copy(): more boxes of `frame` into the same back buffer (a repair after the copy).
  virtual void copy_more(const RenderTarget& frame, std::span<const PixelRegion> boxes) = 0;
  // After copy(): the boxes (frame GL window coordinates) read back from the back buffer, rows
  // top-down, 8-bit RGBA: the pixels the screen will show.
  virtual std::vector<Image> read_shown(std::span<const PixelRegion> boxes) = 0;
  // After copy(): shows the back buffer as frame `frame_number`, its damage the boxes copied.
  virtual void show(std::uint64_t frame_number) = 0;
  // Whether the screen took the last show (its frame callback came, or the wait for it ran out:
  // copy() would not wait), reading the display's events for at most `wait_ms`. The live loop asks
  // before it draws, so that a frame draws the newest state and is shown as soon as it is drawn,
  // one frame in flight. Throws DisplayLost when the display is gone. Displays whose copy() does
  // its own wait (KMS: the page flip) answer true.
  virtual bool ready_for_frame(int wait_ms) {
    (void)wait_ms;
    return true;
  }
  // When the screen last took a frame (CLOCK_MONOTONIC ns; 0: not yet): the arrival of the last
  // commit's frame callback (the compositor's repaint), or the vblank of the last page flip. Late
  // latching predicts the next latch from it.
  virtual std::int64_t last_latch_ns() const { return 0; }
  void present(const RenderTarget& frame, std::span<const PixelRegion> damage, std::uint64_t frame_number) {
    if (copy(frame, damage)) show(frame_number);
  }
  // The feedback that has arrived, in the order the frames were presented (taken once). With
  // `wait_ms` > 0, waits that long at most for the feedback of every frame presented so far.
  virtual std::vector<PresentedFrame> take_presented(int wait_ms = 0) = 0;
  // Frame callbacks or page flips that came later than DisplayOptions::frame_wait_ms (the display froze).
  virtual std::uint64_t stalls() const = 0;
  // Pixels copied into back buffers so far, and pixels of the frames' damage: a partial redraw
  // stays partial on the display when the first stays close to the second.
  virtual std::uint64_t pixels_copied() const = 0;
  // One line for logs: the protocol, the surface, what the compositor offered.
  virtual std::string display_info() const = 0;
};

// Opens the display named by options.target. Throws BackendError naming what was tried.
std::unique_ptr<DisplayBackend> open_display(const DisplayOptions& options);

}  // namespace meter::platform
