// Test helpers for animation sampling: build a sampler from plain keys, sample it into a vec4.
// Shared by view/engine/tests (behaviour) and tests/numerics (hard cases), which both need them.
#pragma once

#include <array>
#include <span>
#include <utility>
#include <vector>

#include "meter/engine/evaluation/animation.hpp"

namespace meter::engine::testing {

inline AnimSampler make(Interpolation i, int comps, std::vector<float> in, std::vector<float> out) {
  AnimSampler s;
  s.interpolation = i;
  s.components = comps;
  s.input = std::move(in);
  s.output = std::move(out);
  return s;
}

// The first s.components entries hold the sample; rot = normalise as a quaternion.
inline std::array<float, 4> at(const AnimSampler& s, double t, bool rot = false) {
  std::array<float, 4> v{};
  sample(s, t, std::span<float>(v.data(), static_cast<std::size_t>(s.components)), rot);
  return v;
}

}  // namespace meter::engine::testing
