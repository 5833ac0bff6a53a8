// The data converter: glTF 2.0 (+ scene config) -> Scene with generated programs, what
// meter-convert does.
//
// Validation names the element and the problem ("nodes[3].rotation: quaternion not unit length
// (|q| = 1.2)"). Problems with one obviously right answer are repaired and reported as warnings
// (docs/engine.md, "Repairs"); everything else is an error and nothing is written.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "meter/convert/merge_break_even.hpp"
#include "meter/convert/vocabulary.hpp"
#include "meter/shadergen/program_cache.hpp"

namespace meter::convert {

struct Diagnostic {
  std::string path;     // JSON-ish element path: "meshes[0].primitives[0].attributes.NORMAL"
  std::string message;  // what is wrong and, for repairs, what was done
};

// All errors found in one file (validation keeps going after the first so an artist sees them all).
struct ConvertError : SceneError {
  ConvertError(const std::string& file, std::vector<Diagnostic> errs);
  std::vector<Diagnostic> errors;
  std::vector<Diagnostic> repairs;  // repairs that would have been applied (not in what())
};

struct ConvertOptions {
  bool optimize = true;         // shader optimizer: shadergen::optimize() with the scene's constants
  bool propose_groups = false;  // mesh concatenation: also group ungrouped objects automatically
  // Optimized programs from earlier conversions (the preview keeps one across reloads); null: a
  // cache for this conversion only. Hits are byte-identical to fresh programs (program_cache.hpp).
  shadergen::ProgramCache* program_cache = nullptr;
  // The break-even test's costs (meter-convert --costs: a meter-costs/1 file's "concatenation"
  // block); none: every allowed group is merged.
  std::optional<ConcatenationCosts> merge_costs{};
};

struct ConvertResult {
  Scene scene;
  std::vector<Diagnostic> repairs;  // warnings: what was repaired and how
  std::string concat_report;        // concatenation decisions (meter-convert --report)
};

// Loads, validates, converts; resolves the config against the scene (every binding's node /
// material / animation must exist) and generates one program per distinct draw. Throws
// ConvertError (validation), SceneError (unreadable file, config does not match the scene).
ConvertResult convert_gltf(const std::string& gltf_path, const SceneConfig& config,
                           const ConvertOptions& options = {});

// Checks that every name the config refers to exists in the scene. Throws SceneError.
void resolve_config(const Scene& scene, const SceneConfig& config, const std::string& origin);
// The scripts' part of it: every output's node / material / animation exists (nodes unique, morph
// targets present), and every script loads in its sandbox and defines run(IN, OUT). Throws
// SceneError naming the config file, the script and the Lua line.
void resolve_scripts(const Scene& scene, const SceneConfig& config);
// The display features' names (pages, theme, units; resolve_features.cpp), called by resolve_config.
void resolve_features(const Scene& scene, const SceneConfig& config, const std::string& origin);

// The `meter-convert --report` text: one block per program (features, instruction and uniform
// counts, draws using it).
std::string program_report(const Scene& scene);

}  // namespace meter::convert
