// One kept program binary as a file: what glGetProgramBinary gave, under a header that says which
// key it was stored for and a digest of the binary, so a file that is truncated, damaged, or stored
// for another driver or other sources is recognised before any byte of it reaches the driver.
//
//   "METERPGB" | u32 file version (1) | u32 GL binary format | key[32] | BLAKE2b-256 of the binary [32]
//   | u64 binary length | binary                                  (integers little-endian)
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "meter/engine/gl/program_binary_key.hpp"

namespace meter::engine {

struct ProgramBinary {
  std::uint32_t format = 0;  // the driver's binary format (glGetProgramBinary's binaryFormat)
  std::vector<std::uint8_t> bytes;
};

std::vector<std::uint8_t> encode_program_binary(const ProgramBinaryKey& key, const ProgramBinary& binary);

// The binary a file holds for `key`, or why it holds none for it ("truncated: 40 bytes, the
// header needs 88", "stored for another driver or other sources", "the binary does not match its
// digest", ...): `problem` is empty exactly when `binary` is set.
struct DecodedProgramBinary {
  std::optional<ProgramBinary> binary;
  std::string problem;
};
DecodedProgramBinary decode_program_binary(std::span<const std::uint8_t> file, const ProgramBinaryKey& key);

}  // namespace meter::engine
