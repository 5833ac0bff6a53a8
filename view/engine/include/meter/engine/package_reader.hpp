// The package reader: a binary scene package (.msp) written by meter-convert, checked and loaded
// into the Scene the renderer draws (format: meter/bridge/package_format.hpp).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "meter/bridge/package_format.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

// What the reader passed over and the caller may log: each chunk it does not know (a section of a
// newer converter), with its tag, size and offset.
using PackageNotes = std::vector<std::string>;

// Throws SceneError naming `origin`, the offset, the chunk and the field being read; a package of
// an older format is refused with the command that reconverts it. Cross-references are checked
// too, so a package that passed the checksum never indexes out of range at runtime. Notes go to
// `notes`, or to stderr when the caller passes none (never silently dropped).
Scene deserialize_scene(std::span<const std::uint8_t> bytes, const std::string& origin = "package",
                        PackageNotes* notes = nullptr);
Scene read_package(const std::string& path, PackageNotes* notes = nullptr);

}  // namespace meter::engine
