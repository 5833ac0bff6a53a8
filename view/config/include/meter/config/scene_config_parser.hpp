// Scene config parsing: text in, SceneConfig out, std::invalid_argument naming the file, the JSON
// path and what was expected (docs/scene-config.md). The library is meter::scene_config, its
// namespace meter::config; the SceneConfig types it fills are the bridge's vocabulary
// (meter/bridge/scene_config.hpp).
#pragma once

#include <string>
#include <string_view>

#include "meter/bridge/scene_config.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::config {

// `origin` names the file in messages. Binding signal names must be in `catalog` (their ids come
// from it). Throws std::invalid_argument.
bridge::SceneConfig parse_scene_config(std::string_view json_text, const protocol::Catalog& catalog,
                                       const std::string& origin);
// The same against the process's active catalog (protocol::active_catalog()).
bridge::SceneConfig parse_scene_config(std::string_view json_text, const std::string& origin = "config");
bridge::SceneConfig load_scene_config(const std::string& path, const protocol::Catalog& catalog);
bridge::SceneConfig load_scene_config(const std::string& path);

}  // namespace meter::config
