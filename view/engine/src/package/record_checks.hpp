// The checks of one package record right after the reader decoded it (record_decoder.hpp): sizes
// that must agree, values in their ranges, integrity regions inside their frame; records without
// any have none. Each names the record's path through `in.fail`. References between sections are
// checked once every section is read (scene_references.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "meter/engine/vocabulary.hpp"
#include "record_decoder.hpp"

namespace meter::engine {

// Any record without checks of its own.
template <class T>
void check_record(const RecordDecoder&, const T&) {}

inline void check_record(const RecordDecoder& in, const VertexAttribute& a) {
  if (a.components < 1 || a.components > 4 || a.offset < 0) in.fail("vertex attribute outside the vertex record");
}

// A Flat list: empty, or the same number of triangles as the list it stands for, inside the vertices.
inline void check_flat_list(const RecordDecoder& in, const Primitive& p, const std::vector<std::uint32_t>& flat,
                            std::size_t size, const std::string& at) {
  if (!flat.empty() && flat.size() != size)
    in.fail_at(at, "expected " + std::to_string(size) + " indices (the triangles it draws flat), got " + std::to_string(flat.size()));
  for (auto idx : flat)
    if (idx >= p.vertex_count)
      in.fail_at(at, "index " + std::to_string(idx) + " out of range of the " + std::to_string(p.vertex_count) + " vertices");
}

inline void check_record(const RecordDecoder& in, const Primitive& p) {
  for (const auto& a : p.layout)
    if (a.offset + a.components > p.stride) in.fail("vertex attribute outside the vertex record");
  if (p.stride <= 0 || p.vertices.size() != std::size_t(p.vertex_count) * std::size_t(p.stride))
    in.fail("vertex data size does not match vertex_count * stride");
  for (auto idx : p.indices)
    if (idx >= p.vertex_count) in.fail("index out of range of the vertex data");
  check_flat_list(in, p, p.flat_indices, p.indices.size(), ".flat_indices");
  for (std::size_t k = 0; k < p.lods.size(); ++k) {
    const LodLevel& l = p.lods[k];
    const std::string at = ".lods[" + std::to_string(k) + "]";
    if (l.error < 0.0f) in.fail_at(at + ".error", "negative");
    if (!(l.triangle_fraction > 0.0f && l.triangle_fraction < 1.0f)) in.fail_at(at + ".triangle_fraction", "expected a value in (0, 1)");
    if (l.indices.empty() || l.indices.size() % 3 != 0) in.fail_at(at + ".indices", "expected whole triangles");
    for (auto idx : l.indices)
      if (idx >= p.vertex_count)
        in.fail_at(at + ".indices", "index " + std::to_string(idx) + " out of range of the " + std::to_string(p.vertex_count) + " vertices");
    if (l.flat_indices.empty() != p.flat_indices.empty())
      in.fail_at(at + ".flat_indices", "expected Flat lists on every level of the primitive or on none");
    check_flat_list(in, p, l.flat_indices, l.indices.size(), at + ".flat_indices");
  }
}

inline void check_record(const RecordDecoder& in, const Texture& t) {
  if (t.width <= 0 || t.height <= 0 || t.width > 16384 || t.height > 16384 ||
      t.rgba.size() != std::size_t(t.width) * std::size_t(t.height) * 4)
    in.fail("texture size does not match its pixel data");
}

inline void check_record(const RecordDecoder& in, const Skin& k) {
  if (k.inverse_bind.size() != k.joints.size()) in.fail("skin has a different number of joints and matrices");
}

inline void check_record(const RecordDecoder& in, const AnimSampler& s) {
  const std::size_t per_key = std::size_t(s.components) * (s.interpolation == Interpolation::CubicSpline ? 3 : 1);
  if (s.components < 1 || s.components > 256 || s.input.empty() || s.output.size() != s.input.size() * per_key)
    in.fail("animation sampler output size does not match its keys");
}

inline void check_record(const RecordDecoder& in, const AttributeInfo& a) {
  if (a.location < 0 || a.location > 15 || a.components < 1 || a.components > 4) in.fail("attribute location/components out of range");
}

inline void check_record(const RecordDecoder& in, const UniformInfo& u) {
  if (u.array_size < 1 || u.array_size > 1024) in.fail("uniform array size out of range");
}

inline void check_record(const RecordDecoder& in, const SamplerInfo& s) {
  if (s.unit < 0 || s.unit > 15) in.fail("sampler unit out of range");
  if (s.slot == TextureSlot::ShadowMap ? s.index < 0 || s.index >= kMaxLights : s.index != -1)
    in.fail_at(".index", "a shadow map names a light 0.." + std::to_string(kMaxLights - 1) + ", any other sampler -1");
}

inline void check_record(const RecordDecoder& in, const Environment& e) {
  const EnvironmentProbe& probe = e.probe;
  const bool none = probe.face_size == 0 && probe.levels == 0 && probe.rgb.empty();
  const bool sized = probe.face_size >= 8 && probe.face_size <= 4096 && (probe.face_size & (probe.face_size - 1)) == 0 &&
                     probe.levels == EnvironmentProbe::levels_for(probe.face_size);
  if (!none && !sized)
    in.fail_at(".probe", "face size " + std::to_string(probe.face_size) + " with " + std::to_string(probe.levels) +
                             " levels; expected a power of two in 8..4096 and log2(face size) - 2 levels");
  if (!none && probe.rgb.size() != EnvironmentProbe::byte_size(probe.face_size, probe.levels))
    in.fail_at(".probe", std::to_string(probe.rgb.size()) + " bytes of texels; expected " +
                             std::to_string(EnvironmentProbe::byte_size(probe.face_size, probe.levels)));
  if (e.strength < 0.0f) in.fail_at(".strength", "negative");
}

inline void check_record(const RecordDecoder& in, const NeedleModel& n) {
  for (std::size_t k = 1; k < n.samples.size(); ++k)
    if (n.samples[k].time <= n.samples[k - 1].time) in.fail("needle samples not in increasing time");
}

// Binding indices are checked against the scene config once it is parsed (the config section).
inline void check_record(const RecordDecoder& in, const SafetyRegion& g) {
  const bool telltale_ok = g.telltale.mask.size() == std::size_t(g.rect.width) * std::size_t(g.rect.height) &&
                           g.telltale.looks.size() >= 2;
  if (g.kind == SafetyKind::Telltale && !telltale_ok) in.fail("region " + g.name + ": telltale mask or looks incomplete");
  const NeedleModel& nd = g.needle;
  if (g.kind == SafetyKind::Needle && (nd.samples.size() < 2 || nd.r_min >= nd.r_max || g.bindings.empty()))
    in.fail("region " + g.name + ": needle model incomplete");
  if (g.kind == SafetyKind::Readout && g.bindings.empty()) in.fail("region " + g.name + ": readout without its binding");
}

inline void check_record(const RecordDecoder& in, const IntegrityTable& t) {
  if (!t.regions.empty() && (t.width <= 0 || t.height <= 0)) in.fail("integrity table without a frame size");
  for (const SafetyRegion& g : t.regions) {
    // The far edges in 64 bits: a stored x near INT_MAX plus a width would overflow an int.
    if (g.rect.empty() || g.rect.x < 0 || g.rect.y < 0 || std::int64_t{g.rect.x} + g.rect.width > t.width ||
        std::int64_t{g.rect.y} + g.rect.height > t.height)
      in.fail("region " + g.name + ": rect outside the integrity table's frame");
  }
}

}  // namespace meter::engine
