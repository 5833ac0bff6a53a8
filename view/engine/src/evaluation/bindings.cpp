#include "meter/engine/evaluation/bindings.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "meter/engine/logic/scripts.hpp"

namespace meter::engine {

std::string binding_text(const Binding& b, double value) {
  if (!std::isfinite(value)) return "---";
  const double r = std::round(value);
  if (!b.map.empty() && std::abs(value - r) < 1e-9 && std::abs(r) < 9e15) {
    auto it = b.map.find(static_cast<long long>(r));
    if (it != b.map.end()) return it->second;
  }
  return format_number(b.format, value);
}

std::optional<protocol::SignalId> bound_signal_id(const Binding& b) {
  if (b.signal_id < 0 || b.signal_id > std::numeric_limits<protocol::SignalId>::max()) return std::nullopt;
  return static_cast<protocol::SignalId>(b.signal_id);
}

BindingOutputs resting_outputs(const Scene& scene) {
  BindingOutputs o;
  o.animation_time.assign(scene.animations.size(), scene.config.time);
  o.node_visible.assign(scene.nodes.size(), -1);
  o.emissive.assign(scene.materials.size(), std::nullopt);
  o.base_color.assign(scene.materials.size(), std::nullopt);
  return o;
}

BindingEvaluator::BindingEvaluator(const Scene& scene)
    : scene_(scene), bindings_(scene.config.bindings), features_(scene) {
  for (const auto& b : bindings_) {
    imperial_.push_back(b.units.quantity == Quantity::None ? b : imperial_binding(b));
    Resolved r;
    switch (b.kind) {
      case BindingKind::Animation: r.animation = scene.find_animation(b.animation); break;
      case BindingKind::Visibility:
      case BindingKind::Text:
      case BindingKind::Morph: r.node = scene.find_node(b.node); break;
      case BindingKind::Emissive:
      case BindingKind::Color: r.material = scene.find_material(b.material); break;
    }
    if (r.animation < 0 && r.node < 0 && r.material < 0) {
      throw SceneError(scene.source_name + ": binding for " + b.signal + " (" + to_string(b.kind) +
                       ") refers to a name the scene does not have");
    }
    resolved_.push_back(r);
  }
  state_.resize(bindings_.size());
  if (!scene.config.link_loss.text_node.empty()) link_loss_node_ = scene.find_node(scene.config.link_loss.text_node);
  out_ = resting_outputs(scene);
  if (!scene.config.scripts.empty()) scripts_ = std::make_unique<ScriptEngine>(scene);
}

BindingEvaluator::~BindingEvaluator() = default;

std::vector<std::string> BindingEvaluator::rebind(const protocol::Catalog& catalog) {
  std::vector<std::string> missing;
  for (auto& b : bindings_) {
    const auto* info = catalog.find(b.signal);
    b.signal_id = info ? info->id : -1;
    if (!info) missing.push_back(b.signal);
  }
  if (scripts_)
    for (auto& name : scripts_->rebind(catalog)) missing.push_back(std::move(name));
  for (std::size_t i = 0; i < bindings_.size(); ++i) imperial_[i].signal_id = bindings_[i].signal_id;
  for (auto& name : features_.rebind(catalog)) missing.push_back(std::move(name));
  return missing;
}

namespace {

double unit(double v, const std::array<double, 2>& range) {
  const double u = (v - range[0]) / (range[1] - range[0]);  // parse guarantees range[0] != range[1]
  return std::clamp(u, 0.0, 1.0);
}

}  // namespace

bool BindingEvaluator::update(const protocol::SignalTable& signals, bool link_up, double dt) {
  using protocol::SignalStatus;
  BindingOutputs next = resting_outputs(scene_);
  next.link_lost = !link_up;
  animating_ = false;
  FeatureInputs feature_inputs = features_.read_inputs(signals, link_up);
  overrides_.apply(feature_inputs);
  features_.update(feature_inputs, dt);
  for (std::size_t i = 0; i < bindings_.size(); ++i) {
    const Quantity quantity = bindings_[i].units.quantity;
    const bool imperial = shows_imperial(features_.state().units, quantity);
    const Binding& b = imperial ? imperial_[i] : bindings_[i];
    const Resolved& r = resolved_[i];
    BindingState& st = state_[i];
    if (st.imperial != imperial) {  // the unit switched: what is drawn switches with it, no smoothing
      auto conv = [&](double v) { return imperial ? to_imperial(quantity, v) : to_metric(quantity, v); };
      st.value = conv(st.value), st.target = conv(st.target), st.imperial = imperial;
    }
    // The sweep leaves its needles at rest: from there they move to their value as smoothed.
    if (features_.sweep_just_ended() && b.kind == BindingKind::Animation && st.has_value &&
        features_.sweeps(r.animation)) {
      st.value = b.input[0];
    }
    // Absent (no such id) and present-but-NotAvailable read the same: status NotAvailable, and the
    // entry's value and text are only ever read when it is Valid.
    const auto id = bound_signal_id(b);
    const protocol::SignalState* sv = id ? signals.find(*id) : nullptr;
    st.status = sv ? sv->status : SignalStatus::NotAvailable;
    const bool valid = link_up && sv && sv->status == SignalStatus::Valid && std::isfinite(sv->value);
    st.failsafe = !valid;
    // Target value.
    bool have_target = false;
    double target = st.target;
    if (valid) {
      target = imperial ? to_imperial(quantity, sv->value) : sv->value, have_target = true;
    } else if (b.failsafe_value) {
      target = *b.failsafe_value, have_target = true;
    }
    if (have_target) {
      st.target = target;
      const bool smooth = b.smoothing_ms > 0 && dt >= 0 && st.has_value;
      if (smooth) {
        const double k = 1.0 - std::exp(-dt * 1000.0 / b.smoothing_ms);
        st.value += (target - st.value) * k;
        const double span = b.has_input ? std::abs(b.input[1] - b.input[0]) : 1.0;
        if (std::abs(target - st.value) <= 1e-4 * span) st.value = target;
      } else {
        st.value = target;
      }
      st.has_value = true;
    }
    if (st.has_value && st.value != st.target) animating_ = true;
    // Effect.
    switch (b.kind) {
      case BindingKind::Animation:
        if (st.has_value) {
          const double u = unit(st.value, b.input);
          next.animation_time[static_cast<std::size_t>(r.animation)] = b.time[0] + u * (b.time[1] - b.time[0]);
        }
        break;
      case BindingKind::Visibility: {
        std::optional<bool> on;
        if (!valid && b.failsafe_visible) on = *b.failsafe_visible;
        else if (st.has_value) on = (st.value >= b.threshold) != b.invert;
        if (on) next.node_visible[static_cast<std::size_t>(r.node)] = *on ? 1 : 0;
        break;
      }
      case BindingKind::Emissive:
      case BindingKind::Color:
        if (st.has_value) {
          const double u = b.has_input ? unit(st.value, b.input) : (st.value >= b.threshold ? 1.0 : 0.0);
          glm::dvec4 c = glm::mix(glm::dvec4(b.off[0], b.off[1], b.off[2], b.off[3]), glm::dvec4(b.on[0], b.on[1], b.on[2], b.on[3]), u);
          if (b.kind == BindingKind::Emissive) next.emissive[static_cast<std::size_t>(r.material)] = glm::vec3(c);
          else next.base_color[static_cast<std::size_t>(r.material)] = glm::vec4(c);
        }
        break;
      case BindingKind::Morph:
        if (st.has_value) {
          const double u = unit(st.value, b.input);
          next.morph.push_back({r.node, b.morph_target, static_cast<float>(b.weight[0] + u * (b.weight[1] - b.weight[0]))});
        }
        break;
      case BindingKind::Text: {
        const auto* info = id ? protocol::find_signal(*id) : nullptr;
        if (valid) {
          st.text = info && info->kind == protocol::SignalKind::Text ? sv->text : binding_text(b, st.value);
        } else if (b.failsafe_text) {
          st.text = *b.failsafe_text;
        } else if (b.failsafe_value) {
          st.text = binding_text(b, *b.failsafe_value);
        }  // else: hold the last text
        if (!st.text.empty()) {
          next.texts.push_back({r.node, st.text, static_cast<int>(std::lround(b.size_px)),
                                glm::vec4(b.color[0], b.color[1], b.color[2], b.color[3]), b.align});
        }
        break;
      }
    }
  }
  features_.apply(next);
  animating_ = animating_ || features_.active();
  // Scripts after the bindings (their outputs win), before the link-loss text (which nothing hides).
  if (scripts_) scripts_->update(signals, link_up, next);
  if (!link_up && link_loss_node_ >= 0) {
    const auto& l = scene_.config.link_loss;
    next.texts.push_back({link_loss_node_, l.text, static_cast<int>(std::lround(l.size_px)),
                          glm::vec4(l.color[0], l.color[1], l.color[2], l.color[3]), l.align});
  }
  const bool changed = first_ || !(next == out_);
  first_ = false;
  out_ = std::move(next);
  return changed;
}

}  // namespace meter::engine
