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
  // unit -> model -> (ms at node scale 1, PSNR), LOD 0 only.
  std::vector<std::map<ShadingModel, Cell>> rows(m.ladders.size());
  for (const auto& l : m.levels) {
    if (l.level.lod != 0 || l.samples.empty()) continue;
    const auto& ladder = m.ladders.at(static_cast<std::size_t>(l.unit));
    rows[static_cast<std::size_t>(l.unit)][ladder.shadings.at(static_cast<std::size_t>(l.level.shading))] = {l.samples.front().ms, l.psnr_db};
  }
  std::string out = "shading ladder: each unit alone at LOD 0, ms over the empty frame (PSNR of the frame with it at that model)\n";
  char buf[96];
  std::snprintf(buf, sizeof buf, "  %-28s", "unit");
  out += buf;
  for (ShadingModel s : kModels) std::snprintf(buf, sizeof buf, " %-20s", bridge::to_string(s)), out += buf;
  out += "\n";
  std::map<ShadingModel, double> total_ms, total_db;
  int complete = 0, steps = 0, inversions = 0;
  for (std::size_t u = 0; u < rows.size(); ++u) {
    const auto& ladder = m.ladders[u];
    if (ladder.safety || ladder.shadings.size() < 2) continue;
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
    for (std::size_t k = 1; k < ladder.shadings.size(); ++k) {
      ++steps;
      inversions += rows[u][ladder.shadings[k]].ms >= rows[u][ladder.shadings[k - 1]].ms ? 1 : 0;
    }
    const bool has_all = rows[u].count(ShadingModel::Gouraud) && rows[u].count(ShadingModel::Flat) && rows[u].count(ShadingModel::Unlit);
    if (!has_all) continue;
    ++complete;
    for (const auto& [s, c] : rows[u]) total_ms[s] += c.ms, total_db[s] += c.psnr_db.value_or(0.0);
  }
  std::snprintf(buf, sizeof buf, "  %-28s", ("total, " + std::to_string(complete) + " units").c_str());
  out += buf;
  for (ShadingModel s : kModels) {
    if (!total_ms.count(s)) std::snprintf(buf, sizeof buf, " %-20s", "-");
    else std::snprintf(buf, sizeof buf, " %7.4f              ", total_ms[s]);
    out += buf;
  }
  std::snprintf(buf, sizeof buf, "\n  rungs costing as much as or more than the rung above: %d of %d\n", inversions, steps);
  return out + buf;
}

}  // namespace meter::calibrate
