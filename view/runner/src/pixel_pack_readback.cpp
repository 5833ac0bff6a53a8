#include "meter/runner/pixel_pack_readback.hpp"

#include <chrono>
#include <cstring>
#include <stdexcept>

#include "meter/runner/stage_meter.hpp"

namespace meter::runner {

PixelPackReadback::PixelPackReadback(const platform::Gl& gl, int width, int height, std::size_t depth,
                                     bool asynchronous)
    : gl_(gl), width_(width), height_(height), depth_(depth == 0 ? 1 : depth) {
  if (!asynchronous) return;
  const auto bytes = static_cast<GLsizeiptr>(width) * height * 4;
  buffers_.resize(depth_);
  busy_.assign(depth_, false);
  gl_.GenBuffers(static_cast<GLsizei>(depth_), buffers_.data());
  for (GLuint b : buffers_) {
    gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, b);
    gl_.BufferData(GL_PIXEL_PACK_BUFFER, bytes, nullptr, GL_STREAM_READ);
  }
  gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  if (gl_.GetError() != GL_NO_ERROR) {  // no usable pixel-pack buffers: the synchronous fallback
    gl_.DeleteBuffers(static_cast<GLsizei>(depth_), buffers_.data());
    buffers_.clear();
    busy_.clear();
  }
}

PixelPackReadback::~PixelPackReadback() {
  for (auto& p : in_flight_) {
    if (p.fence) gl_.DeleteSync(p.fence);
  }
  if (!buffers_.empty()) gl_.DeleteBuffers(static_cast<GLsizei>(buffers_.size()), buffers_.data());
}

void PixelPackReadback::issue(GLuint framebuffer, FrameInfo info, const std::function<void(ReadbackFrame&&)>& done) {
  if (full()) {
    Pending& oldest = in_flight_.front();
    if (oldest.fence) gl_.ClientWaitSync(oldest.fence, GL_SYNC_FLUSH_COMMANDS_BIT, GL_TIMEOUT_IGNORED);
    finish(oldest, done);
    in_flight_.pop_front();
  }
  Pending p;
  p.info = std::move(info);
  gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  gl_.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
  if (buffers_.empty()) {
    p.image = platform::Image(width_, height_);
    gl_.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, p.image.rgba.data());
  } else {
    std::size_t b = 0;
    while (busy_[b]) ++b;  // not full: one is free
    busy_[b] = true;
    p.buffer = b;
    gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, buffers_[b]);
    gl_.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    p.fence = gl_.FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    gl_.Flush();
  }
  platform::check_gl(gl_, "reading a frame back (" + std::to_string(width_) + "x" + std::to_string(height_) + ")");
  in_flight_.push_back(std::move(p));
}

std::int64_t PixelPackReadback::collect(bool wait, const std::function<void(ReadbackFrame&&)>& done) {
  std::int64_t waited = 0;
  while (!in_flight_.empty()) {
    Pending& p = in_flight_.front();
    if (p.fence) {
      const auto began = std::chrono::steady_clock::now();
      const GLenum r = gl_.ClientWaitSync(p.fence, GL_SYNC_FLUSH_COMMANDS_BIT, wait ? GL_TIMEOUT_IGNORED : 0);
      waited += ns_since(began);
      if (r == GL_TIMEOUT_EXPIRED) break;
      if (r == GL_WAIT_FAILED) throw platform::GlError("reading a frame back: glClientWaitSync failed");
    }
    finish(p, done);
    in_flight_.pop_front();
  }
  return waited;
}

void PixelPackReadback::finish(Pending& p, const std::function<void(ReadbackFrame&&)>& done) {
  ReadbackFrame out;
  out.info = std::move(p.info);
  if (p.fence) {
    gl_.DeleteSync(p.fence);
    p.fence = nullptr;
    out.image = platform::Image(width_, height_);
    const std::size_t bytes = out.image.rgba.size();
    gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, buffers_[p.buffer]);
    const void* mapped = gl_.MapBufferRange(GL_PIXEL_PACK_BUFFER, 0, static_cast<GLsizeiptr>(bytes), GL_MAP_READ_BIT);
    if (!mapped) {
      gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
      throw platform::GlError("reading a frame back: glMapBufferRange of the pixel-pack buffer failed");
    }
    std::memcpy(out.image.rgba.data(), mapped, bytes);
    gl_.UnmapBuffer(GL_PIXEL_PACK_BUFFER);
    gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    busy_[p.buffer] = false;
  } else {
    out.image = std::move(p.image);
  }
  done(std::move(out));
}

}  // namespace meter::runner
