// ProgramCache: one link per distinct pair of sources while the program is held or not trimmed,
// the same program name for every later request, held programs never deleted by trim(), a source
// that does not compile reported with its label and nothing stored; and a render target's resolve
// program taken from the cache by the next target of the same resolve. On both backends.
#include <gtest/gtest.h>

#include <string>

#include "gl_test_util.hpp"
#include "meter/platform/program_cache.hpp"
#include "meter/platform/render_target.hpp"

namespace mp = meter::platform;
using mp::BackendKind;

namespace {

class ProgramCacheGl : public mp::test::GlBackendTest {};

INSTANTIATE_TEST_SUITE_P(Both, ProgramCacheGl, ::testing::Values(BackendKind::Egl, BackendKind::OSMesa),
                         mp::test::backend_param_name);

constexpr const char* kVertex =
    "#version 300 es\nlayout(location = 0) in vec4 a_position;\nvoid main() { gl_Position = a_position; }\n";

std::string fragment(const char* colour) {
  return std::string("#version 300 es\nprecision mediump float;\nout vec4 o;\nvoid main() { o = vec4(") + colour + "); }\n";
}

TEST_P(ProgramCacheGl, SameSourcesShareOneLinkedProgram) {
  mp::ProgramCache cache(gl());
  const GLuint red = cache.acquire(kVertex, fragment("1.0, 0.0, 0.0, 1.0"), "red");
  const GLuint again = cache.acquire(kVertex, fragment("1.0, 0.0, 0.0, 1.0"), "red again");
  const GLuint green = cache.acquire(kVertex, fragment("0.0, 1.0, 0.0, 1.0"), "green");
  EXPECT_NE(red, 0u);
  EXPECT_EQ(again, red);
  EXPECT_NE(green, red);
  EXPECT_EQ(cache.compiles(), 2u);
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_TRUE(gl().IsProgram(red));
}

TEST_P(ProgramCacheGl, TrimDeletesOnlyWhatNobodyHolds) {
  mp::ProgramCache cache(gl());
  const GLuint red = cache.acquire(kVertex, fragment("1.0, 0.0, 0.0, 1.0"), "red");
  cache.acquire(kVertex, fragment("1.0, 0.0, 0.0, 1.0"), "red, a second holder");
  const GLuint green = cache.acquire(kVertex, fragment("0.0, 1.0, 0.0, 1.0"), "green");
  cache.release(red);
  cache.release(green);
  cache.release(12345);  // not the cache's: ignored
  // Released but not trimmed: the next request gets the same program without a link.
  EXPECT_EQ(cache.acquire(kVertex, fragment("0.0, 1.0, 0.0, 1.0"), "green again"), green);
  cache.release(green);
  EXPECT_EQ(cache.trim(), 1u);  // green; red is still held once
  EXPECT_FALSE(gl().IsProgram(green));
  EXPECT_TRUE(gl().IsProgram(red));
  EXPECT_EQ(cache.size(), 1u);
  cache.release(red);
  EXPECT_EQ(cache.trim(), 1u);
  EXPECT_EQ(cache.size(), 0u);
  // After the trim the sources link again.
  EXPECT_NE(cache.acquire(kVertex, fragment("0.0, 1.0, 0.0, 1.0"), "green anew"), 0u);
  EXPECT_EQ(cache.compiles(), 3u);
}

TEST_P(ProgramCacheGl, ASourceThatDoesNotCompileIsReportedAndNotStored) {
  mp::ProgramCache cache(gl());
  try {
    cache.acquire(kVertex, "#version 300 es\nvoid main() { undeclared = 1.0; }\n", "the broken material");
    FAIL() << "a fragment shader that does not compile was linked";
  } catch (const mp::GlError& e) {
    EXPECT_NE(std::string(e.what()).find("the broken material"), std::string::npos) << e.what();
  }
  EXPECT_EQ(cache.size(), 0u);
  EXPECT_EQ(cache.compiles(), 0u);
}

// The next target of the same film filter and samples resolves with the program the first linked.
TEST_P(ProgramCacheGl, RenderTargetsOfOneResolveShareItsProgram) {
  mp::ProgramCache cache(gl());
  const mp::RenderTargetOptions options{.width = 32, .height = 16, .samples = 4,
                                        .resolve = {mp::ResolveFilter::Kind::BlackmanHarris, 1.5},
                                        .programs = &cache};
  {
    mp::RenderTarget first(*backend_, options);
    ASSERT_TRUE(first.resolves_by_shader());
    EXPECT_EQ(cache.compiles(), 1u);
  }
  mp::RenderTarget second(*backend_, options);
  EXPECT_EQ(cache.compiles(), 1u);
  EXPECT_EQ(cache.trim(), 0u);  // held by the second target
  mp::RenderTargetOptions box = options;
  box.resolve = {};
  mp::RenderTarget third(*backend_, box);
  EXPECT_EQ(cache.compiles(), 2u);  // another filter: another program
}

}  // namespace
