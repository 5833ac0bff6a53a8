// The data converter's view of the scene model: the bridge vocabulary (scene, config and program
// types shared with the runtime), used in meter::convert under its own names.
#pragma once

#include "meter/bridge/program.hpp"
#include "meter/bridge/scene.hpp"
#include "meter/bridge/scene_config.hpp"

namespace meter::convert {
using namespace meter::bridge;
}  // namespace meter::convert
