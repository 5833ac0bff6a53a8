// Predicting a frame's time from the cost model (cost_model.hpp).
#include "meter/engine/governor/cost_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace meter::engine::governor {

int global_rung(const CostModel& model, const GlobalLevel& level) {
  for (std::size_t i = 0; i < model.globals.size(); ++i)
    if (model.globals[i].level == level) return int(i);
  return -1;
}

double sane_pixels(double p) {
  if (!(p > 0)) return 0.0;  // also NaN
  return std::min(p, kMaxPixels);
}

double relative_error(const std::optional<double>& psnr_db) {
  if (!psnr_db || !std::isfinite(*psnr_db)) return 0.0;
  return std::pow(10.0, -*psnr_db / 10.0);
}

PredictionParts unit_parts(const CostModel& model, int unit, const UnitLevel& level, int global,
                           double pixels) {
  const double p = sane_pixels(pixels);
  if (p == 0) return {};
  const LinearCost& c = model.units[std::size_t(unit)].at(level).cost;
  const double factor = model.globals[std::size_t(global)].pixel_factor;
  // A negative intercept (a fit's line below the origin) never makes a unit cost less than 0.
  return {std::max(0.0, c.a_ms_per_pixel * p * factor), std::max(0.0, c.b_ms)};
}

PredictionParts predict_parts(const CostModel& model, const FrameLoad& load, const QualityChoice& choice) {
  const int g = global_rung(model, choice.global);
  if (g < 0)
    throw std::invalid_argument("cost model: the global rung msaa " + std::to_string(choice.global.msaa) +
                                " scale " + std::to_string(choice.global.scale) + " is not in the model");
  const std::size_t n = model.units.size();
  if (!choice.units.empty() && choice.units.size() != n)
    throw std::invalid_argument("cost model: the choice has " + std::to_string(choice.units.size()) +
                                " units, the model " + std::to_string(n));
  for (std::size_t i = 0; i < choice.units.size(); ++i) {
    const UnitLevel& l = choice.units[i];
    const UnitCosts& u = model.units[i];
    if (l.shading < 0 || l.shading >= u.shadings || l.lod < 0 || l.lod >= u.lods)
      throw std::invalid_argument("cost model: unit '" + u.name + "': level (shading " +
                                  std::to_string(l.shading) + ", lod " + std::to_string(l.lod) +
                                  ") is outside its " + std::to_string(u.shadings) + " x " +
                                  std::to_string(u.lods) + " levels");
  }
  if (!load.drawn) return {};
  if (load.unit_pixels.size() != n)
    throw std::invalid_argument("cost model: the frame load has " + std::to_string(load.unit_pixels.size()) +
                                " units, the model " + std::to_string(n));
  const GlobalCost& rung = model.globals[std::size_t(g)];
  PredictionParts sum{model.overhead.a_ms_per_pixel * sane_pixels(load.redrawn_pixels) * rung.pixel_factor,
                      model.overhead.b_ms + rung.fixed_ms};
  for (std::size_t i = 0; i < n; ++i) {
    const PredictionParts u =
        unit_parts(model, int(i), choice.units.empty() ? UnitLevel{} : choice.units[i], g, load.unit_pixels[i]);
    sum.pixel_ms += u.pixel_ms;
    sum.fixed_ms += u.fixed_ms;
  }
  return sum;
}

double predict_ms(const CostModel& model, const FrameLoad& load, const QualityChoice& choice,
                  const ModelScale& scale) {
  return predict_parts(model, load, choice).total(scale);
}

}  // namespace meter::engine::governor
