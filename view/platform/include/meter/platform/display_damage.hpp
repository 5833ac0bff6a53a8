// Which boxes of a reused back buffer must be written again: a display's swap chain hands back a
// buffer last shown `age` presents ago (EGL_EXT_buffer_age), so it lacks this frame's damage and
// that of the age - 1 frames shown since. Pure: no GL.
#pragma once

#include <deque>
#include <span>
#include <vector>

#include "meter/platform/render_target.hpp"

namespace meter::platform {

class DamageHistory {
 public:
  // `frame_width` x `frame_height`: the frame (and buffer) size; `depth`: how many presents are
  // remembered (an older buffer is repainted whole).
  DamageHistory(int frame_width, int frame_height, int depth = 4);

  // The boxes to write into a buffer of `age` (0: unknown contents) for a frame whose own damage
  // is `damage`: the whole frame when the age is unknown or older than the history, else this
  // frame's boxes and those of the age - 1 presents before it.
  std::vector<PixelRegion> repaint(int age, std::span<const PixelRegion> damage) const;
  // Records a presented frame's damage (cut to the frame).
  void presented(std::span<const PixelRegion> damage);

 private:
  int width_, height_;
  std::size_t depth_;
  std::deque<std::vector<PixelRegion>> recent_;  // newest first
};

// The sum of the boxes' areas (an overlap counted twice).
long long area(std::span<const PixelRegion> boxes);

// The boxes (GL window coordinates: origin bottom-left) of a `surface_height`-high surface with
// their origin top-left, as KMS takes damage (FB_DAMAGE_CLIPS).
std::vector<PixelRegion> top_left_origin(std::span<const PixelRegion> boxes, int surface_height);

}  // namespace meter::platform
