// The package's value encodings (meter/bridge/package_format.hpp), writing any record by its field
// list (meter/bridge/package_fields.hpp; the kinds of value: bridge::visit_value).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "meter/bridge/package_fields.hpp"
#include "meter/convert/vocabulary.hpp"

namespace meter::convert {

class RecordEncoder {
 public:
  std::vector<std::uint8_t> bytes;

  template <class T>
  void value(const T& v) {
    bridge::visit_value(*this, v);
  }

  // The kinds of value, as bridge::visit_value names them.
  template <class T>
  void record(const T& r) {
    bridge::fields(r, [&](const auto&, const auto& member) { value(member); });
  }
  template <class T>
  void list(const std::vector<T>& v) {
    count(v.size());
    if constexpr (std::is_arithmetic_v<T>) raw(v.data(), v.size() * sizeof(T));
    else for (const auto& x : v) value(x);
  }
  template <class T, std::size_t N>
  void array(const std::array<T, N>& a) {
    for (const auto& x : a) value(x);
  }
  void text(const std::string& s) {
    count(s.size());
    raw(s.data(), s.size());
  }
  template <class T>
  void floats(const T& v) {
    bridge::for_each_float(v, [&](float f) { raw(&f, 4); });
  }
  template <class T>
  void scalar(const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
      const std::uint8_t b = v ? 1 : 0;
      raw(&b, 1);
    } else if constexpr (std::is_enum_v<T>) {
      static_assert(bridge::enum_last<T> >= 0, "a stored enum needs its bridge::enum_last");
      const auto i = static_cast<std::int32_t>(v);
      raw(&i, 4);
    } else if constexpr (std::is_same_v<T, std::size_t>) {
      const std::uint64_t u = v;
      raw(&u, 8);
    } else {
      static_assert(std::is_same_v<T, int> || std::is_same_v<T, unsigned> || std::is_same_v<T, float> ||
                    std::is_same_v<T, double>, "no package encoding for this type");
      raw(&v, sizeof v);
    }
  }

 private:
  void raw(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    bytes.insert(bytes.end(), b, b + n);
  }
  void count(std::size_t n) {  // u32
    if (n > 0xffffffffu)
      throw SceneError("package: a list or text of " + std::to_string(n) + " elements, more than a u32 count holds");
    const auto c = static_cast<std::uint32_t>(n);
    raw(&c, 4);
  }
};

}  // namespace meter::convert
