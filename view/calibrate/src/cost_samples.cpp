#include "meter/calibrate/cost_samples.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

namespace meter::calibrate {
namespace gov = engine::governor;
namespace {

std::string level_name(const gov::UnitLadder& ladder, const gov::UnitLevel& l) {
  return ladder.name + " " + bridge::to_string(ladder.shadings.at(static_cast<std::size_t>(l.shading))) + "/lod" + std::to_string(l.lod);
}

}  // namespace

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

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
  std::vector<gov::LinearCost> base(m.ladders.size());  // each unit's level-0 cost
  for (std::size_t u = 0; u < m.ladders.size(); ++u) {
    const auto& ladder = m.ladders[u];
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
  // The units timed alone do not add up to the whole frame exactly (shared state changes, overdraw,
  // and on a busy machine the noise of many small differences). Rung 0's whole frames at each node
  // scale set the scale: time - overhead = alpha x (sum of A x pixels) + c; every A is multiplied by
  // alpha and every B by c / (sum of B), so the model predicts the measured full frame and keeps the
  // units' relative costs. The other rungs are then fitted against that model:
  // time - overhead - c = factor x pixel part + fixed.
  const auto pixel_part = [&](std::size_t k) {
    double p = 0.0;
    for (std::size_t u = 0; u < base.size(); ++u) p += base[u].a_ms_per_pixel * m.unit_pixels[k].at(u);
    return p;
  };
  for (const auto& r : m.rungs)
    if (r.frame_ms.size() != scales)
      throw std::invalid_argument("rung MSAA " + std::to_string(r.level.msaa) + " scale " + std::to_string(r.level.scale) + ": " +
                                  std::to_string(r.frame_ms.size()) + " frame times for " + std::to_string(scales) + " node scales");
  if (m.rungs.empty()) throw std::invalid_argument("no whole-frame timing of rung 0");
  // time - fixed against the pixel part; "pixels" here are the pixel part (ms), so the slope is a
  // factor on it. The intercept is kept when it is >= 0, else the line goes through the origin.
  const auto rung_fit = [&](const RungSamples& r, double fixed, bool through_origin) {
    std::vector<gov::CostSample> samples;
    for (std::size_t k = 0; k < scales; ++k) samples.push_back({pixel_part(k), std::max(0.0, r.frame_ms[k] - fixed)});
    std::set<double> xs;
    for (const auto& s : samples) xs.insert(s.pixels);
    if (!through_origin && xs.size() >= 2) {
      const gov::CostFit f = gov::fit_cost(samples);
      if (f.a_ms_per_pixel > 0 && f.b_ms >= 0) return gov::LinearCost{f.a_ms_per_pixel, f.b_ms};
    }
    double sxy = 0.0, sxx = 0.0;
    for (const auto& s : samples) sxy += s.pixels * s.ms, sxx += s.pixels * s.pixels;
    return gov::LinearCost{sxx > 0 ? std::max(1e-3, sxy / sxx) : 1.0, 0.0};
  };
  // c never exceeds 0.9 x the cheapest whole frame measured (minus the overhead): a cheaper rung can
  // only lower the pixel part, so a larger fixed part could not predict the frames it was seen to
  // draw (the units' boxes do not shrink exactly as the node scale does: a fit of three scales can
  // put pixel work into c).
  double cheapest = std::numeric_limits<double>::infinity();
  for (const auto& r : m.rungs)
    for (double t : r.frame_ms) cheapest = std::min(cheapest, t - file.overhead.b_ms);
  gov::LinearCost whole = rung_fit(m.rungs.front(), file.overhead.b_ms, false);
  if (const double cap = 0.9 * std::max(0.0, cheapest); whole.b_ms > cap) {
    whole = rung_fit(m.rungs.front(), file.overhead.b_ms + cap, true);
    whole.b_ms = cap;
  }
  double sum_b = 0.0;
  for (const auto& c : base) sum_b += c.b_ms;
  for (auto& unit : file.units)
    for (auto& level : unit.levels) {
      level.cost.a_ms_per_pixel *= whole.a_ms_per_pixel;
      level.cost.b_ms = sum_b > 0 ? level.cost.b_ms * whole.b_ms / sum_b : 0.0;
    }
  if (!(sum_b > 0)) file.overhead.b_ms += whole.b_ms;  // no unit has a fixed part to carry c
  const double fixed = file.overhead.b_ms + (sum_b > 0 ? whole.b_ms : 0.0);
  for (auto& c : base) c.a_ms_per_pixel *= whole.a_ms_per_pixel;
  std::vector<gov::GlobalCost> rungs{{m.rungs.front().level, 1.0, 0.0, std::nullopt}};
  for (std::size_t g = 1; g < m.rungs.size(); ++g) {
    const gov::LinearCost f = rung_fit(m.rungs[g], fixed, false);
    rungs.push_back({m.rungs[g].level, f.a_ms_per_pixel, f.b_ms, m.rungs[g].psnr_db});
  }
  std::stable_sort(rungs.begin() + 1, rungs.end(), [](const gov::GlobalCost& a, const gov::GlobalCost& b) {
    return a.psnr_db.value_or(-1.0) > b.psnr_db.value_or(-1.0);
  });
  file.globals = std::move(rungs);
  file.concatenation = m.concatenation;
  return file;
}

}  // namespace meter::calibrate
