// view_bench section 5: the integrity monitor's cost per frame (integrity_bench.cpp).
#pragma once

#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"

namespace meter::bench {

// `cluster` with its safety regions (as meter-convert writes them into the package).
void integrity_cost(platform::GpuBackend& backend, const engine::Scene& cluster);

}  // namespace meter::bench
