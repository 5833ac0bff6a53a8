// A cache of optimized programs, kept across conversions in one process (the preview converts the
// artist's scene again after every save; meter-convert within one run). Its key is everything
// optimize() reads: the whole generated program (both sources, the attribute, uniform and sampler
// tables, the canonical features and flags) and the folded constants bit for bit, so a hit returns
// the very program and report a fresh optimize() would, byte for byte. The optimizer has no
// settings besides its constants (a fixed pass list compiled into this library), so nothing else
// can change its output within one process.
#pragma once

#include <cstddef>
#include <list>
#include <mutex>
#include <string>
#include <unordered_map>

#include "meter/shadergen/shadergen.hpp"

namespace meter::shadergen {

class ProgramCache {
 public:
  // A scene has at most a few dozen distinct programs; 512 keeps every program of the last few
  // versions of a large scene while bounding the memory (a program is 5-30 KB).
  static constexpr std::size_t kDefaultCapacity = 512;
  explicit ProgramCache(std::size_t capacity = kDefaultCapacity);

  // optimize(generated, constants, report), answered from the cache when the same key was
  // optimized before. A failing optimize() throws as it would and caches nothing. Thread-safe
  // (a miss optimizes outside the lock).
  Program optimize(const Program& generated, const ConstantValues& constants, OptimizeReport* report = nullptr);

  // The exact key of (generated, constants): a text naming every field optimize() reads.
  static std::string key(const Program& generated, const ConstantValues& constants);

  std::size_t hits() const;
  std::size_t misses() const;
  std::size_t size() const;

 private:
  struct Entry {
    Program program;
    OptimizeReport report;
    std::list<std::string>::iterator age;  // position in lru_ (front = most recently used)
  };
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, Entry> entries_;
  std::list<std::string> lru_;
  std::size_t hits_ = 0, misses_ = 0;
};

// Every field of a program as text (sources, tables, features, flags): equal texts = equal programs.
std::string describe(const Program& program);

}  // namespace meter::shadergen
