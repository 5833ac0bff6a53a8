#include "egl/egl_display_backend.hpp"

#include <string>
#include <utility>

#include "meter/platform/flip_rows.hpp"

namespace meter::platform::detail {

void EglDisplayBackend::place(int surface_w, int surface_h, int frame_w, int frame_h) {
  surface_w_ = surface_w, surface_h_ = surface_h, frame_w_ = frame_w, frame_h_ = frame_h;
  origin_x_ = (surface_w - frame_w) / 2;
  origin_y_ = (surface_h - frame_h) / 2;
  gl_origin_y_ = surface_h - origin_y_ - frame_h;
  history_.emplace(surface_w, surface_h);
}

std::vector<PixelRegion> EglDisplayBackend::moved(std::span<const PixelRegion> boxes) const {
  std::vector<PixelRegion> out;
  for (const auto& r : boxes)
    if (const PixelRegion c = clip(r, frame_w_, frame_h_); !c.empty())
      out.push_back({c.x + origin_x_, c.y + gl_origin_y_, c.width, c.height});
  return out;
}

void EglDisplayBackend::copy_frame(const RenderTarget& frame, std::span<const PixelRegion> damage) {
  const std::vector<PixelRegion> frame_damage = moved(damage);
  std::vector<PixelRegion> repaint = history_->repaint(egl_->buffer_age(), frame_damage);
  const PixelRegion whole{0, 0, surface_w_, surface_h_};
  if (repaint.size() == 1 && repaint[0] == whole && (surface_w_ != frame_w_ || surface_h_ != frame_h_)) {
    // A buffer of unknown contents on a surface larger than the frame: black around the frame,
    // then all of the frame.
    const Gl& gl = egl_->gl();
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl.Disable(GL_SCISSOR_TEST);
    gl.ClearColor(0, 0, 0, 1);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    repaint = {PixelRegion{origin_x_, gl_origin_y_, frame_w_, frame_h_}};
  }
  egl_->blit().draw(frame, origin_x_, origin_y_, surface_h_, repaint);
  copied_ += static_cast<std::uint64_t>(area(repaint));
  damage_.insert(damage_.end(), frame_damage.begin(), frame_damage.end());
}

void EglDisplayBackend::copy_more(const RenderTarget& frame, std::span<const PixelRegion> boxes) {
  const std::vector<PixelRegion> more = moved(boxes);
  if (more.empty()) return;
  egl_->blit().draw(frame, origin_x_, origin_y_, surface_h_, more);
  copied_ += static_cast<std::uint64_t>(area(more));
  damage_.insert(damage_.end(), more.begin(), more.end());
}

std::vector<Image> EglDisplayBackend::read_shown(std::span<const PixelRegion> boxes) {
  const Gl& gl = egl_->gl();
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  gl.ReadBuffer(GL_BACK);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  std::vector<Image> out(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const PixelRegion r = clip(boxes[i], frame_w_, frame_h_);
    if (r.empty()) continue;
    Image& image = out[i];
    image.width = r.width, image.height = r.height;
    image.rgba.resize(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height) * 4);
    gl.ReadPixels(r.x + origin_x_, r.y + gl_origin_y_, r.width, r.height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    flip_rows(image);  // GL rows are bottom-up; Image rows are top-down
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  check_gl(gl, std::string(egl_platform_) + ": reading back the shown frame's regions");
  return out;
}

std::vector<PixelRegion> EglDisplayBackend::take_shown_damage() {
  std::vector<PixelRegion> damage = std::exchange(damage_, {});
  history_->presented(damage);
  return damage;
}

std::string EglDisplayBackend::placement() const {
  return "the " + std::to_string(frame_w_) + "x" + std::to_string(frame_h_) + " frame at (" + std::to_string(origin_x_) +
         ", " + std::to_string(origin_y_) + ")";
}

}  // namespace meter::platform::detail
