// The scene config's vocabulary ("meter-scene-config/1", docs/scene-config.md): render size,
// camera, clear colour, and the bindings that connect catalog signals to the scene. Plain data:
// the converter parses and validates it (and stores it in the package), the runtime evaluates it.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "meter/bridge/program.hpp"
#include "meter/bridge/scene_scripts.hpp"
#include "meter/bridge/scene_features.hpp"

namespace meter::bridge {

enum class BindingKind { Animation, Visibility, Emissive, Color, Morph, Text };
enum class TextAlign { Left, Center, Right };

struct Binding {
  BindingKind kind = BindingKind::Animation;
  std::string signal;     // catalog name, e.g. "Vehicle.Speed"
  int signal_id = -1;     // resolved against the catalog at parse time
  // animation
  std::string animation;
  std::array<double, 2> input{0.0, 1.0};   // signal range (animation, morph, colour/emissive blend)
  bool has_input = false;                  // colour/emissive: blend over input instead of a threshold
  std::array<double, 2> time{0.0, 1.0};    // animation time range the input range maps to
  double smoothing_ms = 0.0;               // first-order smoothing time constant (0 = none)
  // visibility / emissive / color threshold: "on" when value >= threshold
  double threshold = 0.5;
  bool invert = false;
  // false: a driver aid (a shift light), not a safety item: no integrity region is made for it
  bool safety = true;                     // visibility: visible when the value is below threshold
  // node (visibility, morph, text) / material (emissive, color)
  std::string node, material;
  std::array<double, 4> off{0, 0, 0, 1}, on{1, 1, 1, 1};  // emissive uses rgb, color rgba
  int morph_target = 0;
  std::array<double, 2> weight{0.0, 1.0};
  // text
  std::string format = "%.0f";
  double size_px = 24.0;
  std::array<double, 4> color{1, 1, 1, 1};
  TextAlign align = TextAlign::Left;
  std::map<long long, std::string> map;  // integral value -> text (gear "126" -> "P")
  // failsafe: what is shown while the signal is not Valid or the link is down
  std::optional<double> failsafe_value;
  std::optional<bool> failsafe_visible;
  std::optional<std::string> failsafe_text;
  BindingUnits units;  // quantity and imperial look (scene_features.hpp)
};

struct LinkLossConfig {
  std::string text_node;  // empty = no link-loss text
  std::string text = "NO SIGNAL";
  double size_px = 32.0;
  std::array<double, 4> color{1.0, 0.25, 0.2, 1.0};
  TextAlign align = TextAlign::Center;
};

struct Group {
  std::string name;
  std::vector<std::string> members;
};

struct MaterialOverride {
  std::optional<std::string> shading;  // "unlit" | "flat" | "gouraud" | "blinn-phong" | "pbr"
};

// "resolve": how the engine turns its MSAA samples into pixels (docs/scene-config.md). Box: the
// samples of each pixel averaged (the default, the fastest). BlackmanHarris: the authoring tool's
// film filter (Blender: Render > Film > Filter Size, EEVEE's default 1.5 px), edges spread over
// about three pixels as in its renders.
// "sample_format": how each MSAA sample stores its colour until the filter has run. Srgb8 (the
// default): 8-bit sRGB, light above white clamped per sample. Rgba16f: half float, light above
// white kept until the resolved pixel is clamped, as the authoring tool's float film does; for a
// scene whose thin features are brighter than white (emissive print lit by spots), whose edges
// otherwise come out darker than in its renders.
struct ResolveConfig {
  enum class Filter { Box, BlackmanHarris };
  enum class SampleFormat { Srgb8, Rgba16f };
  Filter filter = Filter::Box;
  double width_px = 1.5;  // BlackmanHarris radius in pixels of the config's size, 0.5 .. 3
  SampleFormat sample_format = SampleFormat::Srgb8;
  bool operator==(const ResolveConfig&) const = default;
};

// "sample_shading": which materials are shaded once per MSAA sample instead of once per pixel
// (docs/scene-config.md): those whose shading varies inside a pixel, which the authoring tool's
// many samples per pixel average. Up to 4x their fragment work at MSAA 4, so a scene opts in where
// the detail shows. None (the default, "off"): every material once per pixel.
//   normal_maps ("normal-maps"): materials with a normal map (a full cluster frame +45 % on
//     llvmpipe for +0.03 dB, the bump feature scene +0.65 dB).
//   mirrors ("mirrors"): materials reflecting the environment sharply (roughness up to
//     kMirrorRoughness, or Blinn-Phong, which reflects it unblurred).
struct SampleShading {
  // sqrt(0.1) * 6 = level 1.9 of EEVEE's 512 px probe: lobes of alpha up to 0.012, sharper than
  // the world image's own texels, so the reflection changes inside a pixel.
  static constexpr float kMirrorRoughness = 0.1f;
  bool normal_maps = false;
  bool mirrors = false;
  bool any() const { return normal_maps || mirrors; }
  // Whether a draw of a program with these features and a material of this roughness factor is
  // shaded per sample (the runtime's choice, and the benchmarks' test of whether a kind matters).
  bool shades_per_sample(const MaterialFeatures& f, float roughness) const {
    if (normal_maps && f.normal_texture) return true;
    return mirrors && f.environment_map_2d && (f.shading == ShadingModel::BlinnPhong || roughness <= kMirrorRoughness);
  }
  bool operator==(const SampleShading&) const = default;
};

struct SceneConfig {
  std::array<int, 2> size{1280, 480};
  std::string camera;  // camera node name or camera name; empty = first camera in the scene
  std::array<double, 4> clear_color{0, 0, 0, 1};
  double time = 0.0;   // animation time used for animations no binding drives
  std::array<double, 3> ambient{0.03, 0.03, 0.03};
  double exposure = 0.0;  // stops; the shaders scale by 2^exposure
  std::vector<Binding> bindings;
  LinkLossConfig link_loss;
  std::vector<Group> groups;
  std::map<std::string, MaterialOverride> materials;
  std::vector<Script> scripts;  // "scripts" (scene_scripts.hpp, docs/scene-logic.md)
  SceneFeaturesConfig features;  // pages, theme, units, sweep (scene_features.hpp)
  ResolveConfig resolve = {};    // "resolve"
  SampleShading sample_shading;  // "sample_shading"
  // "font": the TrueType / OpenType file the texts are drawn with, relative to the config file;
  // empty: DejaVu Sans (fonts-dejavu-core). The converter embeds it in the package (SceneFont).
  std::string font;
  std::string source_json;  // the original text, stored in the package
  std::string origin;       // the file (or name) it was parsed from, for later messages
};

const char* to_string(BindingKind kind);

// Whether the scene draws any text: a text binding, a script's text output or the link-loss text.
// Such a scene needs its font in the package (Scene::font).
bool config_draws_text(const SceneConfig& config);

// Checks a printf format for exactly one floating conversion (%f %e %g %F %E %G, with flags,
// width, precision) and only %% otherwise, so formatting a double can never be UB.
bool valid_number_format(std::string_view format, std::string* why = nullptr);
// Formats `value` with a format accepted by valid_number_format.
std::string format_number(const std::string& format, double value);

}  // namespace meter::bridge
