// What each safety region must show, read from the binding evaluator's outputs (the same
// visibility, emissive / colour, animation time and text the renderer draws from), so the
// integrity checks never re-derive a binding's rule.
#include <cmath>

#include "meter/engine/evaluation/scene_evaluator.hpp"
#include "meter/engine/integrity_check.hpp"

namespace meter::engine {
namespace {

template <typename V>
double distance2(const V& a, const V& b) {
  const V d = a - b;
  return double(glm::dot(d, d));
}

// A colour binding is on when its evaluated colour is nearer its "on" than its "off" value.
bool colour_on(const Binding& b, const glm::vec4& c, bool rgb_only) {
  const glm::vec4 on(b.on[0], b.on[1], b.on[2], rgb_only ? 0.0 : b.on[3]);
  const glm::vec4 off(b.off[0], b.off[1], b.off[2], rgb_only ? 0.0 : b.off[3]);
  const glm::vec4 x(c.r, c.g, c.b, rgb_only ? 0.0f : c.a);
  return distance2(x, on) < distance2(x, off);
}

// The looks were measured at conversion in the day theme at the config's exposure, with no page
// transition and no start-up sweep running. In any other display state a region's pixels differ
// from those looks by design (night materials, dimming, a sliding page, a needle sweeping across
// a lamp), so the region is not judged in it (`known` stays false) rather than judged wrongly.
bool looks_as_measured(const Scene& scene, const BindingEvaluator& ev, SafetyKind kind) {
  const FeatureState& f = ev.features().state();
  if (f.theme_mix > 0.0 || f.exposure_stops != scene.config.exposure || f.page_transition) return false;
  // A sweeping needle is judged (its angle is the sweep's); lamps and texts it passes over are not.
  return !f.sweep || kind == SafetyKind::Needle;
}

}  // namespace

ExpectedStates::ExpectedStates(const IntegrityTable& table, const Scene& scene) : table_(table), scene_(scene) {
  parent_.assign(scene.nodes.size(), -1);
  for (std::size_t n = 0; n < scene.nodes.size(); ++n)
    for (int c : scene.nodes[n].children)
      if (c >= 0 && std::size_t(c) < parent_.size()) parent_[std::size_t(c)] = int(n);
  const auto& bindings = scene.config.bindings;
  resolved_.reserve(table.regions.size());
  for (const auto& region : table.regions) {
    Resolved r;
    for (int i : region.bindings) {
      const bool in = i >= 0 && std::size_t(i) < bindings.size();
      r.nodes.push_back(in ? scene.find_node(bindings[std::size_t(i)].node) : -1);
      r.materials.push_back(in ? scene.find_material(bindings[std::size_t(i)].material) : -1);
    }
    r.node = scene.find_node(region.node);
    if (region.kind == SafetyKind::Needle) r.animation = scene.find_animation(region.needle.animation);
    resolved_.push_back(std::move(r));
  }
}

// Effective visibility of one node: it and every ancestor shown (effective_visibility's rule).
bool ExpectedStates::visible(const BindingOutputs& outputs, int node) const {
  if (node < 0) return false;
  for (int n = node; n >= 0; n = parent_[std::size_t(n)])
    if (std::size_t(n) < outputs.node_visible.size() && outputs.node_visible[std::size_t(n)] == 0) return false;
  return true;
}

RegionExpectation ExpectedStates::of(std::size_t index, const BindingEvaluator& ev) const {
  const SafetyRegion& region = table_.regions[index];
  const Resolved& res = resolved_[index];
  RegionExpectation e;
  if (!looks_as_measured(scene_, ev, region.kind)) return e;
  const auto& out = ev.outputs();
  const auto& bindings = ev.bindings();
  auto binding = [&](int i) -> const Binding* {
    return i >= 0 && std::size_t(i) < bindings.size() ? &bindings[std::size_t(i)] : nullptr;
  };
  switch (region.kind) {
    case SafetyKind::Telltale: {
      e.known = !region.bindings.empty();
      bool lit = true;
      for (std::size_t k = 0; k < region.bindings.size(); ++k) {
        const Binding* b = binding(region.bindings[k]);
        if (b == nullptr) return {};
        if (b->kind == BindingKind::Visibility) {
          lit = lit && visible(out, res.nodes[k]);
        } else if (b->kind == BindingKind::Emissive || b->kind == BindingKind::Color) {
          const int m = res.materials[k];
          if (m < 0) return {};
          const glm::vec4 c = b->kind == BindingKind::Emissive ? glm::vec4(effective_emissive(scene_, out, m), 0.0f)
                                                              : effective_base_color(scene_, out, m);
          lit = lit && colour_on(*b, c, b->kind == BindingKind::Emissive);
        }
      }
      if (!region.node.empty()) lit = lit && visible(out, res.node);
      e.lit = lit;
      return e;
    }
    case SafetyKind::Needle: {
      const Binding* b = region.bindings.empty() ? nullptr : binding(region.bindings.front());
      const int a = res.animation;
      if (b == nullptr || a < 0 || std::size_t(a) >= out.animation_time.size()) return {};
      const auto& st = ev.states()[std::size_t(region.bindings.front())];
      e.known = true;
      e.time = out.animation_time[std::size_t(a)];
      e.value = st.has_value ? st.value : std::nan("");
      e.angle_deg = expected_angle(region.needle, e.time);
      return e;
    }
    case SafetyKind::Readout: {
      if (region.bindings.empty() || binding(region.bindings.front()) == nullptr) return {};
      const auto& st = ev.states()[std::size_t(region.bindings.front())];
      e.text = st.text;
      e.value = st.value;
      e.known = !st.text.empty() && visible(out, res.node);
      return e;
    }
  }
  return e;
}

void ExpectedStates::evaluate(const BindingEvaluator& evaluator, std::vector<RegionExpectation>& out) const {
  out.resize(table_.regions.size());
  for (std::size_t i = 0; i < table_.regions.size(); ++i) out[i] = of(i, evaluator);
}

std::vector<RegionExpectation> expected_states(const IntegrityTable& table, const Scene& scene,
                                               const BindingEvaluator& evaluator) {
  std::vector<RegionExpectation> out;
  ExpectedStates(table, scene).evaluate(evaluator, out);
  return out;
}

RegionExpectation expected_state(const SafetyRegion& region, const Scene& scene, const BindingEvaluator& evaluator) {
  IntegrityTable one;
  one.regions = {region};
  return ExpectedStates(one, scene).of(0, evaluator);
}

}  // namespace meter::engine
