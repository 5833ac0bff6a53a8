// The `meter-costs/1` file (JSON) that meter-calibrate writes beside a package and meter-view
// reads: parse and write as pure functions on text, and matching against the renderer's draw
// units so a file calibrated for another package or an older conversion is rejected by name.
//
//   {
//     "format": "meter-costs/1",
//     "backend": "egl",                      (optional, informative)
//     "package": "cluster.meterpkg",         (optional, informative)
//     "overhead": {"a_ms_per_pixel": 1e-7, "b_ms": 0.4},
//     "globals": [                            [0] = full quality, then cheaper rungs
//       {"msaa": 4, "scale": 1.0, "pixel_factor": 1.0, "fixed_ms": 0.0},
//       {"msaa": 1, "scale": 0.5, "pixel_factor": 0.22, "fixed_ms": 0.3, "psnr_db": 31.5}
//     ],
//     "units": [
//       {"name": "needle", "levels": [
//         {"shading": "pbr", "lod": 0, "a_ms_per_pixel": 2e-5, "b_ms": 0.1},
//         {"shading": "gouraud", "lod": 0, "a_ms_per_pixel": 1e-5, "b_ms": 0.1, "psnr_db": 42.0}
//       ]}
//     ],
//     "concatenation": {"draw_ms": 0.0016, "vertex_ms": 0.0004, "transform_ms": 0.000012}   (optional)
//   }
//
// The concatenation block holds the DENSO paper's costs (eq. 1-3) that the converter's break-even
// test reads (meter-convert --costs): the overhead of one draw, the main (draw) cost of a vertex
// and the CPU cost of transforming a merged member's vertex; each >= 0, in ms of frame time.
//
// Every number is finite; a_ms_per_pixel >= 0; pixel_factor > 0; msaa >= 1; scale in (0, 1];
// psnr_db > 0 (identical frames: write a large value such as 100). Shading names are
// bridge::to_string's ("unlit", "flat", "gouraud", "blinn-phong", "pbr"). Unknown keys, duplicate
// units, levels or rungs are errors. Errors are std::invalid_argument "ORIGIN: JSON.PATH: what was
// expected".
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "meter/engine/governor/cost_model.hpp"

namespace meter::engine::governor {

inline constexpr const char* kCostFormat = "meter-costs/1";

struct UnitCostEntry {
  std::string name;
  std::vector<LevelCost> levels;  // in file order
  bool operator==(const UnitCostEntry&) const = default;
};

// The paper's oh, m and s (eq. 1-3), measured by meter-calibrate on synthetic split models.
struct ConcatenationCosts {
  double draw_ms = 0.0;       // oh: one draw call more
  double vertex_ms = 0.0;     // m: one vertex more, drawn
  double transform_ms = 0.0;  // s: one merged vertex transformed on the CPU
  bool operator==(const ConcatenationCosts&) const = default;
};

// A cost file as written: units keyed by name, levels by (shading name, lod index).
struct CostFile {
  std::string backend;
  std::string package;
  LinearCost overhead;
  std::vector<GlobalCost> globals;
  std::vector<UnitCostEntry> units;
  std::optional<ConcatenationCosts> concatenation{};
  bool operator==(const CostFile&) const = default;
};

CostFile parse_costs(const std::string& text, const std::string& origin);
std::string write_costs(const CostFile& file);

// Matches the file to the renderer's draw units: every ladder unit must have an entry of that
// name with exactly the levels its ladder can take (each shading x each lod), and the file must
// have nothing else. Throws std::invalid_argument "ORIGIN: stale cost file: ..." listing the
// missing and the extra units and levels (at most a few of each, then a count).
CostModel bind_costs(const CostFile& file, std::span<const UnitLadder> ladders, const std::string& origin);

}  // namespace meter::engine::governor
