// The DENSO paper's break-even test for mesh concatenation (sec. 5.2, eq. 1-3): whether drawing a
// group's objects as one merged draw makes the frame cheaper, from the costs meter-calibrate
// measured (meter-costs/1's "concatenation" block: oh, m, s).
//
//   eq. 1  before = (oh + m v) obj                     every object its own draw
//   eq. 2  after  = oh + s (v + k) obj + m (v + k) obj one draw; the CPU transforms the members
//   eq. 3  merging pays when after < before
//
// With v obj = V, the group's vertices. Two differences from the paper, both from what the engine
// does (meter/engine/merged_draws.hpp): the merged array is an indexed triangle list, so no
// joining vertices (k = 0); and a member's vertices are transformed again only when its world
// matrix changes, so s applies to the vertices of members that can move (Vm, the members under an
// animated or scripted node), not to all. Then after < before <=> (obj - 1) oh > s Vm: a group
// that never moves always pays (obj >= 2), a moving one from obj > 1 + s Vm / oh.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "meter/convert/vocabulary.hpp"
#include "meter/engine/governor/cost_file.hpp"

namespace meter::convert {

using engine::governor::ConcatenationCosts;

struct MergePrediction {
  int objects = 0;                     // draws before merging
  std::uint64_t vertices = 0;          // V
  std::uint64_t moving_vertices = 0;   // Vm: re-transformed when their member moves
  double before_ms = 0.0, after_ms = 0.0;
  double break_even_objects = 0.0;     // the object count from which this V, Vm would pay (inf: never)
  bool pays() const { return after_ms < before_ms; }
};

// Pure arithmetic of eq. 1-3 above.
MergePrediction predict_merge(const ConcatenationCosts& costs, int objects, std::uint64_t vertices,
                              std::uint64_t moving_vertices);

// Eq. 1-3 for each of the scene's merged groups (Scene::groups), members moving as in the
// converter's planner (under an animated or scripted node).
std::vector<MergePrediction> predict_groups(const Scene& scene, const ConcatenationCosts& costs);

// One line for the --report: "predicted before 0.31 ms, after 0.05 ms (12 draws, 480 vertices, 0 moving):
// pays" or "... does not pay (break-even at 35.2 objects): stays unmerged".
std::string describe(const MergePrediction& p);

}  // namespace meter::convert
