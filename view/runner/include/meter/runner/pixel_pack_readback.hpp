// The readback stage on the GL thread: frames read from the resolved framebuffer into a ring of
// pixel-pack buffers (PBOs), each with a fence, and collected once the fence has signalled, so the
// render loop does not wait for the copy (GLES 3.0 core on EGL; GL 3.2 core on OSMesa's desktop
// profile: both backends have them). Synchronous fallback (`asynchronous = false`, or a context
// without a PBO: GL error at creation): glReadPixels into client memory at issue time; collect()
// then hands the frame on at once. Rows stay bottom-up: the writer thread flips them (platform::flip_rows).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include "meter/platform/gl_api.hpp"
#include "meter/platform/image.hpp"
#include "meter/runner/readback_frame.hpp"

namespace meter::runner {

class PixelPackReadback {
 public:
  // `depth`: buffers in flight (>= 1). The context must be current.
  PixelPackReadback(const platform::Gl& gl, int width, int height, std::size_t depth, bool asynchronous);
  ~PixelPackReadback();
  PixelPackReadback(const PixelPackReadback&) = delete;
  PixelPackReadback& operator=(const PixelPackReadback&) = delete;

  bool asynchronous() const { return !buffers_.empty(); }
  bool full() const { return in_flight_.size() >= depth_; }
  std::size_t in_flight() const { return in_flight_.size(); }
  // Starts reading `framebuffer` (single-sample, RGBA8, width x height) for `info`. When full(),
  // waits for the oldest read first (handing it to `done`).
  void issue(GLuint framebuffer, FrameInfo info, const std::function<void(ReadbackFrame&&)>& done);
  // Hands every finished read to `done`, oldest first; with `wait`, waits for all in flight.
  // Returns the nanoseconds spent waiting on fences.
  std::int64_t collect(bool wait, const std::function<void(ReadbackFrame&&)>& done);

 private:
  struct Pending {
    std::size_t buffer = 0;
    GLsync fence = nullptr;
    FrameInfo info;
    platform::Image image;  // the synchronous path's pixels
  };
  void finish(Pending& p, const std::function<void(ReadbackFrame&&)>& done);

  const platform::Gl& gl_;
  int width_, height_;
  std::size_t depth_;
  std::vector<GLuint> buffers_;  // empty: synchronous
  std::vector<bool> busy_;
  std::deque<Pending> in_flight_;
};

}  // namespace meter::runner
