#include "meter/preview/signal_controls.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace meter::preview {
namespace {

// The label of an enum value: the first text binding of the signal that maps it, else the number.
std::string choice_label(const std::vector<bridge::Binding>& bindings, const std::string& signal, long long value) {
  for (const auto& b : bindings) {
    if (b.kind != bridge::BindingKind::Text || b.signal != signal) continue;
    const auto it = b.map.find(value);
    if (it != b.map.end()) return it->second + " (" + std::to_string(value) + ")";
  }
  return std::to_string(value);
}

}  // namespace

std::vector<SignalControl> controls_for(const std::vector<bridge::Binding>& bindings,
                                        const protocol::Catalog& catalog) {
  std::vector<SignalControl> controls;
  for (const auto& b : bindings) {
    const auto* info = catalog.find(b.signal);
    if (!info) continue;
    if (std::any_of(controls.begin(), controls.end(), [&](const SignalControl& c) { return c.id == info->id; }))
      continue;
    SignalControl c;
    c.id = info->id;
    c.name = info->name;
    c.unit = info->unit;
    c.min = info->min;
    c.max = info->max;
    switch (info->kind) {
      case protocol::SignalKind::Telltale: c.kind = ControlKind::Toggle; break;
      case protocol::SignalKind::Text: c.kind = ControlKind::Text; break;
      case protocol::SignalKind::Enum: {
        // The first kMaxChoices integers of the range and every value a text binding maps (gear
        // 126 "P" lies far past the numbered gears).
        std::map<long long, std::string> items;
        const double lo = std::ceil(info->min), hi = std::floor(info->max);
        for (double v = lo; v <= hi && v < lo + kMaxChoices; v += 1.0) items[static_cast<long long>(v)];
        for (const auto& other : bindings) {
          if (other.kind != bridge::BindingKind::Text || other.signal != info->name) continue;
          for (const auto& [value, text] : other.map) {
            if (static_cast<double>(value) >= lo && static_cast<double>(value) <= hi) items[value];
          }
        }
        c.kind = ControlKind::Choice;
        for (const auto& [value, unused] : items) c.choices.push_back({value, choice_label(bindings, info->name, value)});
        break;
      }
      case protocol::SignalKind::Gauge:
      case protocol::SignalKind::Counter: break;
    }
    controls.push_back(std::move(c));
  }
  return controls;
}

}  // namespace meter::preview
