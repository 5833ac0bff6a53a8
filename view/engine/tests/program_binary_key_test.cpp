// The program-binary cache's key and file name, pure: one key per driver and pair of sources,
// every input in it, and no two inputs that run together into one.
#include <gtest/gtest.h>

#include <set>

#include "meter/engine/gl/program_binary_cache.hpp"
#include "meter/engine/gl/program_binary_key.hpp"

using namespace meter::engine;

namespace {
const DriverIdentity kMesa{"Mesa/X.org", "llvmpipe (LLVM 15.0.6, 256 bits)", "OpenGL ES 3.2 Mesa 22.3.6"};
}

TEST(ProgramBinaryKey, TheSameDriverAndSourcesGiveTheSameKey) {
  EXPECT_EQ(program_binary_key(kMesa, "vs", "fs"), program_binary_key(DriverIdentity(kMesa), std::string("vs"), "fs"));
}

TEST(ProgramBinaryKey, EveryDriverStringAndSourceIsInTheKey) {
  std::set<ProgramBinaryKey> keys{program_binary_key(kMesa, "vs", "fs")};
  DriverIdentity d = kMesa;
  d.vendor = "Other";
  keys.insert(program_binary_key(d, "vs", "fs"));
  d = kMesa;
  d.renderer = "llvmpipe (LLVM 16.0.6, 256 bits)";
  keys.insert(program_binary_key(d, "vs", "fs"));
  d = kMesa;
  d.version = "OpenGL ES 3.2 Mesa 22.3.7";  // a driver update
  keys.insert(program_binary_key(d, "vs", "fs"));
  keys.insert(program_binary_key(kMesa, "vs ", "fs"));
  keys.insert(program_binary_key(kMesa, "vs", "fs "));
  EXPECT_EQ(keys.size(), 6u);
}

TEST(ProgramBinaryKey, BytesMovedBetweenFieldsGiveAnotherKey) {
  EXPECT_NE(program_binary_key(kMesa, "ab", "c"), program_binary_key(kMesa, "a", "bc"));
  EXPECT_NE(program_binary_key(kMesa, "vs", "fs"), program_binary_key(kMesa, "fs", "vs"));
  EXPECT_NE(program_binary_key({"ab", "c", "v"}, "", ""), program_binary_key({"a", "bc", "v"}, "", ""));
}

TEST(ProgramBinaryKey, TheFileNameIsTheKeyInHex) {
  ProgramBinaryKey key{};
  key[0] = 0x0f, key[31] = 0xa0;
  const std::string name = program_binary_file_name(key);
  EXPECT_EQ(name, "0f" + std::string(60, '0') + "a0.glbin");
  EXPECT_EQ(program_binary_file_name(program_binary_key(kMesa, "vs", "fs")).size(), 64u + 6u);
}

TEST(ProgramCacheDirectory, XdgCacheHomeThenHomeThenNone) {
  EXPECT_EQ(default_program_cache_directory("/var/cache/meter-view", "/home/u"), "/var/cache/meter-view/meter");
  EXPECT_EQ(default_program_cache_directory(nullptr, "/home/u"), "/home/u/.cache/meter");
  EXPECT_EQ(default_program_cache_directory("", "/home/u"), "/home/u/.cache/meter");
  EXPECT_EQ(default_program_cache_directory("relative", "/home/u"), "/home/u/.cache/meter");
  EXPECT_TRUE(default_program_cache_directory(nullptr, nullptr).empty());
  EXPECT_TRUE(default_program_cache_directory(nullptr, "").empty());
}
