// meter-calibrate's measuring: the cost of every draw unit at every level it can take and of each
// global rung, on this machine's GL backend, and the PSNR each loses against full quality
// (cost_samples.hpp says what is drawn and how it is fitted). docs/uniform-frame-rate.md,
// "Calibration".
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "meter/calibrate/cost_samples.hpp"
#include "meter/engine/vocabulary.hpp"
#include "meter/platform/backend.hpp"

namespace meter::calibrate {

struct CalibrationOptions {
  int frames = 5;                                // timed frames per point (median), after one warm-up frame
  std::vector<float> node_scales{1.0f, 0.75f, 0.5f};  // [0] = 1; at least two distinct, in (0, 1]
  int msaa = 4;                                  // the renderer's own samples (rung 0)
  int width = 0, height = 0;                     // 0 = the scene config's size
  // The cheaper rungs tried besides rung 0 ({msaa, 1}); a rung with more samples than the driver
  // draws, or equal to rung 0, is left out.
  std::vector<engine::governor::GlobalLevel> rungs{{2, 1.0f}, {1, 1.0f}, {4, 0.75f}, {1, 0.75f}, {4, 0.5f}, {1, 0.5f}};
};

// Throws std::invalid_argument for options out of range, and the renderer's errors (a program
// that does not compile on this backend) as they are. `progress` (may be null) gets one line per unit.
CostMeasurements measure_costs(platform::GpuBackend& backend, const engine::Scene& scene, const CalibrationOptions& options,
                               std::ostream* progress);

}  // namespace meter::calibrate
