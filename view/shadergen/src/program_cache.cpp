// The optimized-program cache: exact keys (every field optimize() reads, the constants' float bits),
// least recently used entries dropped past the capacity.
#include "meter/shadergen/program_cache.hpp"

#include <bit>
#include <cstdint>
#include <cstdio>
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

void features_text(std::string& out, const MaterialFeatures& f) {
  for (const long long v : {static_cast<long long>(f.shading), static_cast<long long>(f.alpha),
                            static_cast<long long>(f.precision), static_cast<long long>(f.base_color_texture),
                            static_cast<long long>(f.metallic_roughness_texture), static_cast<long long>(f.normal_texture),
                            static_cast<long long>(f.emissive_texture), static_cast<long long>(f.occlusion_texture),
                            static_cast<long long>(f.texcoord1_slots), static_cast<long long>(f.texture_transform),
                            static_cast<long long>(f.vertex_colors), static_cast<long long>(f.vertex_alpha),
                            static_cast<long long>(f.double_sided), static_cast<long long>(f.skin_joints),
                            static_cast<long long>(f.morph_targets), static_cast<long long>(f.morph_normals),
                            static_cast<long long>(f.lights.directional), static_cast<long long>(f.lights.point),
                            static_cast<long long>(f.lights.spot), static_cast<long long>(f.environment_map_2d),
                            static_cast<long long>(f.has_tangents)}) {
    field(out, v);
  }
}

}  // namespace

std::string describe(const Program& p) {
  std::string out = "program\x1f";
  text(out, p.vertex_source);
  text(out, p.fragment_source);
  field(out, static_cast<long long>(p.attributes.size()));
  for (const auto& a : p.attributes) {
    text(out, a.name);
    for (const long long v : {static_cast<long long>(a.semantic), static_cast<long long>(a.index),
                              static_cast<long long>(a.location), static_cast<long long>(a.components)})
      field(out, v);
  }
  field(out, static_cast<long long>(p.uniforms.size()));
  for (const auto& u : p.uniforms) {
    text(out, u.name);
    text(out, u.glsl_type);
    for (const long long v : {static_cast<long long>(u.semantic), static_cast<long long>(u.index),
                              static_cast<long long>(u.array_size)})
      field(out, v);
  }
  field(out, static_cast<long long>(p.samplers.size()));
  for (const auto& s : p.samplers) {
    text(out, s.name);
    field(out, static_cast<long long>(s.slot));
    field(out, static_cast<long long>(s.unit));
  }
  features_text(out, p.features);
  for (const bool b : {p.blend, p.cull_back_faces, p.optimized, p.uber}) field(out, b ? 1 : 0);
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
