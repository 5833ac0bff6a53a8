// Bindings: signal values -> scene effects (animation time, visibility, material colours, morph
// weights, text). Pure: no GL, no sockets; the renderer consumes BindingOutputs.
//
// Per binding, each update():
//   target = the signal value when it is Valid and the link is up, else the failsafe value (when the
//            binding has one), else the last value drawn (hold);
//   drawn  = target, approached with first-order smoothing (time constant smoothing_ms) and snapped
//            once within 1e-4 of the input span, so a settled needle stops producing new frames;
//   effect = a function of drawn only (so equal inputs give equal outputs: the renderer can skip).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "meter/engine/evaluation/scene_features.hpp"
#include "meter/engine/vocabulary.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/protocol/signal_table.hpp"

namespace meter::engine {

struct TextItem {
  int node = -1;
  std::string text;
  int size_px = 24;
  glm::vec4 color{1.0f};  // sRGB-encoded, straight alpha (designer colour)
  TextAlign align = TextAlign::Left;
  bool operator==(const TextItem&) const = default;
};

struct MorphOverride {
  int node = -1, target = 0;
  float weight = 0.0f;
  bool operator==(const MorphOverride&) const = default;
};

// A node's local translation and/or rotation replaced (over its animated or rest value). Only
// scene scripts set these (logic/scripts.hpp); bindings move nodes through animations.
struct NodeTransformOverride {
  int node = -1;
  std::optional<glm::vec3> translation;
  std::optional<glm::quat> rotation;
  bool operator==(const NodeTransformOverride&) const = default;
};

struct BindingOutputs {
  std::vector<double> animation_time;            // per animation; config.time when not driven
  std::vector<signed char> node_visible;         // per node: -1 no override, 0 hidden, 1 shown
  std::vector<std::optional<glm::vec3>> emissive;  // per material
  std::vector<std::optional<glm::vec4>> base_color;
  std::vector<MorphOverride> morph;
  std::vector<TextItem> texts;
  std::vector<NodeTransformOverride> transforms;  // scene scripts' node translations / rotations
  bool link_lost = false;
  std::optional<double> exposure;  // stops, when the brightness changes the config's (scene_features.hpp)
  bool operator==(const BindingOutputs&) const = default;
};

// The outputs when no binding drives anything: every animation at config.time, no overrides.
BindingOutputs resting_outputs(const Scene& scene);

// What each binding showed in the last update (for frames.csv: values as drawn).
struct BindingState {
  double value = 0.0;        // smoothed value used for the effect
  double target = 0.0;       // value being approached
  protocol::SignalStatus status = protocol::SignalStatus::NotAvailable;
  bool failsafe = false;     // the failsafe look is applied
  bool has_value = false;    // false until the first value (or failsafe) arrived
  std::string text;          // text bindings: the text drawn
  bool imperial = false;     // value and effect are in the imperial unit (mph, mi, °F)
};

class ScriptEngine;  // logic/scripts.hpp

class BindingEvaluator {
 public:
  // Resolves names against the scene (throws SceneError like resolve_config). The scene's scripts
  // (config "scripts") run inside update(), after the bindings: a script's output wins over a
  // binding's effect on the same property (docs/scene-logic.md).
  explicit BindingEvaluator(const Scene& scene);
  ~BindingEvaluator();

  // One step over the current signal states (the Subscriber's table live, a parsed one offline).
  // A binding whose signal is not in the table reads as NotAvailable, like the table's own
  // resting entries. dt_seconds: time since the previous step (smoothing); pass a negative dt to
  // jump straight to the targets (offline rendering of a state). Returns true when the outputs
  // changed.
  bool update(const protocol::SignalTable& signals, bool link_up, double dt_seconds);

  // Looks every binding's signal up again by name in `catalog` (the view took its controller's
  // catalog, whose ids may differ). A name the catalog lacks reads as NotAvailable from then on;
  // those names are returned.
  std::vector<std::string> rebind(const protocol::Catalog& catalog);

  const BindingOutputs& outputs() const { return out_; }
  const std::vector<BindingState>& states() const { return state_; }
  const std::vector<Binding>& bindings() const { return bindings_; }
  // True while some smoothed value is still moving towards its target.
  bool animating() const { return animating_; }
  // The scene's scripts (their stats and messages); nullptr when the config has none.
  ScriptEngine* scripts() { return scripts_.get(); }
  const ScriptEngine* scripts() const { return scripts_.get(); }
  // Pages, theme, units and the sweep (scene_features.hpp), advanced by update().
  const SceneFeatures& features() const { return features_; }
  // Feature requests that replace the feature signals from the next update() on (a script sets
  // the page, theme, brightness or units); an empty FeatureOverrides goes back to the signals.
  void set_feature_overrides(const FeatureOverrides& o) { overrides_ = o; }

 private:
  struct Resolved {
    int animation = -1, node = -1, material = -1;
  };
  const Scene& scene_;
  std::vector<Binding> bindings_;
  std::vector<Binding> imperial_;  // each binding's imperial look (the same for one without a quantity)
  SceneFeatures features_;
  FeatureOverrides overrides_;
  std::vector<Resolved> resolved_;
  std::vector<BindingState> state_;
  BindingOutputs out_;
  int link_loss_node_ = -1;
  std::unique_ptr<ScriptEngine> scripts_;
  bool first_ = true;
  bool animating_ = false;
};

// The catalog id a binding reads: std::nullopt when it is unresolved (-1) or outside the SignalId
// range, so an out-of-range number can never wrap onto a real signal's id.
std::optional<protocol::SignalId> bound_signal_id(const Binding& b);

// The text a text binding shows for a value: the map entry for an integral value, else the format.
std::string binding_text(const Binding& b, double value);

}  // namespace meter::engine
