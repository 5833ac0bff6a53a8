// The package's value encodings (meter/bridge/package_format.hpp), read back bounds-checked into
// any record by its field list (meter/bridge/package_fields.hpp). Every record read is checked at
// once (record_checks.hpp), so an error names the byte offset, the chunk and the field's path
// ("meshes[0].primitives[2].vertices").
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "meter/bridge/package_fields.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

class RecordDecoder {
 public:
  // `data` is one chunk's body, found at byte `offset` of the file `origin`.
  RecordDecoder(std::span<const std::uint8_t> data, std::size_t offset, std::string origin, std::string chunk)
      : data_(data), offset_(offset), origin_(std::move(origin)), chunk_(std::move(chunk)) {}

  // Throws SceneError: "<origin>: corrupt package at byte N (chunk TAG): <path>: <what>".
  [[noreturn]] void fail(const std::string& what) const { fail_at("", what); }
  // The same for a part of the field being read: "<path><part>: <what>".
  [[noreturn]] void fail_at(const std::string& part, const std::string& what) const;
  std::string path() const;  // the field being read, e.g. "meshes[0].primitives[2].vertices"
  bool at_end() const { return pos_ == data_.size(); }

  template <class T>
  void value(const char* name, T& v) {
    path_.push_back({name, -1});
    bridge::visit_value(*this, v);
    path_.pop_back();
  }

  // The kinds of value, as bridge::visit_value names them.
  template <class T>
  void record(T& v) {
    bridge::fields(v, [&](const auto& field, auto& member) { value(bridge::field_name(field), member); });
    check_record(*this, v);
  }
  template <class T, std::size_t N>
  void array(std::array<T, N>& a) {
    for (std::size_t i = 0; i < N; ++i) element(a[i], i);
  }
  void text(std::string& s) {
    const std::uint32_t n = count(1);
    s.assign(reinterpret_cast<const char*>(data_.data() + pos_), n);
    pos_ += n;
  }
  template <class T>
  void floats(T& v) {
    bridge::for_each_float(v, [&](float& f) { scalar(f); });
  }
  template <class T>
  void list(std::vector<T>& v);
  template <class T>
  void scalar(T& v);

 private:
  struct Step {
    const char* name;
    long index;  // >= 0: an element of the list `name`
  };

  template <class T>
  void element(T& v, std::size_t i) {
    path_.back().index = static_cast<long>(i);
    bridge::visit_value(*this, v);
    path_.back().index = -1;
  }

  void need(std::size_t n) const {
    if (n > data_.size() - pos_) fail("truncated: " + std::to_string(n) + " bytes needed, " + std::to_string(data_.size() - pos_) + " left in the chunk");
  }
  template <class T>
  T pod() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  // A u32 count of elements of at least `element_size` bytes each, refused when they cannot fit.
  std::uint32_t count(std::size_t element_size) {
    const auto n = pod<std::uint32_t>();
    if (n > (data_.size() - pos_) / element_size) fail("count " + std::to_string(n) + " too large for the " + std::to_string(data_.size() - pos_) + " bytes left in the chunk");
    return n;
  }

  std::span<const std::uint8_t> data_;
  std::size_t offset_;
  std::string origin_, chunk_;
  std::size_t pos_ = 0;
  std::vector<Step> path_;
};

template <class T>
void RecordDecoder::list(std::vector<T>& v) {
  if constexpr (std::is_arithmetic_v<T>) {
    const std::uint32_t n = count(sizeof(T));
    v.resize(n);
    if (n) std::memcpy(v.data(), data_.data() + pos_, n * sizeof(T));
    pos_ += n * sizeof(T);
    if constexpr (std::is_floating_point_v<T>)
      for (T x : v)
        if (!std::isfinite(x)) fail("non-finite value");
  } else {
    // Every element takes at least one byte: a count past the chunk's end is refused before
    // anything is allocated, and elements are appended one by one as they are read.
    const std::uint32_t n = count(1);
    v.clear();
    for (std::uint32_t i = 0; i < n; ++i) element(v.emplace_back(), i);
  }
}

template <class T>
void RecordDecoder::scalar(T& v) {
  if constexpr (std::is_same_v<T, bool>) {
    const auto b = pod<std::uint8_t>();
    if (b > 1) fail("bool byte " + std::to_string(b) + ", expected 0 or 1");
    v = b == 1;
  } else if constexpr (std::is_enum_v<T>) {
    static_assert(bridge::enum_last<T> >= 0, "a stored enum needs its bridge::enum_last");
    const auto i = pod<std::int32_t>();
    if (i < 0 || i > bridge::enum_last<T>) fail("enum value " + std::to_string(i) + ", expected 0.." + std::to_string(bridge::enum_last<T>));
    v = static_cast<T>(i);
  } else if constexpr (std::is_same_v<T, std::size_t>) {
    v = static_cast<std::size_t>(pod<std::uint64_t>());
  } else {
    static_assert(std::is_same_v<T, int> || std::is_same_v<T, unsigned> || std::is_same_v<T, float> ||
                  std::is_same_v<T, double>, "no package encoding for this type");
    v = pod<T>();
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(v)) fail("non-finite value");
  }
}

}  // namespace meter::engine

// The checks record() calls (found by argument-dependent lookup when it is instantiated); they
// need the whole RecordDecoder.
#include "record_checks.hpp"  // IWYU pragma: export
