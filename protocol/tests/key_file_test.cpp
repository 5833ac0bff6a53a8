// The link key file: its grammar, its errors (file, line, what was expected) and the ownership and
// mode checks before it is read.
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <fstream>

#include "link/key_ring.hpp"
#include "meter/protocol/key_file.hpp"
#include "test_util.hpp"

namespace meter::protocol {
namespace {

const std::string kHex(64, 'a');

TEST(KeyFile, ReadsKeysInOrderWithCommentsAndBlankLines) {
  const auto r = parse_key_file("# link keys\n\n7 " + kHex + "\r\n  3\t" + std::string(64, '0').replace(63, 1, "1") + "\n",
                                "k.keys");
  ASSERT_EQ(r.error, "");
  ASSERT_EQ(r.keys.size(), 2U);
  EXPECT_EQ(r.keys[0].id, 7U);
  EXPECT_EQ(r.keys[0].key.bytes[0], 0xAA);
  EXPECT_EQ(r.keys[1].id, 3U);
  EXPECT_EQ(r.keys[1].key.bytes[31], 0x01);
}

TEST(KeyFile, EveryBadLineNamesFileLineAndWhatWasExpected) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "k:1: no key"},
      {"# only a comment\n", "k:1: no key"},
      {"1\n", "k:1: expected '<key id> <64 hex digits>'"},
      {"0 " + kHex, "k:1: key id '0': expected an integer 1..4294967295"},
      {"x " + kHex, "key id 'x'"},
      {"4294967296 " + kHex, "key id '4294967296'"},
      {"1 abc", "k:1: key 1: expected 64 hex digits (a 256-bit key), got 3"},
      {"\n1 " + kHex.substr(1) + "g", "k:2: key 1: character 64 of the key is not a hex digit"},
      {"1 g" + kHex.substr(1), "k:1: key 1: character 1 of the key is not a hex digit"},
      {"1 0g" + kHex.substr(2), "k:1: key 1: character 2 of the key is not a hex digit"},
      {"1 " + std::string(64, '0'), "all zeros"},
      {"1 " + kHex + "\n1 " + kHex, "k:2: key id 1 appears twice"},
      {std::string(kMaxKeyFileBytes + 1, '#'), "a key file at most"},
  };
  for (const auto& [text, expected] : cases) {
    const auto r = parse_key_file(text, "k");
    EXPECT_TRUE(r.keys.empty()) << expected;
    EXPECT_NE(r.error.find(expected), std::string::npos) << "got: " << r.error;
  }
}

TEST(KeyFile, LoaderRefusesAFileOthersMayReadASymlinkAndAMissingFile) {
  test::TempDir dir;
  const auto path = test::write_key_file(dir.file("link.keys"), {{1, 5}});
  ASSERT_EQ(load_key_file(path).error, "");
  ::chmod(path.c_str(), 0640);
  EXPECT_NE(load_key_file(path).error.find("mode 0640: group or others may access it; expected 0600"), std::string::npos);
  ::chmod(path.c_str(), 0400);
  EXPECT_EQ(load_key_file(path).error, "");
  ::symlink(path.c_str(), dir.file("link").c_str());
  EXPECT_NE(load_key_file(dir.file("link")).error.find("cannot open"), std::string::npos);
  EXPECT_NE(load_key_file(dir.file("none")).error.find("none: cannot open the key file"), std::string::npos);
  EXPECT_THROW(detail::KeyRing(dir.file("none")), std::runtime_error);
}

TEST(KeyRing, TakesAChangedFileAndKeepsItsKeysWhenTheFileTurnsBad) {
  test::TempDir dir;
  const auto path = test::write_key_file(dir.file("k"), {{1, 5}});
  detail::KeyRing ring(path);
  std::string error;
  EXPECT_FALSE(ring.refresh(error));
  test::write_key_file(path + ".new", {{2, 6}, {1, 5}});
  std::filesystem::rename(path + ".new", path);  // a new inode, as an atomic replace makes
  EXPECT_TRUE(ring.refresh(error)) << error;
  EXPECT_EQ(ring.current().id, 2U);
  EXPECT_NE(ring.find(1), nullptr);
  EXPECT_EQ(ring.ids(), "2, 1");
  std::ofstream(path + ".bad") << "2 zz\n";
  ::chmod((path + ".bad").c_str(), 0600);
  std::filesystem::rename(path + ".bad", path);
  EXPECT_FALSE(ring.refresh(error));
  EXPECT_NE(error.find("keeping the 2 key(s)"), std::string::npos) << error;
  EXPECT_EQ(ring.current().id, 2U);
}

}  // namespace
}  // namespace meter::protocol
