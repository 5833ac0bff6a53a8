#include "meter/engine/logic/scripts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>

#include <glm/gtc/quaternion.hpp>

#include "logic/lua_sandbox.hpp"

namespace meter::engine {

using bridge::ScriptOutputKind;

struct ScriptEngine::Output {
  const bridge::ScriptOutput* spec = nullptr;
  int target = -1;              // node, material or animation index
  logic::OutputValue value;     // what the script last produced
  logic::OutputValue shown;     // what is laid over the outputs (value, failsafe or held)
};

struct ScriptEngine::Entry {
  const bridge::Script* script = nullptr;
  std::unique_ptr<logic::LuaSandbox> sandbox;
  std::vector<int> signal_ids;                 // per input; -1 = not in the catalog
  std::vector<logic::InputValue> now, seen;    // inputs this update / at the last run
  bool has_seen = false;                       // false: the next update runs it
  std::vector<Output> outputs;
  std::vector<logic::OutputValue> scratch;     // a run's outputs, taken only when it succeeds
  bool failed = false;
  std::uint64_t failed_runs = 0;               // since the last successful run
  // message rate limit
  bool messaged = false;
  Clock::time_point last_message{};
  std::uint64_t suppressed = 0;
  bool last_told_failure = false;
};

namespace {

bool same(const logic::InputValue& a, const logic::InputValue& b) {
  // Bits, as the signal table compares: -0.0 after 0.0 is a change, NaN equals its own bits.
  return std::memcmp(&a.value, &b.value, sizeof a.value) == 0 && a.status == b.status && a.is_text == b.is_text &&
         a.is_integer == b.is_integer && a.text == b.text;
}

logic::OutputValue failsafe_of(const bridge::ScriptOutput& o, const logic::OutputValue& held) {
  logic::OutputValue f;
  f.set = true;
  if (o.failsafe_visible) f.visible = *o.failsafe_visible;
  else if (o.failsafe_text) f.text = *o.failsafe_text;
  else if (o.failsafe_numbers) std::copy_n(o.failsafe_numbers->begin(), std::min<std::size_t>(4, o.failsafe_numbers->size()), f.numbers.begin());
  else return held;  // no failsafe: hold what it showed last, as a binding does
  return f;
}

NodeTransformOverride& transform_of(BindingOutputs& out, int node) {
  for (auto& t : out.transforms)
    if (t.node == node) return t;
  out.transforms.push_back({node, std::nullopt, std::nullopt});
  return out.transforms.back();
}

// Euler angles in degrees, applied about X, then Y, then Z (of the parent's frame).
glm::quat euler_degrees(const std::array<double, 4>& v) {
  const auto axis = [](double deg, glm::vec3 a) { return glm::angleAxis(static_cast<float>(glm::radians(deg)), a); };
  return axis(v[2], {0, 0, 1}) * axis(v[1], {0, 1, 0}) * axis(v[0], {1, 0, 0});
}

void lay(const bridge::ScriptOutput& spec, int target, const logic::OutputValue& v, BindingOutputs& out) {
  if (!v.set) return;
  const auto t = static_cast<std::size_t>(target);
  const auto& n = v.numbers;
  switch (spec.kind) {
    case ScriptOutputKind::Animation: out.animation_time[t] = n[0]; break;
    case ScriptOutputKind::Visible: out.node_visible[t] = v.visible ? 1 : 0; break;
    case ScriptOutputKind::Translation: transform_of(out, target).translation = glm::vec3(n[0], n[1], n[2]); break;
    case ScriptOutputKind::Rotation: transform_of(out, target).rotation = euler_degrees(n); break;
    case ScriptOutputKind::Morph: out.morph.push_back({target, spec.morph_target, static_cast<float>(n[0])}); break;
    case ScriptOutputKind::Color: out.base_color[t] = glm::vec4(n[0], n[1], n[2], n[3]); break;
    case ScriptOutputKind::Emissive: out.emissive[t] = glm::vec3(n[0], n[1], n[2]); break;
    case ScriptOutputKind::Text: {
      // The script's text replaces a binding's on the same node.
      std::erase_if(out.texts, [&](const TextItem& item) { return item.node == target; });
      if (v.text.empty()) break;
      const auto& c = spec.color;
      out.texts.push_back({target, v.text, static_cast<int>(std::lround(spec.size_px)), glm::vec4(c[0], c[1], c[2], c[3]), spec.align});
      break;
    }
  }
}

int resolve_target(const Scene& scene, const bridge::Script& s, const bridge::ScriptOutput& o) {
  int found = -1;
  const char* what = "node";
  if (o.kind == ScriptOutputKind::Animation) found = scene.find_animation(o.target), what = "animation";
  else if (bridge::targets_material(o.kind)) found = scene.find_material(o.target), what = "material";
  else found = scene.find_node(o.target);
  if (found < 0) {
    throw SceneError(scene.source_name + ": script " + s.name + " output " + o.name + ": no " + what + " named \"" + o.target + "\"");
  }
  return found;
}

}  // namespace

std::string describe(const ScriptStats& s) {
  char buf[256];
  const double mean_us = s.runs ? s.total_ms * 1000.0 / static_cast<double>(s.runs) : 0.0;
  std::snprintf(buf, sizeof buf, "%s: %llu runs / %llu updates, %llu failed, %.1f us mean, %.1f us max, %zu KiB%s", s.name.c_str(),
                static_cast<unsigned long long>(s.runs), static_cast<unsigned long long>(s.updates),
                static_cast<unsigned long long>(s.failures), mean_us, s.max_ms * 1000.0, (s.memory_peak_bytes + 1023) / 1024,
                s.failed ? " (failed: outputs in failsafe)" : "");
  return buf;
}

ScriptEngine::ScriptEngine(const Scene& scene, std::chrono::milliseconds message_interval)
    : scene_(scene), interval_(message_interval) {
  for (const auto& s : scene.config.scripts) {
    auto e = std::make_unique<Entry>();
    e->script = &s;
    for (const auto& o : s.outputs) e->outputs.push_back({&o, resolve_target(scene, s, o), {}, {}});
    for (const auto& in : s.inputs) e->signal_ids.push_back(in.signal_id);
    e->now.resize(s.inputs.size());
    entries_.push_back(std::move(e));
    ScriptStats st;
    st.name = s.name;
    stats_.push_back(std::move(st));
  }
  // The states are created once every target resolved: a scene error leaves no state behind.
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    Entry& e = *entries_[i];
    e.sandbox = std::make_unique<logic::LuaSandbox>(*e.script);
    stats_[i].memory_bytes = e.sandbox->memory();
    stats_[i].memory_peak_bytes = e.sandbox->memory_peak();
    if (e.sandbox->broken()) {
      e.failed = true;
      ++stats_[i].failures;
      stats_[i].failed = true;
      stats_[i].last_error = e.sandbox->error();
      note(i, e.sandbox->error() + " (the script did not load: its outputs stay in failsafe)", true);
    }
  }
}

ScriptEngine::~ScriptEngine() = default;

std::vector<std::string> ScriptEngine::rebind(const protocol::Catalog& catalog) {
  std::vector<std::string> missing;
  for (auto& e : entries_) {
    for (std::size_t k = 0; k < e->script->inputs.size(); ++k) {
      const auto* info = catalog.find(e->script->inputs[k].signal);
      e->signal_ids[k] = info ? info->id : -1;
      if (!info) missing.push_back(e->script->inputs[k].signal);
    }
    e->has_seen = false;  // ids changed: look again
  }
  return missing;
}

std::vector<std::string> ScriptEngine::take_messages() { return std::exchange(messages_, {}); }

void ScriptEngine::note(std::size_t i, const std::string& message, bool failure) {
  Entry& e = *entries_[i];
  const auto now = Clock::now();
  // A recovery is always told after a failure that was: the log never ends on a stale failure.
  const bool tells_recovery = !failure && e.last_told_failure;
  if (e.messaged && now - e.last_message < interval_ && !tells_recovery) {
    if (failure) ++e.suppressed;
    return;
  }
  std::string m = message;
  if (e.suppressed > 0) m += " (" + std::to_string(e.suppressed) + " more failures since the last message)";
  messages_.push_back(std::move(m));
  e.messaged = true;
  e.last_message = now;
  e.suppressed = 0;
  e.last_told_failure = failure;
}

void ScriptEngine::run_script(std::size_t i) {
  Entry& e = *entries_[i];
  ScriptStats& st = stats_[i];
  const auto t0 = Clock::now();
  const bool ok = e.sandbox->run(e.now, e.scratch);
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  ++st.runs;
  st.last_ms = ms;
  st.total_ms += ms;
  st.max_ms = std::max(st.max_ms, ms);
  st.memory_bytes = e.sandbox->memory();
  st.memory_peak_bytes = e.sandbox->memory_peak();
  e.seen = e.now;
  e.has_seen = true;
  if (ok) {
    for (std::size_t k = 0; k < e.outputs.size(); ++k) e.outputs[k].value = e.scratch[k];
    if (e.failed) note(i, e.script->name + ": runs again after " + std::to_string(e.failed_runs) + " failed runs", false);
    e.failed = false;
    e.failed_runs = 0;
  } else {
    ++st.failures;
    ++e.failed_runs;
    e.failed = true;
    st.last_error = e.sandbox->error();
    note(i, e.sandbox->error() + " (outputs in failsafe; tried again when an input changes)", true);
  }
  st.failed = e.failed;
}

void ScriptEngine::update(const protocol::SignalTable& signals, bool link_up, BindingOutputs& outputs) {
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    Entry& e = *entries_[i];
    ++stats_[i].updates;
    if (!link_up) {
      e.has_seen = false;  // run again once the link is back, whatever the values then
    } else if (!e.sandbox->broken()) {
      for (std::size_t k = 0; k < e.now.size(); ++k) {
        logic::InputValue& v = e.now[k];
        const int id = e.signal_ids[k];
        const bool in_range = id >= 0 && id <= 0xFFFF;
        const protocol::SignalState* sv = in_range ? signals.find(static_cast<protocol::SignalId>(id)) : nullptr;
        const protocol::SignalInfo* info = in_range ? signals.catalog().find(static_cast<protocol::SignalId>(id)) : nullptr;
        v.is_text = info && info->kind == protocol::SignalKind::Text;
        v.status = sv ? sv->status : protocol::SignalStatus::NotAvailable;
        v.value = sv ? sv->value : 0.0;
        v.text = sv && v.is_text ? sv->text : std::string();
        // A number the view cannot draw is not a value: the script sees it as invalid.
        if (v.status == protocol::SignalStatus::Valid && !v.is_text && !std::isfinite(v.value)) v.status = protocol::SignalStatus::Invalid;
        const bool whole_kind = info && (info->kind == protocol::SignalKind::Enum || info->kind == protocol::SignalKind::Telltale);
        v.is_integer = whole_kind && std::isfinite(v.value) && v.value == std::floor(v.value) && std::abs(v.value) < 9e15;
      }
      bool changed = !e.has_seen;
      for (std::size_t k = 0; k < e.now.size() && !changed; ++k) changed = !same(e.now[k], e.seen[k]);
      if (changed) run_script(i);
    }
    const bool failsafe = !link_up || e.failed;
    for (auto& o : e.outputs) {
      o.shown = failsafe ? failsafe_of(*o.spec, o.shown) : o.value;
      lay(*o.spec, o.target, o.shown, outputs);
    }
  }
}

}  // namespace meter::engine
