// Scene config parsing: text in, SceneConfig out, std::invalid_argument naming the
// file, the JSON path and what was expected (docs/scene-config.md). The library is
// meter::scene_config; the functions are declared in meter::bridge, beside the SceneConfig types
// (meter/bridge/scene_config.hpp) they fill.
#pragma once

#include <string>
#include <string_view>

#include "meter/bridge/scene_config.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::bridge {

// `origin` names the file in messages. Binding signal names must be in `catalog` (their ids come
// from it). Throws std::invalid_argument.
SceneConfig parse_scene_config(std::string_view json_text, const protocol::Catalog& catalog,
                               const std::string& origin);
// The same against the process's active catalog (protocol::active_catalog()).
SceneConfig parse_scene_config(std::string_view json_text, const std::string& origin = "config");
SceneConfig load_scene_config(const std::string& path, const protocol::Catalog& catalog);
SceneConfig load_scene_config(const std::string& path);

}  // namespace meter::bridge
