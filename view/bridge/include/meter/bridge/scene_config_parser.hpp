// Scene config parsing: text in, SceneConfig out, std::invalid_argument naming the
// file, the JSON path and what was expected (docs/scene-config.md).
#pragma once

#include <string>
#include <string_view>

#include "meter/bridge/scene_config.hpp"

namespace meter::bridge {

// `origin` names the file in messages. Throws std::invalid_argument.
SceneConfig parse_scene_config(std::string_view json_text, const std::string& origin = "config");
SceneConfig load_scene_config(const std::string& path);

}  // namespace meter::bridge
