// The break-even test of a merged group (meter/convert/merge_break_even.hpp).
#include "meter/convert/merge_break_even.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "programs/program_features.hpp"

namespace meter::convert {

MergePrediction predict_merge(const ConcatenationCosts& c, int objects, std::uint64_t vertices, std::uint64_t moving_vertices) {
  MergePrediction p;
  p.objects = objects;
  p.vertices = vertices;
  p.moving_vertices = moving_vertices;
  const double v = double(vertices), vm = double(moving_vertices);
  p.before_ms = c.draw_ms * objects + c.vertex_ms * v;                  // eq. 1
  p.after_ms = c.draw_ms + c.transform_ms * vm + c.vertex_ms * v;       // eq. 2, k = 0
  p.break_even_objects = c.draw_ms > 0.0 ? 1.0 + c.transform_ms * vm / c.draw_ms  // eq. 3
                                         : std::numeric_limits<double>::infinity();
  return p;
}

std::vector<MergePrediction> predict_groups(const Scene& s, const ConcatenationCosts& costs) {
  const std::vector<char> moving = dynamic_nodes(s);
  std::vector<MergePrediction> out;
  for (const MergedGroup& g : s.groups) {
    std::uint64_t v = 0, vm = 0;
    for (int d : g.draws) {
      const DrawItem& item = s.draws[static_cast<std::size_t>(d)];
      const std::uint32_t n = s.meshes[static_cast<std::size_t>(item.mesh)].primitives[static_cast<std::size_t>(item.primitive)].vertex_count;
      v += n;
      if (moving[static_cast<std::size_t>(item.node)]) vm += n;
    }
    out.push_back(predict_merge(costs, static_cast<int>(g.draws.size()), v, vm));
  }
  return out;
}

std::string describe(const MergePrediction& p) {
  char buf[320];
  std::snprintf(buf, sizeof buf, "predicted before %.4f ms, after %.4f ms (%d draws, %llu vertices, %llu moving; break-even at %.1f objects): %s",
                p.before_ms, p.after_ms, p.objects, static_cast<unsigned long long>(p.vertices),
                static_cast<unsigned long long>(p.moving_vertices), p.break_even_objects,
                p.pays() ? "pays, merged" : "does not pay, stays unmerged");
  return buf;
}

}  // namespace meter::convert
