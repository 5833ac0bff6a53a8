// The display-feature keys of the scene config: pages, theme, units, sweep, and a binding's unit
// quantity. Errors name the file, the JSON path and what was expected, like the rest of the parser.
#include "scene_features_parser.hpp"

#include <set>

namespace meter::config {
using namespace meter::bridge;  // the vocabulary the parsers fill
namespace {

using namespace config_json;

double duration_ms(const Ctx& c, const json& j, const std::string& path) {
  const double v = number(c, j, path);
  if (v < 0 || v > 60000) c.fail(path, "expected a duration 0..60000 ms");
  return v;
}

PagesConfig parse_pages(const Ctx& c, const json& p) {
  const std::string path = "$.pages";
  if (!p.is_object()) c.fail(path, "expected an object");
  check_keys(c, p, path, {"signal", "nodes", "transitions", "initial", "comment"});
  PagesConfig out;
  if (!p.contains("signal")) c.fail(path + ".signal", "missing (a catalog signal: the page index)");
  out.signal_id = catalog_signal(c, p["signal"], path + ".signal", out.signal);
  if (!p.contains("nodes")) c.fail(path + ".nodes", "missing (the page root nodes, index = page number)");
  out.nodes = strings(c, p["nodes"], path + ".nodes");
  if (out.nodes.size() < 2 || out.nodes.size() > 16) c.fail(path + ".nodes", "expected 2..16 page root nodes");
  out.transitions.resize(out.nodes.size());
  if (p.contains("transitions")) {
    const auto names = strings(c, p["transitions"], path + ".transitions");
    if (names.size() != out.nodes.size()) {
      c.fail(path + ".transitions", "expected one animation name per page (" + std::to_string(out.nodes.size()) +
                                        ", \"\" for none), got " + std::to_string(names.size()));
    }
    for (std::size_t i = 0; i < names.size(); ++i) out.transitions[i].animation = names[i];
  }
  if (p.contains("initial")) {
    const double v = number(c, p["initial"], path + ".initial");
    if (v < 0 || v != std::floor(v) || v >= static_cast<double>(out.nodes.size())) {
      c.fail(path + ".initial", "expected a page index 0.." + std::to_string(out.nodes.size() - 1));
    }
    out.initial = static_cast<int>(v);
  }
  return out;
}

ThemeConfig parse_theme(const Ctx& c, const json& t) {
  const std::string path = "$.theme";
  if (!t.is_object()) c.fail(path, "expected an object");
  check_keys(c, t, path,
             {"signal", "transition_ms", "pairs", "swatch_nodes", "brightness_signal", "brightness_min_stops", "comment"});
  ThemeConfig out;
  if (!t.contains("signal")) c.fail(path + ".signal", "missing (a catalog signal: 0 day, 1 night)");
  out.signal_id = catalog_signal(c, t["signal"], path + ".signal", out.signal);
  if (t.contains("transition_ms")) out.transition_ms = duration_ms(c, t["transition_ms"], path + ".transition_ms");
  if (!t.contains("pairs") || !t["pairs"].is_array() || t["pairs"].empty()) {
    c.fail(path + ".pairs", "expected a non-empty array of {\"day\": material, \"night\": material}");
  }
  std::set<std::string> days;
  for (std::size_t i = 0; i < t["pairs"].size(); ++i) {
    const json& pr = t["pairs"][i];
    const std::string pp = path + ".pairs[" + std::to_string(i) + "]";
    if (!pr.is_object()) c.fail(pp, "expected an object {\"day\": material, \"night\": material}");
    check_keys(c, pr, pp, {"day", "night"});
    if (!pr.contains("day") || !pr.contains("night")) c.fail(pp, "expected both \"day\" and \"night\"");
    ThemePair pair{string(c, pr["day"], pp + ".day"), string(c, pr["night"], pp + ".night")};
    if (!days.insert(pair.day).second) c.fail(pp + ".day", "material \"" + pair.day + "\" is in two pairs");
    out.pairs.push_back(std::move(pair));
  }
  if (t.contains("swatch_nodes")) out.swatch_nodes = strings(c, t["swatch_nodes"], path + ".swatch_nodes");
  if (t.contains("brightness_signal")) {
    out.brightness_signal_id = catalog_signal(c, t["brightness_signal"], path + ".brightness_signal", out.brightness_signal);
  }
  if (t.contains("brightness_min_stops")) {
    out.brightness_min_stops = number(c, t["brightness_min_stops"], path + ".brightness_min_stops");
    if (out.brightness_min_stops < -10 || out.brightness_min_stops > 0) {
      c.fail(path + ".brightness_min_stops", "expected -10..0 stops (the exposure added at 0 % brightness)");
    }
  }
  return out;
}

UnitsConfig parse_units(const Ctx& c, const json& u) {
  const std::string path = "$.units";
  if (!u.is_object()) c.fail(path, "expected an object");
  check_keys(c, u, path,
             {"distance_signal", "temperature_signal", "metric_nodes", "imperial_nodes", "celsius_nodes",
              "fahrenheit_nodes", "comment"});
  UnitsConfig out;
  if (!u.contains("distance_signal") && !u.contains("temperature_signal")) {
    c.fail(path, "expected \"distance_signal\" and/or \"temperature_signal\"");
  }
  if (u.contains("distance_signal")) {
    out.distance_signal_id = catalog_signal(c, u["distance_signal"], path + ".distance_signal", out.distance_signal);
  }
  if (u.contains("temperature_signal")) {
    out.temperature_signal_id =
        catalog_signal(c, u["temperature_signal"], path + ".temperature_signal", out.temperature_signal);
  }
  if (u.contains("metric_nodes")) out.metric_nodes = strings(c, u["metric_nodes"], path + ".metric_nodes");
  if (u.contains("imperial_nodes")) out.imperial_nodes = strings(c, u["imperial_nodes"], path + ".imperial_nodes");
  if (u.contains("celsius_nodes")) out.celsius_nodes = strings(c, u["celsius_nodes"], path + ".celsius_nodes");
  if (u.contains("fahrenheit_nodes")) out.fahrenheit_nodes = strings(c, u["fahrenheit_nodes"], path + ".fahrenheit_nodes");
  return out;
}

SweepConfig parse_sweep(const Ctx& c, const json& s, const json& root) {
  const std::string path = "$.sweep";
  if (!s.is_object()) c.fail(path, "expected an object");
  check_keys(c, s, path, {"signal", "on_at_least", "rise_ms", "hold_ms", "fall_ms", "animations", "comment"});
  SweepConfig out;
  if (!s.contains("signal")) c.fail(path + ".signal", "missing (a catalog signal: the ignition state)");
  out.signal_id = catalog_signal(c, s["signal"], path + ".signal", out.signal);
  if (s.contains("on_at_least")) out.on_at_least = number(c, s["on_at_least"], path + ".on_at_least");
  if (s.contains("rise_ms")) out.rise_ms = duration_ms(c, s["rise_ms"], path + ".rise_ms");
  if (s.contains("hold_ms")) out.hold_ms = duration_ms(c, s["hold_ms"], path + ".hold_ms");
  if (s.contains("fall_ms")) out.fall_ms = duration_ms(c, s["fall_ms"], path + ".fall_ms");
  if (out.rise_ms <= 0 || out.fall_ms <= 0) c.fail(path, "rise_ms and fall_ms must be > 0");
  if (!s.contains("animations")) c.fail(path + ".animations", "missing (the animations of the needles that sweep)");
  out.animations = strings(c, s["animations"], path + ".animations");
  if (out.animations.empty()) c.fail(path + ".animations", "expected at least one animation");
  std::set<std::string> bound;
  if (root.contains("bindings") && root["bindings"].is_array()) {
    for (const auto& b : root["bindings"])
      if (b.is_object() && b.value("kind", "") == "animation" && b.contains("animation") && b["animation"].is_string())
        bound.insert(b["animation"].get<std::string>());
  }
  for (std::size_t i = 0; i < out.animations.size(); ++i) {
    if (!bound.count(out.animations[i])) {
      c.fail(path + ".animations[" + std::to_string(i) + "]",
             "\"" + out.animations[i] + "\" is not the animation of an animation binding");
    }
  }
  return out;
}

}  // namespace

const char* to_string(Quantity q) {
  switch (q) {
    case Quantity::None: return "none";
    case Quantity::Speed: return "speed";
    case Quantity::Distance: return "distance";
    case Quantity::Temperature: return "temperature";
  }
  return "?";
}

SceneFeaturesConfig parse_scene_features(const Ctx& c, const json& root) {
  SceneFeaturesConfig out;
  if (root.contains("pages")) out.pages = parse_pages(c, root["pages"]);
  if (root.contains("theme")) out.theme = parse_theme(c, root["theme"]);
  if (root.contains("units")) out.units = parse_units(c, root["units"]);
  if (root.contains("sweep")) out.sweep = parse_sweep(c, root["sweep"], root);
  return out;
}

BindingUnits parse_binding_units(const Ctx& c, const json& b, const std::string& path, BindingKind kind) {
  BindingUnits out;
  if (b.contains("quantity")) {
    const std::string q = string(c, b["quantity"], path + ".quantity");
    if (q == "speed") out.quantity = Quantity::Speed;
    else if (q == "distance") out.quantity = Quantity::Distance;
    else if (q == "temperature") out.quantity = Quantity::Temperature;
    else c.fail(path + ".quantity", "expected \"speed\", \"distance\" or \"temperature\", got \"" + q + "\"");
  }
  if (!b.contains("imperial")) return out;
  const std::string ip = path + ".imperial";
  if (out.quantity == Quantity::None) c.fail(ip, "needs \"quantity\" (what the value measures)");
  const json& im = b["imperial"];
  if (!im.is_object()) c.fail(ip, "expected an object");
  if (kind == BindingKind::Text) {
    check_keys(c, im, ip, {"format", "failsafe_text"});
    if (im.contains("format")) {
      out.imperial.format = string(c, im["format"], ip + ".format");
      std::string why;
      if (!valid_number_format(*out.imperial.format, &why)) c.fail(ip + ".format", why);
    }
    if (im.contains("failsafe_text")) out.imperial.failsafe_text = string(c, im["failsafe_text"], ip + ".failsafe_text");
  } else {
    check_keys(c, im, ip, {"input"});
    if (im.contains("input")) out.imperial.input = range(c, im["input"], ip + ".input");
  }
  return out;
}

}  // namespace meter::config
