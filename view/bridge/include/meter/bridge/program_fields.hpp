// The field lists of a generated program's records (meter/bridge/program.hpp), and what every
// field list shares: `fields(record, visit)` calls `visit(name, member)` for each stored member in
// order, one METER_PACKAGE_RECORD line per record (package_fields.hpp adds the scene's records). The program cache's key and the
// scene package both describe a program by these lists; its material terms are
// material_feature_fields.hpp's.
#pragma once

#include <array>
#include <concepts>
#include <cstddef>
#include <string>
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

// METER_PACKAGE_RECORD(Type, member...) is the field list of `Type`: it defines
// `fields(record, visit)`, which calls `visit("member", record.member)` for each member in the
// order given, on a const record (writer, dump, cache key) or not (reader).
#define METER_PACKAGE_RECORD(Type, ...)                         \
  template <record_of<Type> R, class V>                         \
  void fields(R& record, V&& visit) {                           \
    METER_PACKAGE_FOR_EACH(METER_PACKAGE_FIELD, __VA_ARGS__)    \
  }
#define METER_PACKAGE_FIELD(member) visit(#member, record.member);
// METER_PACKAGE_FOR_EACH(m, a, b, ...) = m(a) m(b) ... (up to 256 arguments): each step expands
// to the next one only on a later rescan, which METER_PACKAGE_EXPAND forces.
#define METER_PACKAGE_FOR_EACH(m, ...) __VA_OPT__(METER_PACKAGE_EXPAND(METER_PACKAGE_FOR_EACH_STEP(m, __VA_ARGS__)))
#define METER_PACKAGE_FOR_EACH_STEP(m, first, ...) m(first) __VA_OPT__(METER_PACKAGE_FOR_EACH_AGAIN METER_PACKAGE_PARENS(m, __VA_ARGS__))
#define METER_PACKAGE_FOR_EACH_AGAIN() METER_PACKAGE_FOR_EACH_STEP
#define METER_PACKAGE_PARENS ()
#define METER_PACKAGE_EXPAND(...) METER_PACKAGE_EXPAND4(METER_PACKAGE_EXPAND4(METER_PACKAGE_EXPAND4(METER_PACKAGE_EXPAND4(__VA_ARGS__))))
#define METER_PACKAGE_EXPAND4(...) METER_PACKAGE_EXPAND3(METER_PACKAGE_EXPAND3(METER_PACKAGE_EXPAND3(METER_PACKAGE_EXPAND3(__VA_ARGS__))))
#define METER_PACKAGE_EXPAND3(...) METER_PACKAGE_EXPAND2(METER_PACKAGE_EXPAND2(METER_PACKAGE_EXPAND2(METER_PACKAGE_EXPAND2(__VA_ARGS__))))
#define METER_PACKAGE_EXPAND2(...) METER_PACKAGE_EXPAND1(METER_PACKAGE_EXPAND1(METER_PACKAGE_EXPAND1(METER_PACKAGE_EXPAND1(__VA_ARGS__))))
#define METER_PACKAGE_EXPAND1(...) __VA_ARGS__

METER_PACKAGE_RECORD(AttributeInfo, name, semantic, index, location, components)

METER_PACKAGE_RECORD(UniformInfo, name, glsl_type, semantic, index, array_size)

METER_PACKAGE_RECORD(SamplerInfo, name, slot, unit, index)

// Everything a generated program is (the program cache's key describes a program by this list).
METER_PACKAGE_RECORD(Program, vertex_source, fragment_source, attributes, uniforms, samplers, features,
                     blend, cull_back_faces, optimized, uber)

METER_PACKAGE_RECORD(OptimizeReport, source_bytes_before, source_bytes_after, spirv_instructions_before,
                     spirv_instructions_after, uniforms_before, uniforms_after, varyings_before,
                     varyings_after, samplers_before, samplers_after, folded)

// The name of a field, whichever list it comes from.
inline const char* field_name(const char* name) { return name; }
inline const char* field_name(const FeatureField& f) { return f.name; }

// Whether `T` is a record with a field list (visited member by member) rather than a value.
template <class T>
concept package_record = requires(T& t) { fields(t, [](const auto&, auto&) {}); };

// Whether `T` is a run of floats (a glm vector, quaternion or matrix: package_fields.hpp).
template <class T> inline constexpr bool is_float_run = false;

// The one dispatch on the kinds of stored value, for every codec of the field lists (package
// writer and reader, record dump, program cache key): calls codec.record(v) for a record,
// codec.list(v) for a std::vector, codec.array(v) for a std::array, codec.text(v) for a string,
// codec.floats(v) for a run of floats, codec.scalar(v) for a number, flag or enum.
template <class Codec, class T>
void visit_value(Codec& codec, T& v) {
  using U = std::remove_const_t<T>;
  if constexpr (package_record<U>) codec.record(v);
  else if constexpr (is_vector<U>) codec.list(v);
  else if constexpr (is_array<U>) codec.array(v);
  else if constexpr (std::is_same_v<U, std::string>) codec.text(v);
  else if constexpr (is_float_run<U>) codec.floats(v);
  else codec.scalar(v);
}

}  // namespace meter::bridge
