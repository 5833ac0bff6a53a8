// meter-calibrate PACKAGE [--out FILE] [--backend egl|osmesa] [--frames N] [--size WxH] [--msaa N]
// [--samples CSV]:
// measures the package's costs on this machine (calibration.hpp) and writes the meter-costs/1
// file (default PACKAGE.costs.json beside the package), which meter-view --target-ms reads.
#pragma once

#include <ostream>
#include <string>

namespace meter::calibrate {

struct CalibrateToolOptions {
  std::string package;
  std::string out;               // empty = <package>.costs.json
  std::string backend = "egl";
  int frames = 5;
  std::string size;              // WxH; empty = the scene config's size
  int msaa = 4;
  std::string samples;           // non-empty: every timed point as CSV (kind,unit,level,scale,pixels,ms)
};

// 0 on success; 1 with "meter-calibrate: error: ..." on `err` for any failure.
int run_calibrate_tool(const CalibrateToolOptions& options, std::ostream& out, std::ostream& err);

}  // namespace meter::calibrate
