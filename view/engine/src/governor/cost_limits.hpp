// The ranges a cost file's numbers must lie in (shared by the parser and the binding of
// hand-built or calibrated models), and the shading names. Internal to the governor.
//
// The bounds are far beyond any real machine (one second per pixel, a thousand-fold rung) and
// keep every prediction finite: units x kMaxMsPerPixel x kMaxPixels x kMaxPixelFactor stays far
// below the largest double.
#pragma once

#include <optional>
#include <string>

#include "meter/bridge/program.hpp"

namespace meter::engine::governor::limits {

inline constexpr double kMaxMsPerPixel = 1e3;
inline constexpr double kMaxFixedMs = 1e6;
inline constexpr double kMaxPixelFactor = 1e3;
inline constexpr double kMaxPsnrDb = 1e3;
inline constexpr int kMaxMsaa = 64;
inline constexpr int kMaxLod = 1024;

std::optional<bridge::ShadingModel> shading_from_name(const std::string& name);
std::string shading_names();  // "\"unlit\", \"flat\", ..." for error messages

}  // namespace meter::engine::governor::limits

namespace meter::engine::governor {
struct CostModel;
}

namespace meter::engine::governor::limits {

// Checks a model built in code or bound from a file: at least one rung, every unit's level table
// dense (shadings x lods entries), a safety unit with one level, every number finite and inside
// the ranges above. Throws std::invalid_argument "ORIGIN: unit 'NAME' level (shading, lod): ...".
void check_model(const CostModel& model, const std::string& origin);

}  // namespace meter::engine::governor::limits
