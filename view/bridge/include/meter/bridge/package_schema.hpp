// The schema of a package section: its field lists written out as text (field names and the kinds
// of value, nested records in braces, lists in brackets) and hashed. The writer stores each chunk's
// schema; the reader compares it with the schema its own field lists give, so a package written
// before a field was added, removed, renamed or moved is refused naming the section (and how to
// reconvert it) instead of being misread. Changing a field list needs no version bump.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <type_traits>

#include "meter/bridge/package_fields.hpp"
#include "meter/bridge/package_format.hpp"

namespace meter::bridge {

class SchemaText {
 public:
  std::string out;

  template <class T>
  void record(const T& r) {
    out += '{';
    fields(r, [&](const auto& field, const auto& member) {
      out += field_name(field);
      out += ':';
      visit_value(*this, member);
      out += ';';
    });
    out += '}';
  }
  template <class L>
  void list(const L&) {
    const typename L::value_type element{};
    out += '[';
    visit_value(*this, element);
    out += ']';
  }
  template <class A>
  void array(const A& a) {
    out += std::to_string(a.size()) + 'x';
    visit_value(*this, a[0]);
  }
  void text(const std::string&) { out += "str"; }
  template <class T>
  void floats(const T&) {
    int n = 0;
    T v{};
    for_each_float(v, [&](float) { ++n; });
    out += "f32x" + std::to_string(n);
  }
  template <class T>
  void scalar(const T&) {
    if constexpr (std::is_same_v<T, bool>) out += "bool";
    else if constexpr (std::is_enum_v<T>) out += "enum";
    else if constexpr (std::is_floating_point_v<T>) out += "f" + std::to_string(8 * sizeof(T));
    else out += (std::is_signed_v<T> ? "i" : "u") + std::to_string(8 * sizeof(T));
  }
};

// The schema hash of a section whose value has the type of `v` (its contents do not matter).
template <class T>
std::uint64_t section_schema(const T&) {
  static const std::uint64_t hash = [] {
    SchemaText s;
    const T probe{};
    visit_value(s, probe);
    return package_checksum({reinterpret_cast<const std::uint8_t*>(s.out.data()), s.out.size()});
  }();
  return hash;
}

}  // namespace meter::bridge
