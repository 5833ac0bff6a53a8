#include "meter/platform/display_damage.hpp"

namespace meter::platform {

DamageHistory::DamageHistory(int frame_width, int frame_height, int depth)
    : width_(frame_width), height_(frame_height), depth_(depth > 0 ? std::size_t(depth) : 1) {}

std::vector<PixelRegion> DamageHistory::repaint(int age, std::span<const PixelRegion> damage) const {
  const PixelRegion whole{0, 0, width_, height_};
  if (age <= 0 || std::size_t(age - 1) > recent_.size()) return {whole};
  std::vector<PixelRegion> out;
  auto add = [&](const PixelRegion& r) {
    const PixelRegion c = clip(r, width_, height_);
    if (!c.empty()) out.push_back(c);
  };
  for (const auto& r : damage) add(r);
  for (std::size_t i = 0; i + 1 < std::size_t(age); ++i)
    for (const auto& r : recent_[i]) add(r);
  // Many small boxes cost more scissored draws than one copy of the frame.
  if (out.size() > 32) return {whole};
  return out;
}

void DamageHistory::presented(std::span<const PixelRegion> damage) {
  std::vector<PixelRegion> kept;
  for (const auto& r : damage)
    if (const PixelRegion c = clip(r, width_, height_); !c.empty()) kept.push_back(c);
  recent_.push_front(std::move(kept));
  while (recent_.size() > depth_) recent_.pop_back();
}

long long area(std::span<const PixelRegion> boxes) {
  long long sum = 0;
  for (const auto& r : boxes)
    if (!r.empty()) sum += static_cast<long long>(r.width) * r.height;
  return sum;
}

std::vector<PixelRegion> top_left_origin(std::span<const PixelRegion> boxes, int surface_height) {
  std::vector<PixelRegion> out;
  out.reserve(boxes.size());
  for (const auto& r : boxes) out.push_back({r.x, surface_height - r.y - r.height, r.width, r.height});
  return out;
}

}  // namespace meter::platform
