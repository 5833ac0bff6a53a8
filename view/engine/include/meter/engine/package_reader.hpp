// The binary scene package (.msp) that meter-convert writes and meter-view loads.
//
// Layout (little-endian):
//   bytes 0..7   magic "METERSCN"
//   u32          format version (kPackageVersion)
//   u32          reserved (0)
//   u64          payload size in bytes
//   u64          FNV-1a 64 of the payload (detects truncation and corruption)
//   payload      scene sections in a fixed order (see package.cpp), each count-prefixed
// A package with another version is refused with a message naming both versions: the format has no
// optional fields, so "mostly compatible" is not a state it can be in.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "meter/engine/scene.hpp"

namespace meter::engine {

// 2: mesh concatenation groups (issue #10) after the draws.
// 3: the world environment (issue #9: texture index, strength, ambient cube) after the groups.
inline constexpr std::uint32_t kPackageVersion = 3;
inline constexpr char kPackageMagic[8] = {'M', 'E', 'T', 'E', 'R', 'S', 'C', 'N'};

std::vector<std::uint8_t> serialize_scene(const Scene& scene);
// Throws SceneError naming `origin`, the offset and what was being read.
Scene deserialize_scene(std::span<const std::uint8_t> bytes, const std::string& origin = "package");

void write_package(const Scene& scene, const std::string& path);
Scene read_package(const std::string& path);

}  // namespace meter::engine
