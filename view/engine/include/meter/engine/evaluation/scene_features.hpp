// Display features on top of the bindings (the config's "pages", "theme", "units", "sweep";
// docs/scene-config.md): pure timelines and conversions, and SceneFeatures, which reads the
// feature signals, advances the timelines on the render clock and writes its effects into the
// binding outputs. No GL.
//
// Inputs come in as FeatureInputs (read from the signal table by read_inputs()): a script
// or a test can set them directly instead. What the features show is FeatureState: the current
// page, the theme mix, the exposure, the unit systems and the sweep, readable as properties.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "meter/engine/vocabulary.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/protocol/signal_table.hpp"

namespace meter::engine {

struct BindingOutputs;

// ---- units (units.cpp)
struct UnitSystem {
  bool imperial_distance = false;  // mi and mph instead of km and km/h
  bool fahrenheit = false;         // °F instead of °C
  bool operator==(const UnitSystem&) const = default;
};
// True when `q` is shown in its imperial unit under `units`.
bool shows_imperial(const UnitSystem& units, Quantity q);
// Metric value of quantity `q` (km/h, km, °C) in its imperial unit (mph, mi, °F), and back.
double to_imperial(Quantity q, double metric);
double to_metric(Quantity q, double imperial);
// The binding as it looks in the imperial unit: input range (the given one, else the metric one
// converted), format and failsafe text replaced, failsafe value converted. Only for a binding
// with a quantity.
Binding imperial_binding(const Binding& metric);

// ---- theme (theme.cpp)
// The visible mix (0 day, 1 night) at linear progress p of a transition: smoothstep, so the look
// starts and ends without a jump in its rate of change.
double theme_curve(double p);
// Linear progress towards `target` (0 or 1) after dt seconds of a transition lasting duration_s
// (0 = at once); dt < 0 jumps to the target (offline).
double theme_progress(double progress, double target, double duration_s, double dt);
// Exposure added (stops) by a brightness in percent: 0 at 100 %, min_stops at 0 %, linear in
// between (clamped to 0..100).
double brightness_stops(double percent, double min_stops);

// ---- pages (pages.cpp)
// The page switcher: a requested page starts its transition clip; while it plays, the page left
// and the page entered are both shown.
class PageSwitcher {
 public:
  PageSwitcher(int pages, int initial, std::vector<double> transition_s);
  // Requests `page` (ignored when out of range); dt seconds passed; dt < 0 completes a transition at once.
  void update(std::optional<int> page, double dt);
  int current() const { return current_; }
  int previous() const { return previous_; }
  // Progress 0..1 of the running transition, std::nullopt when none runs.
  std::optional<double> transition() const;
  bool shown(int page) const;

 private:
  int pages_, current_, previous_;
  std::vector<double> duration_s_;
  double elapsed_s_ = 0.0;
  bool running_ = false;
};

// ---- sweep (sweep.cpp)
// Needle position 0..1 (0 rest, 1 full scale) `t_s` seconds into the sweep: smoothstep up over
// rise, hold, smoothstep down over fall; std::nullopt once it is over.
std::optional<double> sweep_position(const SweepConfig& sweep, double t_s);
// The sweep timeline: starts when the ignition value rises to >= on_at_least from below or from
// no value (a cluster powered up with the ignition on sweeps too). Offline (dt < 0) it never runs.
class SweepTimeline {
 public:
  explicit SweepTimeline(SweepConfig config) : config_(std::move(config)) {}
  void update(std::optional<double> ignition, double dt);
  std::optional<double> position() const { return running_ ? sweep_position(config_, t_s_) : std::nullopt; }
  bool running() const { return running_; }
  // True for the one update in which the sweep ended.
  bool just_ended() const { return just_ended_; }

 private:
  SweepConfig config_;
  bool was_on_ = false, running_ = false, just_ended_ = false;
  double t_s_ = 0.0;
};

// ---- the coordinator (scene_features.cpp)
struct FeatureInputs {
  std::optional<int> page;           // requested page
  std::optional<double> theme;       // 0 day, 1 night
  std::optional<double> brightness;  // percent
  UnitSystem units;
  std::optional<double> ignition;
};

// What a script (or any caller) requests instead of the feature signals: each engaged field
// replaces what read_inputs() found.
struct FeatureOverrides {
  std::optional<int> page;
  std::optional<double> theme, brightness;
  std::optional<UnitSystem> units;
  void apply(FeatureInputs& in) const;
};

struct FeatureState {
  int page = 0;
  std::optional<double> page_transition;  // progress of a running page transition
  double theme_progress = 0.0, theme_mix = 0.0;  // mix = theme_curve(progress)
  double exposure_stops = 0.0;             // the config's exposure + brightness
  UnitSystem units;
  std::optional<double> sweep;             // needle position while the sweep runs
};

class SceneFeatures {
 public:
  // Resolves every name against the scene; throws SceneError naming the config key.
  explicit SceneFeatures(const Scene& scene);
  // Reads the feature signals (only Valid ones, and only while the link is up).
  FeatureInputs read_inputs(const protocol::SignalTable& signals, bool link_up) const;
  // Advances pages, theme, brightness, units and the sweep by dt seconds (dt < 0: offline, jump
  // to the state itself).
  void update(const FeatureInputs& inputs, double dt);
  // Writes pages, theme, exposure, unit nodes and the sweep into `out` (after the bindings).
  void apply(BindingOutputs& out) const;
  // Looks the feature signals up again by name (the view took its controller's catalog).
  std::vector<std::string> rebind(const protocol::Catalog& catalog);

  const FeatureState& state() const { return state_; }
  bool active() const;  // a transition or the sweep is running (frames keep changing)
  bool sweep_just_ended() const { return sweep_ && sweep_->just_ended(); }
  // True when the sweep drives `animation` (index into the scene's animations).
  bool sweeps(int animation) const;

 private:
  struct ThemeMaterials {
    int day = -1, night = -1;
  };
  const Scene& scene_;
  SceneFeaturesConfig config_;
  std::vector<int> page_nodes_, page_clips_;
  std::optional<PageSwitcher> pages_;
  std::vector<ThemeMaterials> theme_;
  std::vector<int> swatch_nodes_;
  std::vector<int> metric_nodes_, imperial_nodes_, celsius_nodes_, fahrenheit_nodes_;
  std::vector<int> sweep_animations_;
  struct SweptBinding {
    int animation;
    double time0, time1;  // the binding's animation time range
  };
  std::vector<SweptBinding> swept_;
  std::optional<SweepTimeline> sweep_;
  FeatureState state_;
};

}  // namespace meter::engine
