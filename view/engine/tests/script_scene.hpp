// A hand-built scene for the scene-script tests (no glTF, no GL): nodes Lamp, Needle, Text_Gear,
// Warn, Bar; materials LampMat, NeedleMat; an animation Sweep without channels. The config holds
// the given scripts and bindings.
#pragma once

#include <string>

#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::engine::test {

// A piece of Lua and the error it must give.
struct LuaCase {
  const char* code;
  const char* error;
};

inline Scene script_scene(const std::string& scripts_json, const std::string& bindings_json = "[]") {
  Scene s;
  s.source_name = "logic.gltf";
  for (const char* name : {"Lamp", "Needle", "Text_Gear", "Warn", "Bar"}) {
    Node n;
    n.name = name;
    s.roots.push_back(static_cast<int>(s.nodes.size()));
    s.nodes.push_back(n);
  }
  for (const char* name : {"LampMat", "NeedleMat"}) {
    Material m;
    m.name = name;
    s.materials.push_back(m);
  }
  Animation a;
  a.name = "Sweep";
  s.animations.push_back(a);
  s.config = meter::config::parse_scene_config(
      R"({"format": "meter-scene-config/1", "bindings": )" + bindings_json + R"(, "scripts": )" + scripts_json + "}", "logic.json");
  return s;
}

}  // namespace meter::engine::test
