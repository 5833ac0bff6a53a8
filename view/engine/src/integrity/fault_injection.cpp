#include "meter/engine/integrity/fault_injection.hpp"

#include <algorithm>

namespace meter::engine {

namespace {
struct KindName {
  FaultKind kind;
  const char* name;
};
constexpr KindName kKinds[] = {{FaultKind::DropDraw, "drop"},    {FaultKind::WrongColour, "colour"},
                               {FaultKind::CoverDraw, "cover"},  {FaultKind::CoverText, "text"},
                               {FaultKind::StuckFrame, "stuck"}, {FaultKind::StaleNeedle, "needle"}};

std::vector<char> in_subtree(const Scene& scene, int node) {
  std::vector<char> in(scene.nodes.size(), 0);
  for (int n : subtree(scene, node)) in[static_cast<std::size_t>(n)] = 1;
  return in;
}
}  // namespace

std::optional<FaultKind> parse_fault_kind(const std::string& text) {
  for (const auto& k : kKinds)
    if (text == k.name) return k.kind;
  return std::nullopt;
}

const char* fault_kind_name(FaultKind kind) {
  for (const auto& k : kKinds)
    if (k.kind == kind) return k.name;
  return "?";
}

std::vector<int> subtree(const Scene& scene, int node) {
  std::vector<int> out;
  if (node < 0 || static_cast<std::size_t>(node) >= scene.nodes.size()) return out;
  out.push_back(node);
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int c : scene.nodes[static_cast<std::size_t>(out[i])].children) out.push_back(c);
  return out;
}

FrameState faulty_frame(const Scene& scene, const FaultInjection& fault, const FrameState& now,
                        const std::vector<glm::mat4>& held_world) {
  FrameState f = now;
  if (fault.kind != FaultKind::DropDraw && fault.kind != FaultKind::WrongColour && fault.kind != FaultKind::StaleNeedle)
    return f;
  const std::vector<char> in = in_subtree(scene, fault.node);
  for (std::size_t n = 0; n < in.size(); ++n) {
    if (!in[n]) continue;
    if (fault.kind == FaultKind::DropDraw) f.visible[n] = 0;
    if (fault.kind == FaultKind::StaleNeedle && n < held_world.size()) f.world[n] = held_world[n];
  }
  for (std::size_t d = 0; d < scene.draws.size(); ++d) {
    if (!in[static_cast<std::size_t>(scene.draws[d].node)]) continue;
    DrawState& s = f.draws[d];
    if (fault.kind == FaultKind::DropDraw) s.visible = false;
    if (fault.kind == FaultKind::WrongColour) {
      s.base = glm::vec4(s.base.g, s.base.b, s.base.r, s.base.a);
      s.emissive = glm::vec3(s.emissive.g, s.emissive.b, s.emissive.r);
    }
    if (fault.kind == FaultKind::StaleNeedle) s.world = f.world[static_cast<std::size_t>(scene.draws[d].node)];
  }
  return f;
}

FramePlan faulty_plan(const Scene& scene, const DrawClasses& classes, const FaultInjection& fault, FramePlan plan) {
  if (fault.kind != FaultKind::DropDraw) return plan;
  const std::vector<char> in = in_subtree(scene, fault.node);
  auto dropped = [&](int d) {
    const auto i = static_cast<std::size_t>(d);
    return classes.group[i] < 0 && in[static_cast<std::size_t>(scene.draws[i].node)];
  };
  for (Pass& p : plan.passes) std::erase_if(p.draws, dropped);
  if (plan.layer_build) std::erase_if(plan.layer_build->draws, dropped);
  return plan;
}

}  // namespace meter::engine
