// The DENSO paper's concatenation costs (sec. 5.2, eq. 1-3) on this machine: oh (one draw more),
// m (one vertex more, drawn) and s (one merged vertex transformed on the CPU), for the converter's
// break-even test (meter/convert/merge_break_even.hpp), written in the cost file's "concatenation"
// block.
//
// Measured as the paper did: one model of `vertices` vertices split into N small objects (each a
// few pixels, so fill costs nothing), children of one node that moves every frame, drawn unmerged
// (N draws), merged with every member moving (one draw plus the CPU transforms) and merged with
// nothing moving (one draw). Full frames, wall time of Renderer::render (it ends in glFinish).
#pragma once

#include <ostream>
#include <vector>

#include "meter/engine/governor/cost_file.hpp"
#include "meter/engine/vocabulary.hpp"
#include "meter/platform/backend.hpp"

namespace meter::calibrate {

// The split model: `objects` ribbons of total_vertices / objects vertices (an even count >= 4)
// on a grid, children of "Board", which the animation "Wobble" turns about Z; one Gouraud program
// with vertex alpha (the same program draws merged and unmerged), all of them in one merged group.
engine::Scene split_model(int objects, int total_vertices);

struct MergeSample {
  int objects = 0, vertices = 0;
  double unmerged_ms = 0.0;        // N draws, the board moving
  double merged_moving_ms = 0.0;   // one draw, every member re-transformed each frame
  double merged_static_ms = 0.0;   // one draw, nothing moving
};

// Median frame times of split_model(objects, vertices), the three renderers taking turns frame by
// frame so that load from other processes hits them alike.
MergeSample measure_merge(platform::GpuBackend& backend, int objects, int vertices, int frames);

// The points measure_merge_costs measures: N in {10, 100, 400} at 4,000 vertices (oh) and 2,000 /
// 8,000 vertices at N = 100 (m).
std::vector<MergeSample> merge_sample_points(platform::GpuBackend& backend, int frames, std::ostream* progress);

// Pure: oh = the slope of the unmerged time over N among the samples of the most common vertex
// count; m = the slope over V among the samples of the most common N; s = the mean of (merged
// moving - merged static) / V. A slope or mean below 0 (timing noise) is 0. Throws
// std::invalid_argument when there are not two distinct N and two distinct V to fit.
engine::governor::ConcatenationCosts fit_merge_costs(const std::vector<MergeSample>& samples);

}  // namespace meter::calibrate
