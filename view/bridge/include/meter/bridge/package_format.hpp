// The binary scene package (.msp) format that the data converter writes (meter/convert/
// package_writer.hpp) and the runtime reads (meter/engine/package_reader.hpp). Both sides encode
// from this one definition.
//
// Layout (little-endian):
//   bytes 0..7   magic "METERSCN"
//   u32          format version (kPackageVersion)
//   u32          reserved (0)
//   u64          payload size in bytes
//   u64          FNV-1a 64 of the payload (package_checksum; detects truncation and corruption)
//   payload      scene sections in the fixed order below
//
// Field encodings: integers and floats as their little-endian bytes (i32, u32, f32, u64), bool as
// one byte 0 / 1, an enum as the i32 of its value, a string as u32 length + bytes, an array of
// plain values as u32 count + the values, vec3 / vec4 as 3 / 4 f32, a quaternion as x, y, z, w, a
// mat3 / mat4 as its columns. Every list of records is prefixed by its u32 count.
//
// Section order: source name; nodes; roots; meshes (primitives with layout, vertices, indices,
// bounds); materials; textures; cameras; lights; skins; animations (samplers, channels); programs
// (sources, attributes, uniforms, samplers, features, pipeline state, optimizer report); draws;
// mesh concatenation groups; the world environment (reflection probe: i32 face size, i32 levels,
// the sRGB texels as a byte array; strength, ambient cube); the
// scene config's JSON text; the integrity table (frame size, safety regions, integrity.hpp); the
// draw levels (draw_levels.hpp: each primitive's LOD levels in mesh / primitive order, each an f32
// error, f32 triangle fraction and u32 index array; then the DrawLevels of every draw, or none:
// bool safety, i32 lods, the shading levels as i32 model, i32 program, vec3 specular colour, f32
// shininess, f32 base scale).
//
// A package with another version is refused with a message naming both versions: the format has no
// optional fields, so "mostly compatible" is not a state it can be in.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace meter::bridge {

// 2: mesh concatenation groups after the draws.
// 3: the world environment (texture index, strength, ambient cube) after the groups.
// 4: the integrity table (safety regions and their signatures) after the scene config text.
// 5: the draw levels (cheaper LODs and shadings, draw_levels.hpp) after the integrity table.
// 6: shadows: a light's cast_shadow flag, a program's shadow-light mask, a sampler's light index.
// 7: the environment's reflection probe (face size, levels, texels) where its texture index was.
inline constexpr std::uint32_t kPackageVersion = 7;
inline constexpr char kPackageMagic[8] = {'M', 'E', 'T', 'E', 'R', 'S', 'C', 'N'};
// magic + version + reserved + payload size + payload checksum
inline constexpr std::size_t kPackageHeaderSize = 8 + 4 + 4 + 8 + 8;

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
