// Shading names and the ranges of a cost model's numbers (cost_limits.hpp).
#include "governor/cost_limits.hpp"

#include <cmath>
#include <stdexcept>

#include "meter/engine/governor/cost_model.hpp"

namespace meter::engine::governor::limits {
namespace {

constexpr bridge::ShadingModel kShadings[] = {bridge::ShadingModel::Unlit, bridge::ShadingModel::Flat,
                                              bridge::ShadingModel::Gouraud, bridge::ShadingModel::BlinnPhong,
                                              bridge::ShadingModel::PbrMetallicRoughness};

bool within(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

bool psnr_ok(const std::optional<double>& p) { return !p || (within(*p, 0.0, kMaxPsnrDb) && *p > 0); }

}  // namespace

std::optional<bridge::ShadingModel> shading_from_name(const std::string& name) {
  for (bridge::ShadingModel m : kShadings)
    if (name == bridge::to_string(m)) return m;
  return std::nullopt;
}

std::string shading_names() {
  std::string s;
  for (bridge::ShadingModel m : kShadings) s += (s.empty() ? "\"" : ", \"") + std::string(bridge::to_string(m)) + "\"";
  return s;
}

void check_model(const CostModel& model, const std::string& origin) {
  auto fail = [&](const std::string& what) { throw std::invalid_argument(origin + ": " + what); };
  if (model.globals.empty()) fail("no global rung (expected at least the full-quality one)");
  if (!within(model.overhead.a_ms_per_pixel, 0, kMaxMsPerPixel) || !within(model.overhead.b_ms, 0, kMaxFixedMs))
    fail("overhead: expected finite a_ms_per_pixel in [0, 1e3] and b_ms in [0, 1e6]");
  for (std::size_t i = 0; i < model.globals.size(); ++i) {
    const GlobalCost& g = model.globals[i];
    const std::string at = "globals[" + std::to_string(i) + "]: ";
    if (g.level.msaa < 1 || g.level.msaa > kMaxMsaa || !(g.level.scale > 0 && g.level.scale <= 1))
      fail(at + "expected msaa in [1, 64] and scale in (0, 1]");
    if (!within(g.pixel_factor, 0, kMaxPixelFactor) || !(g.pixel_factor > 0) || !within(g.fixed_ms, 0, kMaxFixedMs) ||
        !psnr_ok(g.psnr_db))
      fail(at + "expected finite pixel_factor in (0, 1e3], fixed_ms in [0, 1e6], psnr_db > 0");
  }
  for (const UnitCosts& u : model.units) {
    const std::string at = "unit '" + u.name + "': ";
    if (u.shadings < 1 || u.lods < 1 || u.levels.size() != std::size_t(u.shadings) * std::size_t(u.lods))
      fail(at + "expected shadings x lods levels, got " + std::to_string(u.levels.size()));
    if (u.safety && u.levels.size() != 1) fail(at + "a safety unit has exactly one level");
    for (const LevelCost& l : u.levels) {
      if (!within(l.cost.a_ms_per_pixel, 0, kMaxMsPerPixel) || !within(l.cost.b_ms, -kMaxFixedMs, kMaxFixedMs) ||
          !psnr_ok(l.psnr_db))
        fail(at + "level (" + bridge::to_string(l.shading) + ", lod " + std::to_string(l.lod) +
             "): expected finite a_ms_per_pixel in [0, 1e3], b_ms in [-1e6, 1e6], psnr_db > 0");
    }
  }
}

}  // namespace meter::engine::governor::limits
