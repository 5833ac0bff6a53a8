// Helpers shared by the shadergen unit tests.
#pragma once

#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "meter/shadergen/glsl.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace meter::shadergen::test {

inline bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// True if `source` declares `uniform [precision] <type> <name>` (plain or array).
inline bool declares_uniform(const std::string& source, const std::string& name) {
  const std::regex re("(^|\\n)\\s*uniform\\s+(\\w+\\s+)*\\w+\\s+" + name + "\\s*[\\[;]");
  return std::regex_search(source, re);
}

inline bool declares_any_uniform(const Program& p, const std::string& name) {
  return declares_uniform(p.vertex_source, name) || declares_uniform(p.fragment_source, name);
}

inline ::testing::AssertionResult compiles(const Program& p) {
  const CompileCheck c = check_compiles(p);
  if (c.ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << c.log << "\n---- vertex\n"
                                       << p.vertex_source << "\n---- fragment\n"
                                       << p.fragment_source;
}

inline MaterialFeatures pbr() {
  MaterialFeatures f;
  f.shading = ShadingModel::PbrMetallicRoughness;
  return f;
}

}  // namespace meter::shadergen::test
