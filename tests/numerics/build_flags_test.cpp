// Build checks (docs/numerics.md, "Build"): no fast-math anywhere. cmake/MeterCompilerFlags.cmake
// refuses it in CMAKE_*_FLAGS at configure time; this test also scans every compile command of
// the build it belongs to (compile_commands.json), so a per-target or per-file flag is caught too.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

TEST(BuildFlags, ThisTranslationUnitHasIeeeSemantics) {
#if defined(__FAST_MATH__) || (defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__)
  FAIL() << "compiled with fast-math";
#endif
  volatile double zero = 0.0;
  const double nan = zero / zero;
  EXPECT_TRUE(std::isnan(nan));
  EXPECT_FALSE(nan == nan);
  EXPECT_TRUE(std::isinf(1.0 / zero));
  volatile double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_GT(tiny, 0.0);  // no flush-to-zero
  volatile double a = 1e16, b = -1e16, c = 1.0;
  EXPECT_EQ((a + b) + c, 1.0);  // no reassociation into a + (b + c) = 0
#ifdef __OPTIMIZE__
  std::printf("numerics suite compiled with optimisation (Release -O3 / RelWithDebInfo -O2)\n");
#else
  std::printf("numerics suite compiled without optimisation (-O0)\n");
#endif
}

namespace {

// The sources one compile command compiles: its file, or, for a unity batch (a CMake-generated
// unity_N_cxx.cxx of #include lines), every source the batch includes.
std::vector<std::string> sources_compiled_by(const std::string& file) {
  if (file.find("/Unity/unity_") == std::string::npos) return {file};
  std::ifstream batch(file);
  EXPECT_TRUE(batch) << file << ": a unity batch in the compile database that cannot be read";
  std::vector<std::string> sources;
  const std::regex include_line("^#include \"(.+)\"");
  std::smatch m;
  for (std::string line; std::getline(batch, line);)
    if (std::regex_search(line, m, include_line)) sources.push_back(m[1].str());
  EXPECT_FALSE(sources.empty()) << file << ": a unity batch that includes no source";
  return sources;
}

}  // namespace

TEST(BuildFlags, NoCompileCommandUsesFastMath) {
  const std::string path = std::string(METER_BINARY_DIR) + "/compile_commands.json";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path << " missing (CMAKE_EXPORT_COMPILE_COMMANDS is set by the top-level CMakeLists)";
  const auto db = nlohmann::json::parse(in);
  const std::regex bad("-ffast-math|-Ofast|-funsafe-math-optimizations|-ffinite-math-only|-fno-honor-nans|"
                       "-fno-honor-infinities|-fassociative-math|-freciprocal-math|-fno-signed-zeros|-menable-unsafe-fp-math");
  std::size_t checked = 0;
  bool saw_self = false, saw_controller = false, saw_engine = false;
  for (const auto& e : db) {
    const std::string cmd = e.contains("command") ? e["command"].get<std::string>()
                                                  : e.contains("arguments") ? e["arguments"].dump() : std::string();
    const std::string file = e.value("file", "");
    std::smatch m;
    EXPECT_FALSE(std::regex_search(cmd, m, bad)) << file << " is compiled with " << m.str();
    for (const std::string& source : sources_compiled_by(file)) {
      ++checked;
      saw_self = saw_self || source.find("tests/numerics/build_flags_test.cpp") != std::string::npos;
      saw_controller = saw_controller || source.find("controller/src/conditioning/") != std::string::npos;
      saw_engine = saw_engine || source.find("view/engine/src/") != std::string::npos;
    }
  }
  // Not vacuous: the database covers this file and the libraries the suite tests.
  EXPECT_TRUE(saw_self && saw_controller && saw_engine);
  EXPECT_GT(checked, 20u);
  std::printf("%zu sources' compile commands checked, none with fast-math\n", checked);
}
