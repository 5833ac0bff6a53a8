#include "meter/calibrate/shading_ladder.hpp"

#include <cstdio>
#include <map>

namespace meter::calibrate {

namespace {

using bridge::ShadingModel;

constexpr ShadingModel kModels[] = {ShadingModel::PbrMetallicRoughness, ShadingModel::BlinnPhong, ShadingModel::Gouraud,
                                    ShadingModel::Flat, ShadingModel::Unlit};

struct Cell {
  double ms = 0.0;
  std::optional<double> psnr_db;
};

}  // namespace

std::string shading_ladder_table(const CostMeasurements& m) {
  std::string out =
      "shading ladder, whole frame (every unit at the most expensive of its shadings not above the rung, LOD 0; median frame, "
      "PSNR, median ratio to the rung above drawn just before):\n";
  char buf[160];
  int steps = 0, cheaper = 0;
  for (std::size_t k = 0; k < m.shading_rungs.size(); ++k) {
    const ShadingRungSamples& r = m.shading_rungs[k];
    if (k) ++steps, cheaper += r.vs_above < 1.0 ? 1 : 0;
    std::snprintf(buf, sizeof buf, "  %-12s %9.3f ms%s", bridge::to_string(r.model), r.frame_ms, k ? "" : "  (own)");
    out += buf;
    if (r.psnr_db) std::snprintf(buf, sizeof buf, "  %6.1f dB  %+.1f %% vs the rung above", *r.psnr_db, 100.0 * (r.vs_above - 1.0)), out += buf;
    out += "\n";
  }
  std::snprintf(buf, sizeof buf, "  each rung cheaper than the one above: %d of %d\n", cheaper, steps);
  out += buf;
  // unit -> model -> (ms at node scale 1, PSNR), LOD 0; units too small to time (0 ms at their own) left out.
  std::vector<std::map<ShadingModel, Cell>> rows(m.ladders.size());
  for (const auto& l : m.levels) {
    if (l.level.lod != 0 || l.samples.empty()) continue;
    const auto& ladder = m.ladders.at(static_cast<std::size_t>(l.unit));
    rows[static_cast<std::size_t>(l.unit)][ladder.shadings.at(static_cast<std::size_t>(l.level.shading))] = {l.samples.front().ms, l.psnr_db};
  }
  out += "shading ladder per unit alone (ms over the empty frame; PSNR of the frame with that unit at that model):\n";
  std::snprintf(buf, sizeof buf, "  %-28s", "unit");
  out += buf;
  for (ShadingModel s : kModels) std::snprintf(buf, sizeof buf, " %-20s", bridge::to_string(s)), out += buf;
  out += "\n";
  for (std::size_t u = 0; u < rows.size(); ++u) {
    const auto& ladder = m.ladders[u];
    if (ladder.safety || ladder.shadings.size() < 2 || !(rows[u][ladder.shadings.front()].ms > 0.0)) continue;
    std::snprintf(buf, sizeof buf, "  %-28.28s", ladder.name.c_str());
    out += buf;
    for (ShadingModel s : kModels) {
      const auto it = rows[u].find(s);
      if (it == rows[u].end()) std::snprintf(buf, sizeof buf, " %-20s", "-");
      else if (it->second.psnr_db) std::snprintf(buf, sizeof buf, " %7.4f (%5.1f dB)   ", it->second.ms, *it->second.psnr_db);
      else std::snprintf(buf, sizeof buf, " %7.4f (own)        ", it->second.ms);
      out += buf;
    }
    out += "\n";
  }
  return out;
}

}  // namespace meter::calibrate
