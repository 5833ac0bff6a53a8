// The display features of a scene: their signals read, their timelines advanced on the render
// clock, their effects written over the bindings' outputs.
#include <algorithm>
#include <cmath>
#include <limits>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/evaluation/scene_features.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::engine {

namespace {

int resolve(const Scene& scene, const std::string& key, const std::string& name, bool material = false) {
  const int i = material ? scene.find_material(name) : scene.find_node(name);
  if (i < 0) {
    throw SceneError(scene.source_name + ": scene config " + key + ": no " + (material ? "material" : "node") +
                     " named \"" + name + "\"");
  }
  return i;
}

std::vector<int> resolve_nodes(const Scene& scene, const std::string& key, const std::vector<std::string>& names) {
  std::vector<int> out;
  for (const auto& n : names) out.push_back(resolve(scene, key, n));
  return out;
}

// A Valid signal's value while the link is up, else nothing.
std::optional<double> valid_value(const protocol::SignalTable& signals, bool link_up, int id) {
  if (!link_up || id < 0 || id > std::numeric_limits<protocol::SignalId>::max()) return std::nullopt;
  const auto* s = signals.find(static_cast<protocol::SignalId>(id));
  if (!s || s->status != protocol::SignalStatus::Valid || !std::isfinite(s->value)) return std::nullopt;
  return s->value;
}

void show(BindingOutputs& out, const std::vector<int>& nodes, bool visible) {
  for (int n : nodes) out.node_visible[static_cast<std::size_t>(n)] = visible ? 1 : 0;
}

int rebind_id(const protocol::Catalog& catalog, const std::string& name, std::vector<std::string>& missing) {
  if (name.empty()) return -1;
  const auto* info = catalog.find(name);
  if (!info) missing.push_back(name);
  return info ? info->id : -1;
}

}  // namespace

SceneFeatures::SceneFeatures(const Scene& scene) : scene_(scene), config_(scene.config.features) {
  if (config_.pages) {
    const auto& p = *config_.pages;
    page_nodes_ = resolve_nodes(scene, "$.pages.nodes", p.nodes);
    std::vector<double> durations;
    for (const auto& t : p.transitions) {
      int clip = -1;
      if (!t.animation.empty()) {
        clip = scene.find_animation(t.animation);
        if (clip < 0) throw SceneError(scene.source_name + ": scene config $.pages.transitions: no animation named \"" + t.animation + "\"");
      }
      page_clips_.push_back(clip);
      const auto& a = clip >= 0 ? scene.animations[static_cast<std::size_t>(clip)] : Animation{};
      durations.push_back(clip >= 0 ? static_cast<double>(a.end - a.start) : 0.0);
    }
    pages_.emplace(static_cast<int>(page_nodes_.size()), p.initial, durations);
  }
  if (config_.theme) {
    for (const auto& pr : config_.theme->pairs) {
      theme_.push_back({resolve(scene, "$.theme.pairs", pr.day, true), resolve(scene, "$.theme.pairs", pr.night, true)});
    }
    swatch_nodes_ = resolve_nodes(scene, "$.theme.swatch_nodes", config_.theme->swatch_nodes);
  }
  if (config_.units) {
    const auto& u = *config_.units;
    metric_nodes_ = resolve_nodes(scene, "$.units.metric_nodes", u.metric_nodes);
    imperial_nodes_ = resolve_nodes(scene, "$.units.imperial_nodes", u.imperial_nodes);
    celsius_nodes_ = resolve_nodes(scene, "$.units.celsius_nodes", u.celsius_nodes);
    fahrenheit_nodes_ = resolve_nodes(scene, "$.units.fahrenheit_nodes", u.fahrenheit_nodes);
  }
  if (config_.sweep) {
    for (const auto& a : config_.sweep->animations) {
      const int i = scene.find_animation(a);
      if (i < 0) throw SceneError(scene.source_name + ": scene config $.sweep.animations: no animation named \"" + a + "\"");
      sweep_animations_.push_back(i);
    }
    sweep_.emplace(*config_.sweep);
    // The animation bindings whose needles sweep, resolved once: apply() runs every frame.
    for (const auto& b : scene.config.bindings) {
      if (b.kind != BindingKind::Animation) continue;
      const int a = scene.find_animation(b.animation);
      if (a >= 0 && sweeps(a)) swept_.push_back({a, b.time[0], b.time[1]});
    }
  }
  state_.exposure_stops = scene.config.exposure;
  if (pages_) state_.page = pages_->current();
}

FeatureInputs SceneFeatures::read_inputs(const protocol::SignalTable& signals, bool link_up) const {
  FeatureInputs in;
  if (config_.pages) {
    const auto v = valid_value(signals, link_up, config_.pages->signal_id);
    if (v && std::abs(*v) < 1e6) in.page = static_cast<int>(std::lround(*v));
  }
  if (config_.theme) {
    in.theme = valid_value(signals, link_up, config_.theme->signal_id);
    in.brightness = valid_value(signals, link_up, config_.theme->brightness_signal_id);
  }
  if (config_.units) {
    // Not valid (never received, timed out, link down): the metric look the scene is authored in.
    const auto d = valid_value(signals, link_up, config_.units->distance_signal_id);
    const auto t = valid_value(signals, link_up, config_.units->temperature_signal_id);
    in.units.imperial_distance = d && *d >= 0.5;
    in.units.fahrenheit = t && *t >= 0.5;
  }
  if (config_.sweep) in.ignition = valid_value(signals, link_up, config_.sweep->signal_id);
  return in;
}

void FeatureOverrides::apply(FeatureInputs& in) const {
  if (page) in.page = page;
  if (theme) in.theme = theme;
  if (brightness) in.brightness = brightness;
  if (units) in.units = *units;
}

void SceneFeatures::update(const FeatureInputs& in, double dt) {
  if (pages_) {
    pages_->update(in.page, dt);
    state_.page = pages_->current();
    state_.page_transition = pages_->transition();
  }
  if (config_.theme) {
    // Without a valid theme the look holds (a lost signal does not flash the cluster to day).
    const double target = in.theme ? (*in.theme >= 0.5 ? 1.0 : 0.0) : state_.theme_progress;
    state_.theme_progress = theme_progress(state_.theme_progress, target, config_.theme->transition_ms / 1000.0, dt);
    state_.theme_mix = theme_curve(state_.theme_progress);
    state_.exposure_stops = scene_.config.exposure;
    if (in.brightness) state_.exposure_stops += brightness_stops(*in.brightness, config_.theme->brightness_min_stops);
  }
  state_.units = in.units;
  if (sweep_) {
    sweep_->update(in.ignition, dt);
    state_.sweep = sweep_->position();
  }
}

bool SceneFeatures::active() const {
  const bool theme_moving = config_.theme && state_.theme_progress != 0.0 && state_.theme_progress != 1.0;
  return state_.page_transition.has_value() || theme_moving || state_.sweep.has_value();
}

bool SceneFeatures::sweeps(int animation) const {
  for (int a : sweep_animations_)
    if (a == animation) return true;
  return false;
}

void SceneFeatures::apply(BindingOutputs& out) const {
  if (pages_) {
    for (std::size_t k = 0; k < page_nodes_.size(); ++k) {
      out.node_visible[static_cast<std::size_t>(page_nodes_[k])] = pages_->shown(static_cast<int>(k)) ? 1 : 0;
      const int clip = page_clips_[k];
      if (clip < 0) continue;
      // A page's clip rests at its end (the page in place); it plays while the page is entered.
      const auto& a = scene_.animations[static_cast<std::size_t>(clip)];
      const bool entering = state_.page_transition && static_cast<int>(k) == state_.page;
      const double p = entering ? *state_.page_transition : 1.0;
      out.animation_time[static_cast<std::size_t>(clip)] = a.start + p * (a.end - a.start);
    }
  }
  if (config_.theme) {
    show(out, swatch_nodes_, false);
    if (state_.theme_mix > 0.0) {
      const auto m = static_cast<float>(state_.theme_mix);
      for (const auto& t : theme_) {
        const auto& day = scene_.materials[static_cast<std::size_t>(t.day)];
        const auto& night = scene_.materials[static_cast<std::size_t>(t.night)];
        out.base_color[static_cast<std::size_t>(t.day)] = glm::mix(day.base_color, night.base_color, m);
        out.emissive[static_cast<std::size_t>(t.day)] = glm::mix(day.emissive, night.emissive, m);
      }
    }
    if (state_.exposure_stops != scene_.config.exposure) {
      out.exposure = state_.exposure_stops;
      // Texts are drawn with designer (sRGB) colours, outside the shaders: dimmed the same way.
      const double k = std::exp2(state_.exposure_stops - scene_.config.exposure);
      for (auto& t : out.texts)
        for (int c = 0; c < 3; ++c)
          t.color[c] = static_cast<float>(platform::linear_to_srgb(std::min(1.0, platform::srgb_to_linear(t.color[c]) * k)));
    }
  }
  if (config_.units) {
    show(out, metric_nodes_, !state_.units.imperial_distance);
    show(out, imperial_nodes_, state_.units.imperial_distance);
    show(out, celsius_nodes_, !state_.units.fahrenheit);
    show(out, fahrenheit_nodes_, state_.units.fahrenheit);
  }
  if (state_.sweep) {
    for (const auto& s : swept_)
      out.animation_time[static_cast<std::size_t>(s.animation)] = s.time0 + *state_.sweep * (s.time1 - s.time0);
  }
}

std::vector<std::string> SceneFeatures::rebind(const protocol::Catalog& catalog) {
  std::vector<std::string> missing;
  if (config_.pages) config_.pages->signal_id = rebind_id(catalog, config_.pages->signal, missing);
  if (config_.theme) {
    config_.theme->signal_id = rebind_id(catalog, config_.theme->signal, missing);
    config_.theme->brightness_signal_id = rebind_id(catalog, config_.theme->brightness_signal, missing);
  }
  if (config_.units) {
    config_.units->distance_signal_id = rebind_id(catalog, config_.units->distance_signal, missing);
    config_.units->temperature_signal_id = rebind_id(catalog, config_.units->temperature_signal, missing);
  }
  if (config_.sweep) config_.sweep->signal_id = rebind_id(catalog, config_.sweep->signal, missing);
  return missing;
}

}  // namespace meter::engine
