// Matching a cost file to the renderer's draw units (cost_file.hpp: bind_costs).
#include <map>
#include <stdexcept>

#include "governor/cost_limits.hpp"
#include "meter/engine/governor/cost_file.hpp"

namespace meter::engine::governor {
namespace {

// At most this many names per list in the message, then "and N more".
constexpr std::size_t kListed = 5;

void add(std::vector<std::string>& list, std::size_t& more, std::string item) {
  if (list.size() < kListed)
    list.push_back(std::move(item));
  else
    ++more;
}

std::string join(const std::vector<std::string>& list, std::size_t more) {
  std::string s;
  for (const auto& x : list) s += (s.empty() ? "" : ", ") + x;
  if (more) s += " and " + std::to_string(more) + " more";
  return s;
}

std::string level_name(const std::string& unit, bridge::ShadingModel s, int lod) {
  return "'" + unit + "' (" + bridge::to_string(s) + ", lod " + std::to_string(lod) + ")";
}

}  // namespace

CostModel bind_costs(const CostFile& file, std::span<const UnitLadder> ladders, const std::string& origin) {
  // Units of the same name (a node drawn as several draws) match in order of occurrence.
  std::map<std::string, std::vector<std::size_t>> by_name;
  for (std::size_t i = 0; i < file.units.size(); ++i) by_name[file.units[i].name].push_back(i);
  std::map<std::string, std::size_t> taken;
  std::vector<char> used_unit(file.units.size(), 0);
  std::vector<std::string> missing, extra;
  std::size_t missing_more = 0, extra_more = 0;

  CostModel model;
  model.overhead = file.overhead;
  model.globals = file.globals;
  for (const UnitLadder& ladder : ladders) {
    if (ladder.shadings.empty() || ladder.lod_errors.empty())
      throw std::invalid_argument(origin + ": draw unit '" + ladder.name + "' has no level 0 in its ladder");
    UnitCosts u;
    u.name = ladder.name;
    u.safety = ladder.safety;
    u.shadings = int(ladder.shadings.size());
    u.lods = int(ladder.lod_errors.size());
    u.levels.resize(std::size_t(u.shadings) * std::size_t(u.lods));
    const auto found = by_name.find(ladder.name);
    const std::size_t k = taken[ladder.name]++;
    if (found == by_name.end() || k >= found->second.size()) {
      add(missing, missing_more, "unit '" + ladder.name + "'");
      model.units.push_back(std::move(u));
      continue;
    }
    const UnitCostEntry& entry = file.units[found->second[k]];
    used_unit[found->second[k]] = 1;
    std::vector<char> used_level(entry.levels.size(), 0);
    for (int s = 0; s < u.shadings; ++s) {
      for (int l = 0; l < u.lods; ++l) {
        const bridge::ShadingModel shading = ladder.shadings[std::size_t(s)];
        bool hit = false;
        for (std::size_t e = 0; e < entry.levels.size() && !hit; ++e) {
          if (entry.levels[e].shading != shading || entry.levels[e].lod != l) continue;
          u.levels[std::size_t(s * u.lods + l)] = entry.levels[e];
          used_level[e] = 1;
          hit = true;
        }
        if (!hit) add(missing, missing_more, "level " + level_name(ladder.name, shading, l));
      }
    }
    for (std::size_t e = 0; e < entry.levels.size(); ++e)
      if (!used_level[e]) add(extra, extra_more, "level " + level_name(ladder.name, entry.levels[e].shading, entry.levels[e].lod));
    model.units.push_back(std::move(u));
  }
  for (std::size_t i = 0; i < file.units.size(); ++i)
    if (!used_unit[i]) add(extra, extra_more, "unit '" + file.units[i].name + "'");
  if (!missing.empty() || !extra.empty()) {
    std::string what = origin + ": stale cost file (calibrate it again for this package):";
    if (!missing.empty()) what += " missing " + join(missing, missing_more) + ";";
    if (!extra.empty()) what += " not in the package " + join(extra, extra_more) + ";";
    what.pop_back();
    throw std::invalid_argument(what);
  }
  limits::check_model(model, origin);
  return model;
}

}  // namespace meter::engine::governor
