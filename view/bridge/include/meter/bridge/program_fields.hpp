// The field lists of a generated program's records (meter/bridge/program.hpp), and what every
// field list shares: `fields(record, visit)` calls `visit(name, member)` for each stored member in
// order (see package_fields.hpp, which adds the scene's records). The program cache's key and the
// scene package both describe a program by these lists; its material terms are
// material_feature_fields.hpp's.
#pragma once

#include <array>
#include <concepts>
#include <cstddef>
#include <type_traits>
#include <vector>

#include "meter/bridge/material_feature_fields.hpp"
#include "meter/bridge/program.hpp"

namespace meter::bridge {

// `R` is the record type `T`, const or not.
template <class R, class T>
concept record_of = std::same_as<std::remove_const_t<R>, T>;

// The largest value of each stored enum (the reader refuses larger ones).
template <class E> inline constexpr int enum_last = -1;
template <> inline constexpr int enum_last<ShadingModel> = int(ShadingModel::PbrMetallicRoughness);
template <> inline constexpr int enum_last<AlphaMode> = int(AlphaMode::Blend);
template <> inline constexpr int enum_last<Precision> = int(Precision::Highp);
template <> inline constexpr int enum_last<TextureSlot> = int(TextureSlot::ShadowMap);
template <> inline constexpr int enum_last<UniformSemantic> = int(UniformSemantic::LightShadowMatrix);
template <> inline constexpr int enum_last<AttributeSemantic> = int(AttributeSemantic::VertexAlpha);

// The kinds of stored lists: a std::vector (u32 count, then the elements) and a std::array (the
// elements only).
template <class T> inline constexpr bool is_vector = false;
template <class T> inline constexpr bool is_vector<std::vector<T>> = true;
template <class T> inline constexpr bool is_array = false;
template <class T, std::size_t N> inline constexpr bool is_array<std::array<T, N>> = true;

template <record_of<AttributeInfo> R, class V>
void fields(R& a, V&& v) {
  v("name", a.name), v("semantic", a.semantic), v("index", a.index), v("location", a.location);
  v("components", a.components);
}

template <record_of<UniformInfo> R, class V>
void fields(R& u, V&& v) {
  v("name", u.name), v("glsl_type", u.glsl_type), v("semantic", u.semantic), v("index", u.index);
  v("array_size", u.array_size);
}

template <record_of<SamplerInfo> R, class V>
void fields(R& s, V&& v) {
  v("name", s.name), v("slot", s.slot), v("unit", s.unit), v("index", s.index);
}

// Everything a generated program is (the program cache's key describes a program by this list).
template <record_of<Program> R, class V>
void fields(R& p, V&& v) {
  v("vertex_source", p.vertex_source), v("fragment_source", p.fragment_source);
  v("attributes", p.attributes), v("uniforms", p.uniforms), v("samplers", p.samplers);
  v("features", p.features), v("blend", p.blend), v("cull_back_faces", p.cull_back_faces);
  v("optimized", p.optimized), v("uber", p.uber);
}

template <record_of<OptimizeReport> R, class V>
void fields(R& o, V&& v) {
  v("source_bytes_before", o.source_bytes_before), v("source_bytes_after", o.source_bytes_after);
  v("spirv_instructions_before", o.spirv_instructions_before);
  v("spirv_instructions_after", o.spirv_instructions_after);
  v("uniforms_before", o.uniforms_before), v("uniforms_after", o.uniforms_after);
  v("varyings_before", o.varyings_before), v("varyings_after", o.varyings_after);
  v("samplers_before", o.samplers_before), v("samplers_after", o.samplers_after), v("folded", o.folded);
}

// The name of a field, whichever list it comes from.
inline const char* field_name(const char* name) { return name; }
inline const char* field_name(const FeatureField& f) { return f.name; }

// Whether `T` is a record with a field list (visited member by member) rather than a value.
template <class T>
concept package_record = requires(T& t) { fields(t, [](const auto&, auto&) {}); };

}  // namespace meter::bridge
