// The binary scene package (.msp) that the data converter writes (meter/convert/package_writer.hpp)
// and the runtime reads (meter/engine/package_reader.hpp): a header, then tagged, length-prefixed
// chunks, one per section of the scene. What each chunk holds is the field list of its records
// (meter/bridge/package_fields.hpp); how each kind of value is encoded is defined here. The full
// description is docs/package-format.md.
//
// Header (little-endian, kPackageHeaderSize bytes):
//   bytes 0..7   magic "METERSCN"
//   u32          framing version (kPackageVersion)
//   u32          reserved (0)
//   u64          payload size in bytes
//   u64          FNV-1a 64 of the payload (package_checksum; detects truncation and corruption)
// Payload: chunks, each
//   4 bytes      tag, four ASCII characters (SceneSection::tag: "NODE", "MESH", ...)
//   u64          schema: the hash of the section's field lists (package_schema.hpp)
//   u64          length of the chunk's body in bytes
//   body         the section's value
// A reader skips a chunk whose tag it does not know (and notes it for the caller: tag, size,
// offset); a section marked required that has no chunk is an error naming it; a chunk longer than
// what follows it, or a body not used up exactly by its section, is an error naming the chunk and
// its offset; a chunk whose schema is not the reader's (written by a converter with other field
// lists) is refused with the command that reconverts the package, never misread. New content
// comes as a new chunk, so an older reader still reads a newer package's sections it knows.
//
// Value encodings, by type, for every field list: integers as their little-endian bytes (int i32,
// unsigned u32, std::size_t u64), bool as one byte 0 / 1, an enum as the i32 of its value (at most
// enum_last), float f32 and double f64 (finite only), a string as u32 length + bytes, a vector of
// numbers as u32 count + the values, any other vector as u32 count + each element, a std::array as
// its elements (no count), vec3 / vec4 as 3 / 4 f32, a quaternion as x, y, z, w, a mat3 / mat4 as
// its columns, a record as its fields in list order.
//
// Packages of format 7 and before (a fixed-order layout with the same header) are refused with the
// command that reconverts them: their layout cannot be told apart field by field.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace meter::bridge {

// 2..7: the fixed-order layout (mesh concatenation groups, world environment, integrity table,
//       draw levels, shadows, reflection probe), each bump making every older package unreadable.
// 8:    tagged, length-prefixed chunks driven by the records' field lists.
inline constexpr std::uint32_t kPackageVersion = 8;
inline constexpr char kPackageMagic[8] = {'M', 'E', 'T', 'E', 'R', 'S', 'C', 'N'};
// magic + version + reserved + payload size + payload checksum
inline constexpr std::size_t kPackageHeaderSize = 8 + 4 + 4 + 8 + 8;
// tag + schema + body length
inline constexpr std::size_t kChunkHeaderSize = 4 + 8 + 8;

// FNV-1a 64 of the payload, stored in the header.
inline std::uint64_t package_checksum(std::span<const std::uint8_t> payload) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::uint8_t b : payload) {
    h ^= b;
    h *= 0x100000001b3ull;
  }
  return h;
}

}  // namespace meter::bridge
