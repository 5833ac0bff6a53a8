#include "meter/calibrate/cost_samples.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

namespace meter::calibrate {
namespace gov = engine::governor;
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

std::string level_name(const gov::UnitLadder& ladder, const gov::UnitLevel& l) {
  return ladder.name + " " + bridge::to_string(ladder.shadings.at(static_cast<std::size_t>(l.shading))) + "/lod" + std::to_string(l.lod);
}

}  // namespace

gov::LinearCost level_cost(const std::vector<gov::CostSample>& samples) {
  std::vector<double> ms;
  std::set<double> pixels;
  for (const auto& s : samples) ms.push_back(s.ms), pixels.insert(s.pixels);
  const gov::LinearCost flat{0.0, std::max(0.0, median(ms))};
  if (pixels.size() < 2) return flat;
  const gov::CostFit f = gov::fit_cost(samples);
  if (!(f.a_ms_per_pixel > 0.0)) return flat;
  return {f.a_ms_per_pixel, std::max(0.0, f.b_ms)};
}

gov::CostFile cost_file(const CostMeasurements& m) {
  gov::CostFile file;
  file.backend = m.backend;
  file.package = m.package;
  file.overhead = {0.0, std::max(0.0, m.empty_ms)};
  const std::size_t scales = m.unit_pixels.size();
  std::set<std::string> names;
  std::vector<gov::LinearCost> base(m.ladders.size());  // each unit's level-0 cost
  for (std::size_t u = 0; u < m.ladders.size(); ++u) {
    const auto& ladder = m.ladders[u];
    if (!names.insert(ladder.name).second)
      throw std::invalid_argument("two draw units are named \"" + ladder.name + "\": the cost file keys units by name");
    gov::UnitCostEntry entry{ladder.name, {}};
    for (std::size_t sh = 0; sh < ladder.shadings.size(); ++sh)
      for (std::size_t lod = 0; lod < ladder.lod_errors.size(); ++lod) {
        const gov::UnitLevel level{static_cast<int>(sh), static_cast<int>(lod)};
        const auto it = std::find_if(m.levels.begin(), m.levels.end(),
                                     [&](const LevelSamples& s) { return s.unit == static_cast<int>(u) && s.level == level; });
        if (it == m.levels.end() || it->samples.empty())
          throw std::invalid_argument("no timing for " + level_name(ladder, level));
        const gov::LinearCost cost = level_cost(it->samples);
        if (sh == 0 && lod == 0) base[u] = cost;
        entry.levels.push_back({ladder.shadings[sh], static_cast<int>(lod), cost, sh == 0 && lod == 0 ? std::nullopt : it->psnr_db});
      }
    file.units.push_back(std::move(entry));
  }
  // A rung's frame: overhead + sum of B (fixed, the rung does not scale it) + factor x pixel part.
  double fixed = file.overhead.b_ms;
  for (const auto& c : base) fixed += c.b_ms;
  std::vector<gov::GlobalCost> rungs;
  for (const auto& r : m.rungs) {
    if (r.frame_ms.size() != scales)
      throw std::invalid_argument("rung MSAA " + std::to_string(r.level.msaa) + " scale " + std::to_string(r.level.scale) + ": " +
                                  std::to_string(r.frame_ms.size()) + " frame times for " + std::to_string(scales) + " node scales");
    std::vector<gov::CostSample> samples;
    for (std::size_t k = 0; k < scales; ++k) {
      double pixel_part = 0.0;
      for (std::size_t u = 0; u < base.size(); ++u) pixel_part += base[u].a_ms_per_pixel * m.unit_pixels[k].at(u);
      samples.push_back({pixel_part, std::max(0.0, r.frame_ms[k] - fixed)});
    }
    // Pixels here are the level-0 pixel part (ms): the fitted slope is the rung's factor on it.
    const gov::LinearCost f = level_cost(samples);
    double factor = f.a_ms_per_pixel, extra = f.b_ms;
    if (!(factor > 0.0)) {  // no pixel part to scale (or noise): the whole difference is the factor's
      factor = samples.front().pixels > 0 ? std::max(1e-3, samples.front().ms / samples.front().pixels) : 1.0;
      extra = 0.0;
    }
    rungs.push_back({r.level, factor, extra, r.psnr_db});
  }
  if (!rungs.empty()) {
    std::stable_sort(rungs.begin() + 1, rungs.end(), [](const gov::GlobalCost& a, const gov::GlobalCost& b) {
      return a.psnr_db.value_or(-1.0) > b.psnr_db.value_or(-1.0);
    });
    rungs.front().psnr_db.reset();
  }
  file.globals = std::move(rungs);
  return file;
}

}  // namespace meter::calibrate
