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

RegionExpectation expect(const SafetyRegion& region, const Scene& scene, const BindingEvaluator& ev,
                         const std::vector<char>& visible) {
  RegionExpectation e;
  if (!looks_as_measured(scene, ev, region.kind)) return e;
  const auto& out = ev.outputs();
  const auto& bindings = ev.bindings();
  auto binding = [&](int i) -> const Binding* {
    return i >= 0 && std::size_t(i) < bindings.size() ? &bindings[std::size_t(i)] : nullptr;
  };
  switch (region.kind) {
    case SafetyKind::Telltale: {
      e.known = !region.bindings.empty();
      bool lit = true;
      for (int i : region.bindings) {
        const Binding* b = binding(i);
        if (b == nullptr) return {};
        if (b->kind == BindingKind::Visibility) {
          const int n = scene.find_node(b->node);
          lit = lit && n >= 0 && visible[std::size_t(n)] != 0;
        } else if (b->kind == BindingKind::Emissive || b->kind == BindingKind::Color) {
          const int m = scene.find_material(b->material);
          if (m < 0) return {};
          const glm::vec4 c = b->kind == BindingKind::Emissive ? glm::vec4(effective_emissive(scene, out, m), 0.0f)
                                                              : effective_base_color(scene, out, m);
          lit = lit && colour_on(*b, c, b->kind == BindingKind::Emissive);
        }
      }
      if (!region.node.empty()) {
        const int n = scene.find_node(region.node);
        lit = lit && n >= 0 && visible[std::size_t(n)] != 0;
      }
      e.lit = lit;
      return e;
    }
    case SafetyKind::Needle: {
      const Binding* b = region.bindings.empty() ? nullptr : binding(region.bindings.front());
      const int a = scene.find_animation(region.needle.animation);
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
      const int n = scene.find_node(region.node);
      e.text = st.text;
      e.value = st.value;
      e.known = !st.text.empty() && n >= 0 && visible[std::size_t(n)] != 0;
      return e;
    }
  }
  return e;
}

}  // namespace

std::vector<RegionExpectation> expected_states(const IntegrityTable& table, const Scene& scene,
                                               const BindingEvaluator& evaluator) {
  const auto visible = effective_visibility(scene, evaluator.outputs().node_visible);
  std::vector<RegionExpectation> out;
  out.reserve(table.regions.size());
  for (const auto& r : table.regions) out.push_back(expect(r, scene, evaluator, visible));
  return out;
}

RegionExpectation expected_state(const SafetyRegion& region, const Scene& scene, const BindingEvaluator& evaluator) {
  return expect(region, scene, evaluator, effective_visibility(scene, evaluator.outputs().node_visible));
}

}  // namespace meter::engine
