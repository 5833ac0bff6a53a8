// The runtime's view of the scene model: the bridge vocabulary (scene, config and program types
// shared with the converter), used in the engine under its own names.
#pragma once

#include "meter/bridge/program.hpp"
#include "meter/bridge/scene.hpp"
#include "meter/bridge/scene_config.hpp"

namespace meter::engine {
using namespace meter::bridge;
}  // namespace meter::engine
