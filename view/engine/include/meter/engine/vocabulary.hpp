// The bridge's vocabulary under meter::engine's names: the scene model (meter/bridge/scene.hpp, the
// one scene.hpp), the scene config's and the programs' types, shared with the converter. The runtime
// defines no scene model of its own; this header only makes the shared one its own words.
#pragma once

#include "meter/bridge/program.hpp"
#include "meter/bridge/scene.hpp"
#include "meter/bridge/scene_config.hpp"

namespace meter::engine {
using namespace meter::bridge;
}  // namespace meter::engine
