// The package reader: a binary scene package (.msp) written by meter-convert, checked and loaded
// into the Scene the renderer draws (format: meter/bridge/package_format.hpp).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "meter/bridge/package_format.hpp"
#include "meter/engine/scene.hpp"

namespace meter::engine {

// Throws SceneError naming `origin`, the offset and what was being read. Cross-references are
// checked too, so a package that passed the checksum never indexes out of range at runtime.
Scene deserialize_scene(std::span<const std::uint8_t> bytes, const std::string& origin = "package");
Scene read_package(const std::string& path);

}  // namespace meter::engine
