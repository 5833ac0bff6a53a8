// The signal state the view draws from: catalog id -> value, status and text. The one container
// the values input fills and the render modes look signals up in.
#pragma once

#include <map>

#include "meter/engine/evaluation/bindings.hpp"

namespace meter::view {

using SignalValues = std::map<int, engine::SignalValue>;

// A lookup for BindingEvaluator::update over `values` (nullptr for a signal not in it: not
// available). `values` must outlive the lookup.
inline engine::SignalLookup lookup_in(const SignalValues& values) {
  return [&values](int id) -> const engine::SignalValue* {
    auto it = values.find(id);
    return it == values.end() ? nullptr : &it->second;
  };
}

}  // namespace meter::view
