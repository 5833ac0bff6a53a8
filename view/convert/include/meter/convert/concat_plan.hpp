// Mesh concatenation planning (the DENSO paper sec. 5.2, docs/concatenation.md).
//
// Many small objects that share a material are drawn as ONE draw (the runtime side is
// meter/engine/merged_draws.hpp). The data converter decides which (plan_groups): a group is only
// accepted when merging it cannot change the image:
//   - every member is a mesh node whose primitives all use the group's one material (so one set of
//     uniforms and one blend state serve all), with the same vertex layout, no skin, no morph;
//   - no member is in two groups;
//   - members do not overlap each other on screen (blended) or on screen at intersecting depth
//     ranges (opaque / mask: the depth test makes order irrelevant unless depths tie), over the
//     whole range of every animation that moves them;
//   - the merged draw takes the representative's place in the sorted draw list, so for every
//     overlapping pair of draws in different units (group or single draw) the order between their
//     units must equal the order between the draws themselves, at every animation time.
// Pure functions on the Scene: no GL, no shader compiler.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meter/convert/merge_break_even.hpp"
#include "meter/convert/vocabulary.hpp"

namespace meter::convert {

// Where a would-be draw (node x primitive, in the traversal order the converter emits draws in)
// can be on screen and in depth over the animation ranges.
struct DrawExtent {
  int node = -1, primitive = -1;
  bool blend = false;
  glm::vec2 screen_min{0.0f}, screen_max{0.0f};  // pixels; with no camera: world x/y
  float depth_min = 0.0f, depth_max = 0.0f;      // clip w of the geometry (view depth)
  float key_min = 0.0f, key_max = 0.0f;          // clip w of the bounds centre (the sort key)
};

// Draws in converter order with their extents. Every animation is sampled over its whole key range
// (keys plus 8 steps per key interval) with the other animations at their start and at their end.
std::vector<DrawExtent> draw_extents(const Scene& scene);

struct GroupDecision {
  std::string group;
  bool accepted = false;
  std::vector<std::string> members;
  std::vector<std::string> reasons;  // why accepted (what was checked) or why rejected
};

struct ConcatPlan {
  std::vector<Group> groups;              // accepted groups, members in draw order
  std::vector<GroupDecision> decisions;   // one per configured / proposed group (and rejected nodes)
};

// Checks the config's groups; with `propose`, also groups the remaining mesh nodes automatically
// (greedy in draw order per material + layout + blend state). Throws SceneError naming the file,
// the group and the objects when a configured group violates a constraint. With `costs`, a group
// (configured or proposed) that the break-even test says would not pay stays unmerged, and every
// group's decision gives its predicted before / after (merge_break_even.hpp); without, every
// allowed group is merged.
ConcatPlan plan_groups(const Scene& scene, const std::vector<Group>& configured, bool propose,
                       const std::string& origin, const ConcatenationCosts* costs = nullptr);

// The `--report` section: each decision with its reasons.
std::string concat_report(const ConcatPlan& plan);

// Fills scene.groups (draw indices) from the plan once scene.draws exists.
void attach_groups(Scene& scene, const ConcatPlan& plan);

}  // namespace meter::convert
