// The name a linked program's binary is kept under across runs: one key per driver and program.
// A binary is the driver's own compiled form of the program, so it may only be handed back to the
// driver that made it (the same vendor, renderer and version strings: a Mesa update changes the
// version, another GPU the renderer) and only for the very sources it was linked from.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace meter::engine {

// What the context says it is (GL_VENDOR, GL_RENDERER, GL_VERSION).
struct DriverIdentity {
  std::string vendor, renderer, version;
};

// BLAKE2b-256 (libsodium) over the key's version, the three driver strings and the two sources, each
// preceded by its length, so no two different inputs run together into the same bytes.
using ProgramBinaryKey = std::array<std::uint8_t, 32>;

ProgramBinaryKey program_binary_key(const DriverIdentity& driver, std::string_view vertex_source,
                                    std::string_view fragment_source);

// The key as a file name: 64 lower-case hex digits and ".glbin".
std::string program_binary_file_name(const ProgramBinaryKey& key);

}  // namespace meter::engine
