// Which control the preview shows for each signal a scene config binds: pure data from the
// bindings and the signal catalog, so the panel's content is testable without a window.
#pragma once

#include <string>
#include <vector>

#include "meter/engine/vocabulary.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::preview {

enum class ControlKind {
  Slider,  // gauges and counters: the catalog's [min, max]
  Toggle,  // telltales: off (0) / on (1)
  Choice,  // enums: the integers of the catalog range (the first kMaxChoices) and every value a
           // text binding maps, labelled by that map
  Text,    // text signals: a line of text
};

struct ChoiceItem {
  long long value = 0;
  std::string label;  // "R" for gear -1 when a text binding maps it, else the number
  bool operator==(const ChoiceItem&) const = default;
};

struct SignalControl {
  protocol::SignalId id = 0;
  std::string name, unit;
  ControlKind kind = ControlKind::Slider;
  double min = 0.0, max = 1.0;
  std::vector<ChoiceItem> choices;  // Choice only
};

// A combo of hundreds of entries helps nobody: an enum lists at most this many numbered values.
inline constexpr int kMaxChoices = 64;

// One control per distinct signal the bindings read, in the order the config first uses them.
// Bindings whose signal the catalog lacks get none (the converter already refused them).
std::vector<SignalControl> controls_for(const std::vector<bridge::Binding>& bindings,
                                        const protocol::Catalog& catalog);

}  // namespace meter::preview
