// Screen boxes for partial redraw, in GL window coordinates (origin bottom-left, as glScissor):
// a primitive's projected bounds, and the union, overlap and normalisation of damaged regions.
#pragma once

#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/vocabulary.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::engine {

using platform::PixelRegion;

long long area(const PixelRegion& r);
PixelRegion unite(const PixelRegion& a, const PixelRegion& b);
bool overlap(const PixelRegion& a, const PixelRegion& b);
bool contains(const PixelRegion& outer, const PixelRegion& inner);  // inner lies wholly in outer

// Clips to the width x height target, then merges until the regions are disjoint (text is
// alpha-blended: a pixel in two regions would get it twice) and at most kMaxRegions remain (each
// region is one more pass over every draw call), merging first the pair whose union adds the
// least area.
constexpr std::size_t kMaxRegions = 4;
void normalise(std::vector<PixelRegion>& regions, int width, int height);

// Pixel box (padded 1 px) of a primitive's bounds under vp * world on a width x height target;
// nullopt when a corner is at or behind the eye (no finite box).
std::optional<PixelRegion> screen_box(const Primitive& prim, const glm::mat4& world, const glm::mat4& vp, int width,
                                      int height);

}  // namespace meter::engine
