// Parsing of the display-feature keys of the scene config ("pages", "theme", "units", "sweep" and
// a binding's "quantity" / "imperial"): scene_features.hpp. Internal to meter_scene_config.
#pragma once

#include <string>

#include "config_json.hpp"
#include "meter/bridge/scene_features.hpp"

namespace meter::config {
using namespace meter::bridge;  // the vocabulary the parsers fill

// The top-level feature keys of `root` (the other keys are the main parser's); the sweep's
// animation names are checked against the animation bindings in root["bindings"].
SceneFeaturesConfig parse_scene_features(const config_json::Ctx& c, const nlohmann::json& root);
// A binding's "quantity" and "imperial" keys.
BindingUnits parse_binding_units(const config_json::Ctx& c, const nlohmann::json& binding, const std::string& path,
                                 BindingKind kind);

}  // namespace meter::config
