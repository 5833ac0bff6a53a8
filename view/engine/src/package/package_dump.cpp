// The record dump (package_dump.hpp), driven by the package's field lists.
#include "meter/engine/package_dump.hpp"

#include <array>
#include <cinttypes>
#include <cstdio>
#include <type_traits>
#include <utility>
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
std::string scalar_text(const T& v) {
  if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
  else if constexpr (std::is_floating_point_v<T>) return number(v);
  else if constexpr (std::is_enum_v<T>) return std::to_string(static_cast<long long>(v));
  else if constexpr (std::is_signed_v<T>) return std::to_string(static_cast<long long>(v));
  else return std::to_string(static_cast<unsigned long long>(v));
}

// A vector, quaternion (x, y, z, w) or matrix (its columns) as "(a, b, ...)".
template <class T>
std::string floats_text(const T& v) {
  std::string s = "(";
  bridge::for_each_float(v, [&](float f) { (s.size() > 1 ? s += ", " : s) += number(f); });
  return s + ")";
}

std::string quoted(const std::string& s) {
  bool plain = s.size() <= kLongText;
  for (unsigned char c : s) plain = plain && c >= 0x20 && c < 0x7f && c != '"' && c != '\\';
  return plain ? "\"" + s + "\"" : hashed(s.size(), "bytes", s.data(), s.size());
}

class Dump {
 public:
  std::string out;

  template <class T>
  void value(const std::string& path, const T& v) {
    const std::string outer = std::exchange(path_, path);
    bridge::visit_value(*this, v);
    path_ = outer;
  }

  // The kinds of value, as bridge::visit_value names them.
  template <class T>
  void record(const T& v) {
    const std::string at = path_;
    bridge::fields(v, [&](const auto& field, const auto& member) { value(at + "." + bridge::field_name(field), member); });
  }
  template <class T>
  void list(const std::vector<T>& items) {
    if constexpr (std::is_arithmetic_v<T>) {
      numbers(items);
    } else {
      line(std::to_string(items.size()), ".count");
      elements(items);
    }
  }
  template <class T, std::size_t N>
  void array(const std::array<T, N>& items) {
    if constexpr (std::is_arithmetic_v<T>) numbers(items);
    else elements(items);
  }
  void text(const std::string& s) { line(quoted(s)); }
  template <class T>
  void floats(const T& v) {
    line(floats_text(v));
  }
  template <class T>
  void scalar(const T& v) {
    line(scalar_text(v));
  }

 private:
  std::string path_;

  void line(const std::string& v, const char* suffix = "") { out += path_ + suffix + " = " + v + "\n"; }

  template <class L>
  void numbers(const L& items) {
    using T = typename L::value_type;
    if (items.size() > kLongArray) return line(hashed(items.size(), "values", items.data(), items.size() * sizeof(T)));
    std::string s = "[";
    for (const T& x : items) (s.size() > 1 ? s += ", " : s) += scalar_text(x);
    line(s + "]");
  }
  template <class L>
  void elements(const L& items) {
    const std::string at = path_;
    for (std::size_t i = 0; i < items.size(); ++i) value(at + "[" + std::to_string(i) + "]", items[i]);
  }
};

}  // namespace

std::string dump_scene(const Scene& scene) {
  Dump d;
  bridge::fields(scene, [&](const bridge::SceneSection& section, const auto& member) { d.value(section.name, member); });
  return d.out;
}

}  // namespace meter::engine
