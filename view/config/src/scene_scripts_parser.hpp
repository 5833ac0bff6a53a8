// The scene config's "scripts" key (docs/scene-logic.md), parsed apart from the rest of the
// config so the two grow independently.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "meter/bridge/scene_scripts.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::config {
using namespace meter::bridge;  // the vocabulary the parsers fill

// Parses and checks `scripts` (the value of $.scripts): names, inputs against `catalog`, outputs'
// shapes, limits, and each script's Lua syntax (text mode). A script given as "file" is read
// relative to the directory of `origin` and its code is inlined into `scripts` (its "file"
// becomes "inlined_from"), so the stored config text carries the code; `*inlined` says whether
// that happened. Throws std::invalid_argument naming `origin`, the JSON path, the script and the
// Lua line.
std::vector<Script> parse_scripts(nlohmann::json& scripts, const protocol::Catalog& catalog, const std::string& origin,
                                  bool* inlined);

}  // namespace meter::config
