// The scene config's display features beyond bindings (docs/scene-config.md, "Pages, theme,
// units, sweep"): pages switched by a signal with the artist's transition clips, a day/night
// material set with a timed transition and a brightness, the unit system of the readouts and
// printed scales, and the start-up needle sweep. Plain data, parsed with the rest of the config;
// every feature is optional (absent = the scene looks as without it).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace meter::bridge {

// What a binding's value measures, so the unit system can convert it. None: shown as received.
enum class Quantity { None, Speed, Distance, Temperature };

// A binding's look in the imperial unit (mph, mi, °F): its value is converted first, then these
// replace the metric ones where given.
struct ImperialLook {
  std::optional<std::array<double, 2>> input;  // animation / morph / blend input range
  std::optional<std::string> format;           // text
  std::optional<std::string> failsafe_text;    // text
};

struct BindingUnits {
  Quantity quantity = Quantity::None;
  ImperialLook imperial;
};

// Page k is the subtree of nodes[k]; only the current page is shown. Changing to page k plays
// `transitions[k]` (an animation clip, from its first to its last key, on the render clock) while
// both the old and the new page are shown.
struct PageTransition {
  std::string animation;  // empty = switch at once
};
struct PagesConfig {
  std::string signal;                     // catalog enum: the page index requested
  int signal_id = -1;
  std::vector<std::string> nodes;         // page roots, index = page number
  std::vector<PageTransition> transitions;  // per page (entering it); same length as nodes
  int initial = 0;                        // shown until the signal is valid
};

// Day/night: pairs of materials (the day one is drawn, the night one only carries its look); the
// drawn factors go from day to night over `transition_ms` as the theme signal says.
struct ThemePair {
  std::string day, night;
};
struct ThemeConfig {
  std::string signal;              // catalog enum: 0 day, 1 night
  int signal_id = -1;
  double transition_ms = 0.0;      // 0 = switch at once
  std::vector<ThemePair> pairs;
  std::vector<std::string> swatch_nodes;  // nodes that only carry night materials: never shown
  std::string brightness_signal;   // optional catalog gauge 0..100 %: scales the exposure
  int brightness_signal_id = -1;
  double brightness_min_stops = -3.0;  // exposure added at 0 %; 100 % adds 0
};

// Unit systems: distance (km and km/h vs mi and mph) and temperature (°C vs °F), each from an
// enum signal (0 metric, 1 imperial); node lists shown only in one of them (printed scales).
struct UnitsConfig {
  std::string distance_signal, temperature_signal;
  int distance_signal_id = -1, temperature_signal_id = -1;
  std::vector<std::string> metric_nodes, imperial_nodes;      // distance system
  std::vector<std::string> celsius_nodes, fahrenheit_nodes;  // temperature system
};

// Start-up sweep: when the ignition signal rises to >= `on_at_least`, the listed animation
// bindings' needles go from their rest to full scale and back (rise, hold, fall, smoothstep
// eased) before they show their values again.
struct SweepConfig {
  std::string signal;            // catalog enum, e.g. Vehicle.LowVoltageSystemState
  int signal_id = -1;
  double on_at_least = 4.0;      // LowVoltageSystemState: 4 = ON
  double rise_ms = 1000.0, hold_ms = 200.0, fall_ms = 1000.0;
  std::vector<std::string> animations;  // animation names of animation bindings
};

struct SceneFeaturesConfig {
  std::optional<PagesConfig> pages;
  std::optional<ThemeConfig> theme;
  std::optional<UnitsConfig> units;
  std::optional<SweepConfig> sweep;
};

const char* to_string(Quantity q);

}  // namespace meter::bridge
