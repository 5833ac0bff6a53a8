// The package writer: a converted Scene as the binary scene package (.msp) meter-view loads
// (format: meter/bridge/package_format.hpp; reader: meter/engine/package_reader.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "meter/convert/vocabulary.hpp"

namespace meter::convert {

std::vector<std::uint8_t> serialize_scene(const Scene& scene);
// Writes through a temporary file and a rename, so a viewer never sees a half-written package.
// Throws SceneError naming the path.
void write_package(const Scene& scene, const std::string& path);

}  // namespace meter::convert
