// What a scene script's output kinds are: their names, the components of their values and whether
// they drive a node or a material (meter/bridge/scene_scripts.hpp).
#include "meter/bridge/scene_scripts.hpp"

namespace meter::bridge {

const char* to_string(ScriptOutputKind kind) {
  switch (kind) {
    case ScriptOutputKind::Animation: return "time";
    case ScriptOutputKind::Visible: return "visible";
    case ScriptOutputKind::Translation: return "translation";
    case ScriptOutputKind::Rotation: return "rotation";
    case ScriptOutputKind::Morph: return "morph";
    case ScriptOutputKind::Color: return "color";
    case ScriptOutputKind::Emissive: return "emissive";
    case ScriptOutputKind::Text: return "text";
  }
  return "?";
}

int value_components(ScriptOutputKind kind) {
  switch (kind) {
    case ScriptOutputKind::Animation:
    case ScriptOutputKind::Morph: return 1;
    case ScriptOutputKind::Translation:
    case ScriptOutputKind::Rotation:
    case ScriptOutputKind::Emissive: return 3;
    case ScriptOutputKind::Color: return 4;
    case ScriptOutputKind::Visible:
    case ScriptOutputKind::Text: return 0;
  }
  return 0;
}

bool targets_node(ScriptOutputKind kind) {
  return kind == ScriptOutputKind::Visible || kind == ScriptOutputKind::Translation || kind == ScriptOutputKind::Rotation ||
         kind == ScriptOutputKind::Morph || kind == ScriptOutputKind::Text;
}

bool targets_material(ScriptOutputKind kind) { return kind == ScriptOutputKind::Color || kind == ScriptOutputKind::Emissive; }

}  // namespace meter::bridge
