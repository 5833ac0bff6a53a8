// The optimized-program cache: exact keys (every field optimize() reads, the constants' float bits),
// least recently used entries dropped past the capacity.
#include "meter/shadergen/program_cache.hpp"

#include "meter/bridge/program_fields.hpp"

#include <bit>
#include <cstdint>
#include <cstdio>
#include <type_traits>
#include <utility>

namespace meter::shadergen {

namespace {

// Fields joined with separators that cannot occur inside them ('\x1f' between fields, lengths before
// the sources), so two different programs never give the same text.
void field(std::string& out, long long v) {
  out += std::to_string(v);
  out += '\x1f';
}

void text(std::string& out, const std::string& s) {
  field(out, static_cast<long long>(s.size()));
  out += s;
  out += '\x1f';
}

// The program's field list (meter/bridge/program_fields.hpp) as text: texts with their length,
// lists with their count, records field by field, numbers and flags as integers.
struct KeyText {
  std::string& out;
  template <class T>
  void record(const T& r) {
    bridge::fields(r, [&](const auto&, const auto& member) { bridge::visit_value(*this, member); });
  }
  template <class T>
  void list(const std::vector<T>& v) {
    field(out, static_cast<long long>(v.size()));
    for (const auto& x : v) bridge::visit_value(*this, x);
  }
  void text(const std::string& s) { shadergen::text(out, s); }
  template <class T>
  void scalar(const T& v) {
    static_assert(std::is_integral_v<T> || std::is_enum_v<T>, "a program holds texts, lists, integers and flags");
    field(out, static_cast<long long>(v));
  }
};

}  // namespace

// Every field of the program, by the program's field list (the material terms included).
std::string describe(const Program& p) {
  std::string out = "program\x1f";
  KeyText key{out};
  bridge::visit_value(key, p);
  return out;
}

std::string ProgramCache::key(const Program& generated, const ConstantValues& constants) {
  std::string k = describe(generated);
  k += "constants\x1f";
  field(k, static_cast<long long>(constants.values.size()));
  for (const auto& [where, values] : constants.values) {
    field(k, static_cast<long long>(where.first));
    field(k, where.second);
    field(k, static_cast<long long>(values.size()));
    // The bits, not a printed number: -0 and 0, or two NaNs, fold differently (or are rejected).
    for (const float v : values) {
      char hex[12];
      std::snprintf(hex, sizeof hex, "%08x", std::bit_cast<std::uint32_t>(v));
      k += hex;
    }
    k += '\x1f';
  }
  return k;
}

ProgramCache::ProgramCache(std::size_t capacity) : capacity_(capacity == 0 ? 1 : capacity) {}

Program ProgramCache::optimize(const Program& generated, const ConstantValues& constants, OptimizeReport* report) {
  std::string k = key(generated, constants);
  {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(k);
    if (it != entries_.end()) {
      ++hits_;
      lru_.splice(lru_.begin(), lru_, it->second.age);
      if (report) *report = it->second.report;
      return it->second.program;
    }
    ++misses_;
  }
  OptimizeReport r;
  Program p = shadergen::optimize(generated, constants, &r);
  if (report) *report = r;
  std::lock_guard lock(mutex_);
  if (!entries_.count(k)) {
    lru_.push_front(k);
    entries_.emplace(std::move(k), Entry{p, std::move(r), lru_.begin()});
    while (entries_.size() > capacity_) {
      entries_.erase(lru_.back());
      lru_.pop_back();
    }
  }
  return p;
}

std::size_t ProgramCache::hits() const {
  std::lock_guard lock(mutex_);
  return hits_;
}

std::size_t ProgramCache::misses() const {
  std::lock_guard lock(mutex_);
  return misses_;
}

std::size_t ProgramCache::size() const {
  std::lock_guard lock(mutex_);
  return entries_.size();
}

}  // namespace meter::shadergen
