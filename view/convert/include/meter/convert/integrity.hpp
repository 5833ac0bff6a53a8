// Display integrity at conversion: the safety regions of a converted scene and their signatures,
// measured from the runtime engine's own offscreen renders at the scene config's size
// (meter/bridge/integrity.hpp; docs/integrity.md):
//   telltales  every visibility / emissive / colour binding, grouped per signal: the lamp pixels
//              (where the lit render differs from the unlit ones) and the mean colour of each look;
//   needles    every animation binding whose animation rotates a node: pivot, the annulus where
//              only that needle moves, the needle's colour, and the screen angle at sampled times;
//   readouts   every text binding: the box its texts can ink, its anchor and format.
// A binding whose region cannot be measured (off screen, covered, a needle whose colour its
// dial shares) is left out and named in IntegrityMeasurement::skipped.
#pragma once

#include <string>
#include <vector>

#include "meter/bridge/integrity.hpp"
#include "meter/convert/vocabulary.hpp"
#include "meter/platform/backend.hpp"

namespace meter::convert {

struct IntegrityOptions {
  int msaa = 4;          // the renders' sample count (the view's default)
  int needle_samples = 25;  // evenly spaced animation times per needle (both ends included)
};

struct IntegrityMeasurement {
  bridge::IntegrityTable table;
  std::vector<std::string> skipped;  // "<binding>: why it is not monitored"
  // Needles: the largest difference, over the midpoints between samples, between the angle read
  // from a render and the one the table interpolates (degrees).
  double needle_interpolation_deg = 0.0;
};

// Renders `scene` on `backend` (throws platform / engine errors naming what failed to draw).
IntegrityMeasurement measure_integrity(const Scene& scene, platform::GpuBackend& backend,
                                       const IntegrityOptions& options = {});

// The `meter-convert --report` block: one line per region (kind, name, signal, rect, model).
std::string integrity_report(const IntegrityMeasurement& m);

}  // namespace meter::convert
