// The choices drawn once at load (warm_up_choices.hpp).
#include "meter/engine/governor/warm_up_choices.hpp"

#include <algorithm>

namespace meter::engine::governor {

std::vector<QualityChoice> warm_up_choices(const CostModel& model) {
  int steps = 1;
  for (const UnitCosts& u : model.units)
    if (!u.safety) steps = std::max({steps, u.shadings, u.lods});
  std::vector<QualityChoice> out;
  for (const GlobalCost& rung : model.globals) {
    for (int k = steps - 1; k >= 0; --k) {
      QualityChoice c;
      c.global = rung.level;
      c.units.reserve(model.units.size());
      for (const UnitCosts& u : model.units)
        c.units.push_back(u.safety ? UnitLevel{} : UnitLevel{std::min(k, u.shadings - 1), std::min(k, u.lods - 1)});
      if (out.empty() || !(out.back() == c)) out.push_back(std::move(c));
    }
  }
  return out;
}

}  // namespace meter::engine::governor
