// The authenticated link end to end in one process: both transports sync with a MAC on every
// frame, unauthenticated TCP is refused unless a lab allows it, ends that disagree about keys
// refuse each other clearly, and keys rotate without a restart.
#include <gtest/gtest.h>

#include <filesystem>

#include "meter/protocol/link.hpp"
#include "test_util.hpp"

namespace meter::protocol {
namespace {

using namespace std::chrono_literals;
using test::fast_options;
using test::LogCapture;
using test::pump;
using test::TempDir;
using test::write_key_file;

LinkOptions keyed(const std::string& key_file, std::string name = "") {
  LinkOptions o = fast_options(std::move(name));
  o.key_file = key_file;
  return o;
}

TEST(LinkAuth, UnixAndTcpSyncWithAMacOnEveryFrame) {
  LogCapture log;
  TempDir dir;
  const auto keys = write_key_file(dir.file("link.keys"), {{1, 40}});
  for (const auto& where : {dir.unix_endpoint(), Endpoint::parse("tcp:127.0.0.1:0")}) {
    Publisher pub(where, keyed(keys, "ctl"));
    pub.set(sig::kSpeed, 42.0, SignalStatus::Valid);
    Subscriber sub(pub.endpoint(), keyed(keys, "view"));
    ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up() && sub.get(sig::kSpeed).value == 42.0; }))
        << where.to_string() << ": " << sub.last_error();
    for (int i = 0; i < 50; ++i) pub.set(sig::kSpeed, i, SignalStatus::Valid);
    ASSERT_TRUE(pump(pub, sub, [&] { return sub.get(sig::kSpeed).value == 49 && pub.stats().status_received + pub.stats().heartbeats_received > 0; }));
    EXPECT_EQ(sub.stats().bad_frames.total(), 0U);
    EXPECT_EQ(pub.stats().bad_frames.total(), 0U);
    EXPECT_EQ(sub.stats().sequence_gaps + sub.stats().sequence_replays, 0U);
  }
  EXPECT_FALSE(log.contains("UNAUTHENTICATED"));
}

TEST(LinkAuth, UnauthenticatedTcpIsRefusedUnlessALabAllowsItAndThenSaysSo) {
  LogCapture log;
  try {
    Publisher pub(Endpoint::parse("tcp:127.0.0.1:0"), fast_options());
    FAIL() << "an unauthenticated TCP publisher started";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--insecure-link"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Subscriber(Endpoint::parse("tcp:127.0.0.1:1"), fast_options()), std::invalid_argument);
  auto lab = fast_options();
  lab.insecure_link = true;
  Publisher pub(Endpoint::parse("tcp:127.0.0.1:0"), lab);
  Subscriber sub(pub.endpoint(), lab);
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up(); }));
  EXPECT_TRUE(log.contains("UNAUTHENTICATED link on tcp:127.0.0.1:"));
  EXPECT_TRUE(log.contains("UNAUTHENTICATED link to tcp:127.0.0.1:"));
  EXPECT_TRUE(log.contains("[UNAUTHENTICATED] (--insecure-link)"));
}

TEST(LinkAuth, EndsThatDisagreeAboutKeysRefuseEachOtherClearly) {
  LogCapture log;
  TempDir dir;
  const auto mine = write_key_file(dir.file("a.keys"), {{1, 40}});
  const auto other = write_key_file(dir.file("b.keys"), {{1, 41}});
  const auto unknown = write_key_file(dir.file("c.keys"), {{9, 40}});
  struct Case {
    std::string pub_keys, sub_keys, expected;
  } cases[] = {
      {mine, other, "different keys under that id"},
      {mine, unknown, "key id 9, which"},
      {mine, "", "does not authenticate"},
      {"", mine, "this end has no key file"},
  };
  for (const auto& c : cases) {
    Publisher pub(dir.unix_endpoint(), keyed(c.pub_keys, "ctl"));
    pub.set(sig::kSpeed, 77.0, SignalStatus::Valid);
    Subscriber sub(dir.unix_endpoint(), keyed(c.sub_keys, "view"));
    pump(pub, sub, [&] { return pub.stats().handshakes_refused + sub.stats().handshakes_refused >= 2; }, 1000ms);
    EXPECT_FALSE(sub.link_up()) << c.expected;
    EXPECT_EQ(sub.stats().snapshots_received, 0U) << c.expected;
    EXPECT_NE(sub.get(sig::kSpeed).value, 77.0) << c.expected;
    EXPECT_TRUE(log.contains(c.expected)) << c.expected;
  }
}

TEST(LinkAuth, KeysRotateWithoutARestartAndARemovedKeyEndsItsConnection) {
  LogCapture log;
  TempDir dir;
  const auto pub_keys = write_key_file(dir.file("pub.keys"), {{1, 40}});
  const auto sub_keys = write_key_file(dir.file("sub.keys"), {{1, 40}});
  Publisher pub(dir.unix_endpoint(), keyed(pub_keys, "ctl"));
  Subscriber sub(dir.unix_endpoint(), keyed(sub_keys, "view"));
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up(); }));
  // Step 1 on both ends: the new key 2 is accepted; step 2 on the view: it tags with key 2.
  write_key_file(pub_keys + ".new", {{1, 40}, {2, 50}});
  std::filesystem::rename(pub_keys + ".new", pub_keys);
  write_key_file(sub_keys + ".new", {{2, 50}, {1, 40}});
  std::filesystem::rename(sub_keys + ".new", sub_keys);
  // Step 3 on the controller: key 1 is gone, so the live connection (keyed 1) ends, and the view
  // comes back on key 2 and gets a fresh SNAPSHOT.
  write_key_file(pub_keys + ".new", {{2, 50}});
  std::filesystem::rename(pub_keys + ".new", pub_keys);
  pub.set(sig::kSpeed, 12.5, SignalStatus::Valid);
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.stats().reconnects >= 1 && sub.link_up(); }, 4000ms))
      << sub.last_error();
  EXPECT_EQ(sub.get(sig::kSpeed).value, 12.5);
  EXPECT_TRUE(log.contains("was removed from")) << pub.last_error();
}

}  // namespace
}  // namespace meter::protocol
