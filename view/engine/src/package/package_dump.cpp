// The record dump (package_dump.hpp), driven by the package's field lists.
#include "meter/engine/package_dump.hpp"

#include <array>
#include <cinttypes>
#include <cstdio>
#include <type_traits>
#include <vector>

#include "meter/bridge/package_fields.hpp"
#include "meter/bridge/package_format.hpp"

namespace meter::engine {
namespace {

// Arrays and texts longer than this are printed as their size and hash.
constexpr std::size_t kLongArray = 16;
constexpr std::size_t kLongText = 96;

std::uint64_t hash(const void* data, std::size_t size) {
  return package_checksum({static_cast<const std::uint8_t*>(data), size});
}

std::string hashed(std::size_t count, const char* unit, const void* data, std::size_t bytes) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%zu %s, fnv1a64 %016" PRIx64, count, unit, hash(data, bytes));
  return buf;
}

std::string number(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", double(v));
  return buf;
}
std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// A scalar (integer, enum, bool, float) as text.
template <class T>
std::string scalar(const T& v) {
  if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
  else if constexpr (std::is_floating_point_v<T>) return number(v);
  else if constexpr (std::is_enum_v<T>) return std::to_string(static_cast<long long>(v));
  else if constexpr (std::is_signed_v<T>) return std::to_string(static_cast<long long>(v));
  else return std::to_string(static_cast<unsigned long long>(v));
}

template <class T>
constexpr bool is_glm = std::is_same_v<T, glm::vec3> || std::is_same_v<T, glm::vec4> || std::is_same_v<T, glm::quat> ||
                        std::is_same_v<T, glm::mat3> || std::is_same_v<T, glm::mat4>;

// A vector, quaternion (x, y, z, w) or matrix (its columns) as "(a, b, ...)".
template <class T>
std::string glm_text(const T& v) {
  std::string s = "(";
  auto put = [&](float f) { (s.size() > 1 ? s += ", " : s) += number(f); };
  if constexpr (std::is_same_v<T, glm::quat>) {
    put(v.x), put(v.y), put(v.z), put(v.w);
  } else if constexpr (std::is_same_v<T, glm::mat3> || std::is_same_v<T, glm::mat4>) {
    for (int c = 0; c < T::length(); ++c)
      for (int r = 0; r < T::col_type::length(); ++r) put(v[c][r]);
  } else {
    for (int i = 0; i < T::length(); ++i) put(v[i]);
  }
  return s + ")";
}

std::string text(const std::string& s) {
  bool plain = s.size() <= kLongText;
  for (unsigned char c : s) plain = plain && c >= 0x20 && c < 0x7f && c != '"' && c != '\\';
  return plain ? "\"" + s + "\"" : hashed(s.size(), "bytes", s.data(), s.size());
}

class Dump {
 public:
  std::string out;

  template <class T>
  void value(const std::string& path, const T& v) {
    if constexpr (bridge::package_record<T>) {
      bridge::fields(v, [&](const auto& field, const auto& member) { value(path + "." + bridge::field_name(field), member); });
    } else if constexpr (bridge::is_vector<T> || bridge::is_array<T>) {
      list(path, v);
    } else if constexpr (std::is_same_v<T, std::string>) {
      line(path, text(v));
    } else if constexpr (is_glm<T>) {
      line(path, glm_text(v));
    } else {
      line(path, scalar(v));
    }
  }

 private:
  void line(const std::string& path, const std::string& v) { out += path + " = " + v + "\n"; }

  template <class L>
  void list(const std::string& path, const L& items) {
    using T = typename L::value_type;
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      if (items.size() > kLongArray) return line(path, hashed(items.size(), "values", items.data(), items.size() * sizeof(T)));
      std::string s = "[";
      for (const T& x : items) (s.size() > 1 ? s += ", " : s) += scalar(x);
      return line(path, s + "]");
    } else {
      if constexpr (bridge::is_vector<L>) line(path + ".count", std::to_string(items.size()));
      for (std::size_t i = 0; i < items.size(); ++i) value(path + "[" + std::to_string(i) + "]", items[i]);
    }
  }
};

}  // namespace

std::string dump_scene(const Scene& scene) {
  Dump d;
  bridge::fields(scene, [&](const bridge::SceneSection& section, const auto& member) { d.value(section.name, member); });
  return d.out;
}

}  // namespace meter::engine
