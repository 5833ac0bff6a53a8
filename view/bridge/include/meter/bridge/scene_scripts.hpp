// Scene scripts (docs/scene-logic.md): Lua 5.4 code in the scene config whose typed inputs are
// catalog signals and whose outputs are the node and material properties a binding can set (plus
// a node's translation and rotation). Plain data: the parser validates it (names, types, Lua
// syntax in text mode), the converter checks the targets against the scene, the engine runs it.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace meter::bridge {

enum class TextAlign;  // scene_config.hpp (an opaque declaration: its underlying type is int)

enum class ScriptOutputKind { Animation, Visible, Translation, Rotation, Morph, Color, Emissive, Text };

// One input: the name the script reads (IN.<name>) and the catalog signal behind it.
struct ScriptInput {
  std::string name;    // Lua identifier
  std::string signal;  // catalog name, e.g. "Vehicle.Speed"
  int signal_id = -1;  // resolved against the catalog at parse time
};

// One output: what the script writes (OUT.<name>) and the property it sets.
struct ScriptOutput {
  std::string name;    // Lua identifier
  ScriptOutputKind kind = ScriptOutputKind::Visible;
  std::string target;  // node (visible, translation, rotation, morph, text), material (color,
                       // emissive) or animation (animation) name
  int morph_target = 0;
  // text look (as a text binding's)
  double size_px = 24.0;
  std::array<double, 4> color{1, 1, 1, 1};  // sRGB rgba
  TextAlign align{};                        // left
  // failsafe: what the output shows while the script is failed or the link is down; absent =
  // hold what it showed last (as a binding without a failsafe). Numbers: animation time, morph
  // weight (1), translation / rotation / emissive (3), colour (4, alpha 1 when 3 are given).
  std::optional<std::vector<double>> failsafe_numbers;
  std::optional<bool> failsafe_visible;
  std::optional<std::string> failsafe_text;
};

struct ScriptLimits {
  long long instructions = 100000;       // Lua VM instructions per run
  std::size_t memory_bytes = 256 * 1024; // live bytes of the script's Lua state
  std::size_t run_alloc_bytes = 4u << 20;  // bytes allocated during one run (copies included)
};

struct Script {
  std::string name;   // shown in messages and stats ("shift_light"); the Lua chunk name
  std::string file;   // the file the code came from, relative to the config ("" = inline)
  std::string code;   // the Lua source (text; bytecode is refused)
  std::vector<ScriptInput> inputs;
  std::vector<ScriptOutput> outputs;
  ScriptLimits limits;
};

const char* to_string(ScriptOutputKind kind);
// Number of components an output kind's value has (0 for visible and text).
int value_components(ScriptOutputKind kind);
// Node outputs: visible, translation, rotation, morph, text; material: color, emissive.
bool targets_node(ScriptOutputKind kind);
bool targets_material(ScriptOutputKind kind);

}  // namespace meter::bridge
