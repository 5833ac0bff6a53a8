// Display faults put into the draw submission on purpose, so the integrity monitor can be shown to
// catch them (test hook: meter-view's hidden --inject-fault, docs/integrity.md). Each fault is made
// where the real one would happen: the GL execution draws a frame that differs from the evaluated
// one (a draw left out, a wrong colour uniform, a stale transform, an extra draw or text on top)
// or draws nothing at all (the same image presented again), while the frame plan and every
// record of what was drawn stay as if the frame had been drawn right. The verdict is never faked.
// Pure: the transforms below take and give plain data.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/evaluation/frame_state.hpp"
#include "meter/engine/frame_plan/draw_classes.hpp"
#include "meter/engine/frame_plan/frame_plan.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

enum class FaultKind {
  DropDraw,     // the item's draws are not submitted (a merged member is left out of its group)
  WrongColour,  // the item is drawn with its base and emissive colour channels rotated (r,g,b -> g,b,r)
  CoverDraw,    // a solid grey box is drawn over the item's region after the frame
  CoverText,    // a text ("88") is drawn over the item's region after the frame
  StuckFrame,   // nothing is submitted: the target keeps (presents again) the last image
  StaleNeedle,  // the item keeps the transform it had when the fault started
};

// "drop" | "colour" | "cover" | "text" | "stuck" | "needle"; nullopt otherwise.
std::optional<FaultKind> parse_fault_kind(const std::string& text);
const char* fault_kind_name(FaultKind kind);

struct FaultInjection {
  FaultKind kind = FaultKind::DropDraw;
  int node = -1;                 // the item's node (its subtree is affected); unused for StuckFrame
  platform::PixelRegion box;     // CoverDraw / CoverText: the box covered (GL window coordinates)
};

// The nodes of `node`'s subtree (node first).
std::vector<int> subtree(const Scene& scene, int node);

// The frame the GL execution is given under `fault` instead of `now`. `held_world`: the per-node
// world matrices when the fault started (StaleNeedle). DropDraw hides the subtree's draws;
// WrongColour rotates their colours; the others leave the frame as it is.
FrameState faulty_frame(const Scene& scene, const FaultInjection& fault, const FrameState& now,
                        const std::vector<glm::mat4>& held_world);

// The plan with the subtree's own (unmerged) draws left out of every pass (DropDraw; merged
// members are left out through their visibility in faulty_frame). Other kinds: unchanged.
FramePlan faulty_plan(const Scene& scene, const DrawClasses& classes, const FaultInjection& fault, FramePlan plan);

}  // namespace meter::engine
