// The package's value encodings (meter/bridge/package_format.hpp), writing any record by its field
// list (meter/bridge/package_fields.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "meter/bridge/package_fields.hpp"
#include "meter/convert/scene.hpp"

namespace meter::convert {

class RecordEncoder {
 public:
  std::vector<std::uint8_t> bytes;

  template <class T>
  void value(const T& v) {
    if constexpr (bridge::package_record<T>) {
      bridge::fields(v, [&](const auto&, const auto& member) { value(member); });
    } else if constexpr (bridge::is_vector<T>) {
      count(v.size());
      if constexpr (std::is_arithmetic_v<typename T::value_type>) {
        raw(v.data(), v.size() * sizeof(typename T::value_type));
      } else {
        for (const auto& x : v) value(x);
      }
    } else if constexpr (bridge::is_array<T>) {
      for (const auto& x : v) value(x);
    } else if constexpr (std::is_same_v<T, std::string>) {
      count(v.size());
      raw(v.data(), v.size());
    } else if constexpr (std::is_same_v<T, glm::quat>) {
      value(v.x), value(v.y), value(v.z), value(v.w);
    } else if constexpr (std::is_same_v<T, glm::mat3> || std::is_same_v<T, glm::mat4>) {
      for (int c = 0; c < T::length(); ++c) value(v[c]);
    } else if constexpr (std::is_same_v<T, glm::vec3> || std::is_same_v<T, glm::vec4>) {
      for (int i = 0; i < T::length(); ++i) value(v[i]);
    } else {
      scalar(v);
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

  template <class T>
  void scalar(const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
      const std::uint8_t b = v ? 1 : 0;
      raw(&b, 1);
    } else if constexpr (std::is_enum_v<T>) {
      static_assert(bridge::enum_last<T> >= 0, "a stored enum needs its bridge::enum_last");
      const std::int32_t i = static_cast<std::int32_t>(v);
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
};

}  // namespace meter::convert
