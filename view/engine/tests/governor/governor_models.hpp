// Hand-built cost models for the governor's tests: every number is chosen so the expected
// choices can be worked out by hand (each test states its arithmetic).
#pragma once

#include <string>
#include <vector>

#include "meter/engine/governor/cost_model.hpp"

namespace meter::engine::governor::fixtures {

// The shadings of a test ladder, best first.
inline constexpr bridge::ShadingModel kShadingOrder[] = {
    bridge::ShadingModel::PbrMetallicRoughness, bridge::ShadingModel::BlinnPhong, bridge::ShadingModel::Gouraud,
    bridge::ShadingModel::Flat, bridge::ShadingModel::Unlit};

// A unit with `shadings` x `lods` levels; a_per_rank[lod * shadings + shading] is that level's
// ms per pixel (B = b for every level). psnr_per_rank, when given, is each level's PSNR.
inline UnitCosts unit(std::string name, int shadings, int lods, std::vector<double> a_per_rank, double b = 0.0,
                      std::vector<double> psnr_per_rank = {}) {
  UnitCosts u;
  u.name = std::move(name);
  u.shadings = shadings;
  u.lods = lods;
  u.levels.resize(std::size_t(shadings * lods));  // stored [shading * lods + lod]
  for (int l = 0; l < lods; ++l) {
    for (int s = 0; s < shadings; ++s) {
      const std::size_t rank = std::size_t(l * shadings + s);
      LevelCost& c = u.levels[std::size_t(s * lods + l)];
      c.shading = kShadingOrder[s];
      c.lod = l;
      c.cost = {a_per_rank.at(rank), b};
      if (!psnr_per_rank.empty() && rank > 0) c.psnr_db = psnr_per_rank.at(rank);
    }
  }
  return u;
}

inline UnitCosts safety_unit(std::string name, double a) {
  UnitCosts u = unit(std::move(name), 1, 1, {a});
  u.safety = true;
  return u;
}

// One full-quality rung (factor 1, nothing fixed), no overhead.
inline CostModel model(std::vector<UnitCosts> units) {
  CostModel m;
  m.globals.push_back(GlobalCost{});
  m.units = std::move(units);
  return m;
}

inline FrameLoad load(std::vector<double> pixels, bool full_frame = true) {
  FrameLoad l;
  l.drawn = true;
  l.full_frame = full_frame;
  for (double p : pixels) l.redrawn_pixels += p;
  l.unit_pixels = std::move(pixels);
  return l;
}

inline QualityChoice at(std::vector<UnitLevel> units, GlobalLevel g = {}) {
  QualityChoice c;
  c.global = g;
  c.units = std::move(units);
  return c;
}

}  // namespace meter::engine::governor::fixtures
