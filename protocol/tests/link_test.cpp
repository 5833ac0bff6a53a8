// Publisher/Subscriber over real sockets: handshake, snapshot + deltas, per-peer dirty tracking,
// coalescing under a stalled reader, reconnect with catch-up, refusals, heartbeat loss, bad input.
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <mutex>
#include <thread>

#include "meter/protocol/link.hpp"
#include "meter/protocol/wire.hpp"
#include "test_util.hpp"

namespace meter::protocol {
namespace {

using namespace std::chrono_literals;
using test::pump;
using test::RawUnixClient;
using test::TempDir;
using test::LogCapture;
using test::fast_options;

// A TCP link without a key file, as a lab allows it with --insecure-link: what these tests check
// (stream framing, reassembly) is the same with and without a MAC.
LinkOptions lab_tcp_options() {
  LinkOptions o = fast_options();
  o.insecure_link = true;
  return o;
}

// ---- endpoints ----------------------------------------------------------------------------

TEST(Endpoint, ParsesAndPrintsBothKinds) {
  auto u = Endpoint::parse("unix:/run/user/1000/meter.sock");
  EXPECT_EQ(u.kind, Endpoint::Kind::Unix);
  EXPECT_EQ(u.path, "/run/user/1000/meter.sock");
  EXPECT_EQ(u.to_string(), "unix:/run/user/1000/meter.sock");
  auto t = Endpoint::parse("tcp:127.0.0.1:7400");
  EXPECT_EQ(t.kind, Endpoint::Kind::Tcp);
  EXPECT_EQ(t.host, "127.0.0.1");
  EXPECT_EQ(t.port, 7400);
  EXPECT_EQ(Endpoint::parse(t.to_string()), t);
  auto v6 = Endpoint::parse("tcp:[::1]:0");
  EXPECT_EQ(v6.host, "::1");
  EXPECT_EQ(v6.to_string(), "tcp:[::1]:0");
}

TEST(Endpoint, RejectsBadTextWithAClearMessage) {
  for (const char* bad : {"", "unix:", "udp:1.2.3.4:5", "tcp:host", "tcp::80", "tcp:h:", "tcp:h:65536",
                          "tcp:h:12x", "tcp:::1:80", "tcp:[::1:80", "tcp:[::1]80", "/tmp/x.sock"}) {
    try {
      Endpoint::parse(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(Endpoint::parse("unix:/" + std::string(200, 'a')), std::invalid_argument);
}

// A checkout, a build folder or a test's work folder can sit arbitrarily deep; sun_path holds only
// 107 bytes, so a long socket path must still link up (the file name alone has to fit).
TEST(Endpoint, UnixSocketInAFolderDeeperThanSunPathLinksUp) {
  LogCapture log;
  TempDir dir;
  std::string deep = dir.file("");
  while (deep.size() < 2 * sizeof(sockaddr_un::sun_path)) deep += "a-folder-of-a-deep-checkout/";
  std::filesystem::create_directories(deep);
  const auto ep = Endpoint::parse("unix:" + deep + "link.sock");
  ASSERT_GT(ep.path.size(), sizeof(sockaddr_un::sun_path));
  {
    Publisher pub(ep, fast_options("ctl"));
    struct stat st{};
    ASSERT_EQ(::stat(ep.path.c_str(), &st), 0) << "the socket is not at the path that was asked for";
    EXPECT_TRUE(S_ISSOCK(st.st_mode));
    EXPECT_EQ(st.st_mode & 0777, 0600U);
    pub.set(sig::kSpeed, 42.0, SignalStatus::Valid);
    Subscriber sub(ep, fast_options("view"));
    ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up() && sub.get(sig::kSpeed).value == 42.0; }))
        << sub.last_error();
    EXPECT_THROW(Publisher second(ep, fast_options()), std::runtime_error);  // the live one is seen
  }
  EXPECT_NE(::access(ep.path.c_str(), F_OK), 0);  // removed on shutdown
  // A file name that cannot fit even on its own is refused up front, naming both lengths.
  try {
    Endpoint::parse("unix:" + deep + std::string(120, 'n'));
    ADD_FAILURE() << "accepted a 120-byte socket file name";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("file name"), std::string::npos) << e.what();
  }
}

TEST(Endpoint, DefaultUsesXdgRuntimeDir) {
  const char* old = std::getenv("XDG_RUNTIME_DIR");
  const std::string saved = old ? old : "";
  ::setenv("XDG_RUNTIME_DIR", "/run/user/4242", 1);
  EXPECT_EQ(default_endpoint().to_string(), "unix:/run/user/4242/meter.sock");
  ::unsetenv("XDG_RUNTIME_DIR");
  EXPECT_EQ(default_endpoint().to_string(), "unix:/tmp/meter-" + std::to_string(::getuid()) + "/meter.sock");
  if (old) ::setenv("XDG_RUNTIME_DIR", saved.c_str(), 1);
}

// ---- state sync -----------------------------------------------------------------------------

TEST(Link, SnapshotThenDeltasOverUnix) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options("ctl"));
  pub.set(sig::kSpeed, 88.0, SignalStatus::Valid);
  pub.set_text(sig::kCurrentGear, "D", SignalStatus::Valid);
  Subscriber sub(dir.unix_endpoint(), fast_options("view"));
  EXPECT_FALSE(sub.link_up());
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up(); }));
  EXPECT_EQ(sub.get(sig::kSpeed).value, 88.0);
  EXPECT_EQ(sub.get(sig::kSpeed).status, SignalStatus::Valid);
  EXPECT_EQ(sub.get(sig::kCurrentGear).text, "D");
  EXPECT_EQ(sub.get(sig::kFuelLevel).status, SignalStatus::NotAvailable);
  EXPECT_EQ(pub.peer_count(), 1U);
  EXPECT_EQ(sub.stats().snapshots_received, 1U);

  const auto v0 = sub.state_version();
  const auto before = pub.stats();
  pub.set(sig::kSpeed, 90.5, SignalStatus::Valid);
  const std::int64_t t_set = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                 std::chrono::steady_clock::now().time_since_epoch()).count();
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.get(sig::kSpeed).value == 90.5; }));
  EXPECT_EQ(sub.state_version(), v0 + 1);
  // The received state is one SignalTable, read in place; only the changed signal is stamped.
  EXPECT_EQ(&sub.signals().get(sig::kSpeed), &sub.get(sig::kSpeed));
  EXPECT_EQ(sub.signals().version(), sub.state_version());
  EXPECT_GT(sub.signals().changed_at(sig::kSpeed), v0);
  EXPECT_LE(sub.signals().changed_at(sig::kCurrentGear), v0);
  EXPECT_EQ(sub.signals().find(60000), nullptr);
  const auto after = pub.stats();
  EXPECT_EQ(after.deltas_sent, before.deltas_sent + 1);
  EXPECT_EQ(after.signal_updates_sent, before.signal_updates_sent + 1);  // only the changed signal
  // The sender timestamp is CLOCK_MONOTONIC, the same base as steady_clock on Linux.
  EXPECT_GE(sub.last_sender_time_ns(), t_set - 1'000'000'000);
  EXPECT_LE(sub.last_sender_time_ns(), t_set + 1'000'000'000);
  EXPECT_EQ(sub.stats().sequence_gaps, 0U);
  EXPECT_EQ(pub.stats().bad_frames.total(), 0U);
  EXPECT_EQ(sub.stats().bad_frames.total(), 0U);
}

TEST(Link, SettingTheSameValueAgainSendsNothing) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  Subscriber sub(dir.unix_endpoint(), fast_options());
  pub.set(sig::kSpeed, 10.0, SignalStatus::Valid);
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up() && sub.get(sig::kSpeed).value == 10.0; }));
  const auto deltas = pub.stats().deltas_sent;
  for (int i = 0; i < 100; ++i) {
    pub.set(sig::kSpeed, 10.0, SignalStatus::Valid);
    pub.poll(0ms);
  }
  EXPECT_EQ(pub.stats().deltas_sent, deltas);
  pub.set(sig::kSpeed, 10.0, SignalStatus::TimedOut);  // a status change is a change
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.get(sig::kSpeed).status == SignalStatus::TimedOut; }));
  EXPECT_EQ(pub.stats().deltas_sent, deltas + 1);
}

TEST(Link, PerPeerDirtyTrackingAndCatchUpForALateView) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  Subscriber a(dir.unix_endpoint(), fast_options("a"));
  ASSERT_TRUE(pump(pub, a, [&] { return a.link_up(); }));
  pub.set(sig::kSpeed, 1.0, SignalStatus::Valid);
  pub.set(sig::kEngineSpeed, 800.0, SignalStatus::Valid);
  ASSERT_TRUE(pump(pub, a, [&] { return a.get(sig::kEngineSpeed).value == 800.0; }));

  // b joins late: it must get the whole current state as SNAPSHOT, not the history.
  Subscriber b(dir.unix_endpoint(), fast_options("b"));
  ASSERT_TRUE(pump(pub, b, [&] { return b.link_up(); }));
  EXPECT_EQ(b.get(sig::kSpeed).value, 1.0);
  EXPECT_EQ(b.get(sig::kEngineSpeed).value, 800.0);
  EXPECT_EQ(b.stats().deltas_received, 0U);

  const auto sent = pub.stats().signal_updates_sent;
  pub.set(sig::kFuelLevel, 55.0, SignalStatus::Valid);
  ASSERT_TRUE(pump(pub, b, [&] { return b.get(sig::kFuelLevel).value == 55.0; }));
  ASSERT_TRUE(pump(pub, a, [&] { return a.get(sig::kFuelLevel).value == 55.0; }));
  EXPECT_EQ(pub.stats().signal_updates_sent, sent + 2);  // one entry per view, nothing else
  EXPECT_EQ(pub.peer_count(), 2U);
}

TEST(Link, StatusFromTheViewReachesThePublisher) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  Subscriber sub(dir.unix_endpoint(), fast_options());
  pub.set(sig::kSpeed, 3.0, SignalStatus::Valid);
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up(); }));
  sub.send_status(600, 0x5);
  ASSERT_TRUE(pump(pub, sub, [&] {
    auto ps = pub.peer_status();
    return ps.size() == 1 && ps[0].frames_rendered == 600;
  }));
  const auto ps = pub.peer_status()[0];
  EXPECT_EQ(ps.fault_flags, 0x5U);
  EXPECT_EQ(ps.last_sequence_applied, sub.last_sequence_applied());
  EXPECT_GT(ps.last_sequence_applied, 0U);
}

TEST(Link, StatusFromThePublisherReachesEveryView) {
  // The controller's own health (frames received, frames lost, bus faults) goes to each view,
  // to a view that connects later too, and only when it changed.
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  Subscriber a(dir.unix_endpoint(), fast_options());
  ASSERT_TRUE(pump(pub, a, [&] { return a.link_up(); }));
  EXPECT_FALSE(a.publisher_status().has_value()) << "nothing sent yet";
  pub.send_status(1000, 7, kControllerFaultBusOff | kControllerFaultFramesLost);
  ASSERT_TRUE(pump(pub, a, [&] { return a.publisher_status().has_value(); }));
  EXPECT_EQ(a.publisher_status()->frames_rendered, 1000U) << "frames received by the controller";
  EXPECT_EQ(a.publisher_status()->last_sequence_applied, 7U) << "frames lost by the controller";
  EXPECT_EQ(a.publisher_status()->fault_flags, kControllerFaultBusOff | kControllerFaultFramesLost);
  const auto sent = pub.stats().status_sent;
  pub.send_status(1000, 7, kControllerFaultBusOff | kControllerFaultFramesLost);
  pub.poll(std::chrono::milliseconds(20));
  EXPECT_EQ(pub.stats().status_sent, sent) << "an unchanged status is not sent again";
  Subscriber b(dir.unix_endpoint(), fast_options());
  ASSERT_TRUE(pump(pub, b, [&] { return b.publisher_status().has_value(); })) << "a late view gets it too";
  EXPECT_EQ(b.publisher_status()->fault_flags, kControllerFaultBusOff | kControllerFaultFramesLost);
  pub.send_status(1200, 7, 0);
  ASSERT_TRUE(pump(pub, a, [&] { return a.publisher_status()->fault_flags == 0; }));
  EXPECT_EQ(a.stats().bad_frames.malformed, 0U) << "a publisher's STATUS is not a protocol error";
  EXPECT_EQ(a.stats().status_received, 2U);
  // New counts only: they go in place of the next heartbeat, so they arrive within its period.
  pub.send_status(1300, 7, 0);
  ASSERT_TRUE(pump(pub, a, [&] { return a.publisher_status()->frames_rendered == 1300; }));
  EXPECT_EQ(a.stats().status_received, 3U);
}

TEST(Link, NonFiniteValuesNeverReachTheWire) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  pub.set(sig::kSpeed, std::nan(""), SignalStatus::Valid);
  EXPECT_EQ(pub.get(sig::kSpeed).value, 0.0);
  EXPECT_EQ(pub.get(sig::kSpeed).status, SignalStatus::Invalid);
  EXPECT_TRUE(log.contains("non-finite"));
  EXPECT_THROW(pub.set(999, 1.0, SignalStatus::Valid), std::invalid_argument);
  EXPECT_THROW(pub.get(999), std::out_of_range);
  // Text is cut to the wire limit at a character boundary and invalid bytes become '?'.
  std::string long_text;
  for (int i = 0; i < 200; ++i) long_text += "\xC3\xA9";  // 400 bytes of é
  pub.set_text(sig::kCurrentGear, long_text, SignalStatus::Valid);
  EXPECT_EQ(pub.get(sig::kCurrentGear).text.size(), 254U);
  EXPECT_TRUE(is_valid_utf8(pub.get(sig::kCurrentGear).text));
  pub.set_text(sig::kCurrentGear, "a\xFF" "b", SignalStatus::Valid);
  EXPECT_EQ(pub.get(sig::kCurrentGear).text, "a?b");
}

// ---- latest-value semantics under a stalled reader -----------------------------------------

TEST(Link, StalledViewCoalescesInsteadOfQueueing) {
  LogCapture log;
  TempDir dir;
  auto opts = fast_options();
  opts.heartbeat_period = 2000ms;  // the stall is shorter than the loss threshold on purpose
  Publisher pub(dir.unix_endpoint(), opts);
  Subscriber sub(dir.unix_endpoint(), opts);
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up(); }));

  // The view stops reading; the controller keeps producing.
  constexpr int kUpdates = 20000;
  for (int i = 1; i <= kUpdates; ++i) {
    pub.set(sig::kSpeed, i, SignalStatus::Valid);
    pub.set(sig::kEngineSpeed, 2 * i, SignalStatus::Valid);
    pub.poll(0ms);
  }
  const auto st = pub.stats();
  EXPECT_GT(st.write_stalls, 0U) << "the socket buffer never filled: the test did not stall the reader";
  EXPECT_GT(st.coalesced_updates, 0U);
  EXPECT_LT(st.deltas_sent, static_cast<std::uint64_t>(kUpdates));
  // At most one batch (a DELTA of every signal plus a heartbeat) is ever waiting for a peer.
  std::size_t one_batch = kHeaderSize + kUpdateListOverhead + catalog().size() * kMaxEntrySize + kHeaderSize;
  EXPECT_LE(st.max_pending_bytes, one_batch);

  // When the view resumes it converges on the latest values, with no gaps.
  ASSERT_TRUE(pump(pub, sub, [&] {
    return sub.get(sig::kSpeed).value == kUpdates && sub.get(sig::kEngineSpeed).value == 2 * kUpdates;
  }));
  EXPECT_EQ(sub.stats().sequence_gaps, 0U);
  EXPECT_LT(sub.stats().deltas_received, static_cast<std::uint64_t>(kUpdates));
}

// ---- reconnect and catch-up -----------------------------------------------------------------

TEST(Link, ViewReconnectsWithBackoffAndGetsAFreshSnapshot) {
  LogCapture log;
  TempDir dir;
  auto opts = fast_options();
  auto pub = std::make_unique<Publisher>(dir.unix_endpoint(), opts);
  pub->set(sig::kSpeed, 10.0, SignalStatus::Valid);
  Subscriber sub(dir.unix_endpoint(), opts);
  ASSERT_TRUE(pump(*pub, sub, [&] { return sub.link_up(); }));
  EXPECT_EQ(sub.stats().reconnects, 0U);

  pub.reset();  // the controller goes away
  const auto t0 = std::chrono::steady_clock::now();
  while (sub.link_up() && std::chrono::steady_clock::now() - t0 < 2s) sub.poll(5ms);
  EXPECT_FALSE(sub.link_up());
  EXPECT_EQ(sub.stats().link_losses, 1U);
  EXPECT_EQ(sub.get(sig::kSpeed).value, 10.0);  // the last known state stays readable
  // Retries against a missing socket back off instead of spinning.
  for (int i = 0; i < 20; ++i) sub.poll(5ms);
  EXPECT_FALSE(sub.last_error().empty());

  Publisher pub2(dir.unix_endpoint(), opts);  // the controller restarts with new state
  pub2.set(sig::kSpeed, 77.0, SignalStatus::Valid);
  pub2.set(sig::kFuelLow, 1.0, SignalStatus::Valid);
  ASSERT_TRUE(pump(pub2, sub, [&] { return sub.link_up(); }));
  EXPECT_EQ(sub.get(sig::kSpeed).value, 77.0);
  EXPECT_EQ(sub.get(sig::kFuelLow).value, 1.0);
  EXPECT_EQ(sub.stats().reconnects, 1U);
  EXPECT_EQ(sub.stats().snapshots_received, 2U);
}

TEST(Link, RestartedViewGetsCatchUpSnapshot) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  {
    Subscriber first(dir.unix_endpoint(), fast_options());
    ASSERT_TRUE(pump(pub, first, [&] { return first.link_up(); }));
  }
  pub.set(sig::kCoolantTemp, 90.0, SignalStatus::Valid);  // changed while no view was connected
  Subscriber second(dir.unix_endpoint(), fast_options());
  ASSERT_TRUE(pump(pub, second, [&] { return second.link_up() && pub.peer_count() == 1; }));
  EXPECT_EQ(second.get(sig::kCoolantTemp).value, 90.0);
}

// ---- refusals -------------------------------------------------------------------------------

TEST(Link, CatalogHashMismatchIsRefusedOnBothSides) {
  LogCapture log;
  TempDir dir;
  auto other = fast_options("other-build");
  other.catalog_hash_override = catalog_hash() ^ 1;
  Publisher pub(dir.unix_endpoint(), other);
  Subscriber sub(dir.unix_endpoint(), fast_options("view"));
  pump(pub, sub, [&] { return pub.stats().handshakes_refused > 0 && sub.stats().handshakes_refused > 0; }, 1000ms);
  EXPECT_FALSE(sub.link_up());
  EXPECT_EQ(pub.peer_count(), 0U);
  EXPECT_GE(pub.stats().handshakes_refused, 1U);
  EXPECT_GE(sub.stats().handshakes_refused, 1U);
  EXPECT_NE(sub.last_error().find("signal catalog mismatch"), std::string::npos) << sub.last_error();
  EXPECT_NE(pub.last_error().find("signal catalog mismatch"), std::string::npos) << pub.last_error();
  EXPECT_EQ(sub.stats().snapshots_received, 0U);  // not one value crossed a mismatched link
  EXPECT_TRUE(log.contains("give both the same --catalog"));
}

TEST(Link, UidNotInTheAllowListIsRejected) {
  LogCapture log;
  TempDir dir;
  auto opts = fast_options();
  opts.allowed_uids = {::getuid() + 1};
  Publisher pub(dir.unix_endpoint(), opts);
  Subscriber sub(dir.unix_endpoint(), fast_options());
  pump(pub, sub, [&] { return pub.stats().peers_rejected > 0 && !sub.last_error().empty(); }, 1000ms);
  EXPECT_GE(pub.stats().peers_rejected, 1U);
  EXPECT_FALSE(sub.link_up());
  EXPECT_NE(pub.last_error().find("allow-list"), std::string::npos) << pub.last_error();
  EXPECT_NE(sub.last_error().find("not allowed"), std::string::npos) << sub.last_error();
}

TEST(Link, SubscriberChecksThePublishersUidToo) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  auto opts = fast_options();
  opts.allowed_uids = {::getuid() + 1};
  Subscriber sub(dir.unix_endpoint(), opts);
  pump(pub, sub, [&] { return sub.stats().peers_rejected > 0; }, 1000ms);
  EXPECT_GE(sub.stats().peers_rejected, 1U);
  EXPECT_FALSE(sub.link_up());
  EXPECT_NE(sub.last_error().find("allow-list"), std::string::npos) << sub.last_error();
}

TEST(Link, ConnectionsBeyondMaxPeersAreTurnedAway) {
  LogCapture log;
  TempDir dir;
  auto opts = fast_options();
  opts.max_peers = 1;
  Publisher pub(dir.unix_endpoint(), opts);
  Subscriber first(dir.unix_endpoint(), fast_options());
  ASSERT_TRUE(pump(pub, first, [&] { return first.link_up(); }));
  Subscriber second(dir.unix_endpoint(), fast_options());
  pump(pub, second, [&] { return pub.stats().peers_rejected > 0 && !second.last_error().empty(); }, 1000ms);
  EXPECT_FALSE(second.link_up());
  EXPECT_NE(second.last_error().find("too many connections"), std::string::npos) << second.last_error();
  EXPECT_TRUE(first.link_up() || pump(pub, first, [&] { return first.link_up(); }));
  EXPECT_EQ(pub.peer_count(), 1U);
}

TEST(Link, UnixSocketIsPrivateAndNotStolen) {
  LogCapture log;
  TempDir dir;
  const auto ep = dir.unix_endpoint();
  {
    Publisher pub(ep, fast_options());
    struct stat st{};
    ASSERT_EQ(::stat(ep.path.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600U);
    try {
      Publisher second(ep, fast_options());
      ADD_FAILURE() << "a second publisher took over a live socket";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("already listening"), std::string::npos) << e.what();
    }
  }
  EXPECT_NE(::access(ep.path.c_str(), F_OK), 0);  // removed on shutdown

  // A stale socket file (publisher crashed) is replaced; a regular file is not.
  {
    int fd = ::socket(AF_UNIX, SOCK_SEQPACKET, 0);
    const detail::UnixAddress addr(ep.path);
    ASSERT_EQ(addr.error(), 0);
    ASSERT_EQ(::bind(fd, addr.get(), addr.size()), 0);
    ::close(fd);  // bound but never listening: what a crash leaves behind
    EXPECT_NO_THROW(Publisher replaced(ep, fast_options()));
  }
  std::ofstream(dir.file("plain")) << "not a socket";
  EXPECT_THROW(Publisher(dir.unix_endpoint("plain"), fast_options()), std::runtime_error);
}

// ---- link supervision -----------------------------------------------------------------------

TEST(Link, HeartbeatLossIsDetectedByTheViewAndRecovered) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  Subscriber sub(dir.unix_endpoint(), fast_options());
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up(); }));
  // Run the view alone for a while: the controller hangs (no heartbeats), 3 x 50 ms = loss.
  const auto t0 = std::chrono::steady_clock::now();
  while (sub.link_up() && std::chrono::steady_clock::now() - t0 < 1s) sub.poll(5ms);
  const auto lost_after = std::chrono::steady_clock::now() - t0;
  EXPECT_FALSE(sub.link_up());
  EXPECT_GE(lost_after, 140ms);
  EXPECT_EQ(sub.stats().link_losses, 1U);
  EXPECT_TRUE(log.contains("lost"));
  // The controller wakes up: the view reconnects and catches up.
  pub.set(sig::kSpeed, 33.0, SignalStatus::Valid);
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up() && sub.get(sig::kSpeed).value == 33.0; }));
  EXPECT_EQ(sub.stats().reconnects, 1U);
}

TEST(Link, HeartbeatLossIsDetectedByThePublisher) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  Subscriber sub(dir.unix_endpoint(), fast_options());
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up() && pub.peer_count() == 1; }));
  const auto t0 = std::chrono::steady_clock::now();
  while (pub.peer_count() > 0 && std::chrono::steady_clock::now() - t0 < 1s) pub.poll(5ms);
  EXPECT_EQ(pub.peer_count(), 0U);
  EXPECT_EQ(pub.stats().link_losses, 1U);
  EXPECT_FALSE(pub.stats().link_up);
  EXPECT_NE(pub.last_error().find("no message for"), std::string::npos) << pub.last_error();
}

TEST(Link, WaitFdWakesTheCallersEventLoop) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  Subscriber sub(dir.unix_endpoint(), fast_options());
  int ep = ::epoll_create1(0);
  epoll_event ev{};
  ev.events = EPOLLIN;
  ASSERT_EQ(::epoll_ctl(ep, EPOLL_CTL_ADD, pub.wait_fd(), &ev), 0);
  // The subscriber's HELLO makes the publisher's fd readable without anyone polling it.
  epoll_event out{};
  EXPECT_EQ(::epoll_wait(ep, &out, 1, 1000), 1);
  ::close(ep);
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up(); }));
}

// ---- TCP ------------------------------------------------------------------------------------

TEST(Link, TcpLoopbackSyncWithEphemeralPort) {
  LogCapture log;
  Publisher pub(Endpoint::parse("tcp:127.0.0.1:0"), lab_tcp_options());
  const Endpoint bound = pub.endpoint();
  ASSERT_NE(bound.port, 0);
  pub.set(sig::kOdometer, 123456.7, SignalStatus::Valid);
  Subscriber sub(bound, lab_tcp_options());
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up(); }));
  EXPECT_EQ(sub.get(sig::kOdometer).value, 123456.7);
  for (int i = 0; i < 200; ++i) pub.set(sig::kSpeed, i, SignalStatus::Valid);
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.get(sig::kSpeed).value == 199; }));
  EXPECT_EQ(sub.stats().sequence_gaps, 0U);
}

int tcp_connect(std::uint16_t port) {
  int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

TEST(Link, TcpReassemblesAHelloWrittenOneByteAtATime) {
  LogCapture log;
  auto opts = lab_tcp_options();
  opts.heartbeat_period = 300ms;  // 60 one-byte writes must fit inside the handshake timeout
  Publisher pub(Endpoint::parse("tcp:127.0.0.1:0"), opts);
  pub.set(sig::kSpeed, 61.0, SignalStatus::Valid);
  int fd = tcp_connect(pub.endpoint().port);
  ASSERT_GE(fd, 0);
  const auto hello = encode(Frame{1, 0, test::subscriber_hello()});
  for (std::uint8_t b : hello) {
    ASSERT_EQ(::send(fd, &b, 1, MSG_NOSIGNAL), 1);
    pub.poll(1ms);  // each byte arrives in its own segment and its own read
  }
  // Read back HELLO + SNAPSHOT through the same reassembly, in small reads.
  StreamAssembler in;
  bool got_snapshot = false;
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  while (!got_snapshot && std::chrono::steady_clock::now() < deadline) {
    pub.poll(1ms);
    std::uint8_t buf[7];
    const ssize_t n = ::recv(fd, buf, sizeof buf, MSG_DONTWAIT);
    if (n > 0) in.append(std::span(buf, static_cast<std::size_t>(n)));
    while (auto r = in.next()) {
      ASSERT_EQ(r->error, DecodeError::None) << r->detail;
      if (auto* s = std::get_if<Snapshot>(&r->frame.message)) {
        got_snapshot = s->complete;
        EXPECT_EQ(s->signals.size(), catalog().size());
        EXPECT_EQ(s->signals[0].id, sig::kSpeed);
        EXPECT_EQ(s->signals[0].value, 61.0);
      }
    }
  }
  EXPECT_TRUE(got_snapshot);
  EXPECT_EQ(pub.peer_count(), 1U);
  ::close(fd);
}

TEST(Link, TcpGarbageClosesTheConnectionAndIsCounted) {
  LogCapture log;
  Publisher pub(Endpoint::parse("tcp:127.0.0.1:0"), lab_tcp_options());
  int fd = tcp_connect(pub.endpoint().port);
  ASSERT_GE(fd, 0);
  const std::string junk = "GET / HTTP/1.1\r\nHost: x\r\n\r\n";
  ASSERT_EQ(::send(fd, junk.data(), junk.size(), MSG_NOSIGNAL), static_cast<ssize_t>(junk.size()));
  bool closed = false;
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  while (!closed && std::chrono::steady_clock::now() < deadline) {
    pub.poll(1ms);
    char buf[4096];
    const ssize_t n = ::recv(fd, buf, sizeof buf, MSG_DONTWAIT);
    closed = n == 0 || (n < 0 && errno == ECONNRESET);
  }
  EXPECT_TRUE(closed);
  EXPECT_EQ(pub.stats().bad_frames.bad_magic, 1U);
  EXPECT_EQ(pub.peer_count(), 0U);
  ::close(fd);
}

// ---- bad input over a datagram socket -------------------------------------------------------

TEST(Link, EveryBadFrameClassIsCountedAndDroppedWithoutLosingTheLink) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  RawUnixClient raw(dir.unix_endpoint().path);
  ASSERT_TRUE(raw.connected());
  auto hello_frame = encode(Frame{1, 0, test::subscriber_hello()});

  auto bad_crc = encode(Frame{1, 0, Heartbeat{}});
  bad_crc[30] ^= 0xFF;
  auto bad_magic = encode(Frame{1, 0, Heartbeat{}});
  bad_magic[0] = 'X';
  auto truncated = std::vector<std::uint8_t>(hello_frame.begin(), hello_frame.begin() + 40);
  auto oversized = std::vector<std::uint8_t>(kMaxFrameSize + 100, 0);
  auto unknown = test::raw_frame(77, {});
  auto malformed = test::raw_frame(4, {1, 2, 3});  // HEARTBEAT must be empty
  auto trailing = encode(Frame{1, 0, Heartbeat{}});
  trailing.push_back(0);
  for (const auto* f : {&bad_crc, &bad_magic, &truncated, &oversized, &unknown, &malformed, &trailing}) {
    ASSERT_TRUE(raw.send(*f));
  }
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  while (pub.stats().bad_frames.total() < 7 && std::chrono::steady_clock::now() < deadline) pub.poll(1ms);
  const auto b = pub.stats().bad_frames;
  EXPECT_EQ(b.crc, 1U);
  EXPECT_EQ(b.bad_magic, 1U);
  EXPECT_EQ(b.truncated, 1U);
  EXPECT_EQ(b.oversized, 1U);
  EXPECT_EQ(b.unknown_type, 1U);
  EXPECT_EQ(b.malformed, 2U);
  EXPECT_EQ(b.version, 0U);
  EXPECT_TRUE(log.contains("CRC mismatch"));

  // The connection survived: a proper HELLO still gets the snapshot.
  ASSERT_TRUE(raw.send(hello_frame));
  bool snapshot = false;
  for (int i = 0; i < 5 && !snapshot; ++i) {
    auto dgram = raw.receive(pub, 1s);
    auto r = decode(dgram);
    ASSERT_EQ(r.error, DecodeError::None) << r.detail;
    snapshot = std::holds_alternative<Snapshot>(r.frame.message);
  }
  EXPECT_TRUE(snapshot);
  EXPECT_EQ(pub.peer_count(), 1U);
}

TEST(Link, WrongVersionClosesWithAReason) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  RawUnixClient raw(dir.unix_endpoint().path);
  ASSERT_TRUE(raw.connected());
  auto v2 = encode(Frame{1, 0, test::subscriber_hello()});
  v2[4] = kProtocolVersion + 1;  // version byte; CRC now wrong too, but the version is checked first
  ASSERT_TRUE(raw.send(v2));
  bool got_close = false;
  for (int i = 0; i < 5 && !got_close && !raw.eof(); ++i) {
    auto r = decode(raw.receive(pub, 1s));
    if (auto* c = std::get_if<Close>(&r.frame.message)) {
      got_close = true;
      EXPECT_EQ(c->reason, CloseReason::VersionMismatch);
      EXPECT_NE(c->text.find("version " + std::to_string(kProtocolVersion + 1)), std::string::npos) << c->text;
    }
  }
  EXPECT_TRUE(got_close);
  EXPECT_EQ(pub.stats().bad_frames.version, 1U);
  EXPECT_EQ(pub.peer_count(), 0U);
}

TEST(Link, SequenceGapsAreCounted) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  RawUnixClient raw(dir.unix_endpoint().path);
  ASSERT_TRUE(raw.send(encode(Frame{1, 0, test::subscriber_hello()})));
  ASSERT_TRUE(raw.send(encode(Frame{2, 0, Heartbeat{}})));
  ASSERT_TRUE(raw.send(encode(Frame{6, 0, Heartbeat{}})));  // 3, 4, 5 never arrived
  ASSERT_TRUE(raw.send(encode(Frame{7, 0, Heartbeat{}})));
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  while (pub.stats().heartbeats_received < 3 && std::chrono::steady_clock::now() < deadline) pub.poll(1ms);
  EXPECT_EQ(pub.stats().sequence_gaps, 1U);
  EXPECT_EQ(pub.stats().sequence_frames_missed, 3U);
}

TEST(Link, BadInputLoggingIsRateLimited) {
  LogCapture log;
  TempDir dir;
  Publisher pub(dir.unix_endpoint(), fast_options());
  RawUnixClient raw(dir.unix_endpoint().path);
  auto junk = test::raw_frame(88, {});
  for (int i = 0; i < 200; ++i) ASSERT_TRUE(raw.send(junk));
  // The wait is a hang guard (a loaded machine under the sanitizers took over 2 s to read the 200
  // frames); the bound on the lines follows from the time the reading took.
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + 20s;
  while (pub.stats().bad_frames.unknown_type < 200 && std::chrono::steady_clock::now() < deadline) pub.poll(1ms);
  const auto took = std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now() - start);
  EXPECT_EQ(pub.stats().bad_frames.unknown_type, 200U);
  std::size_t lines = 0;
  for (const auto& l : log.lines()) lines += l.find("unknown message type") != std::string::npos;
  EXPECT_GE(lines, 1U);
  // A burst of 5, then about one a second: 8 for a read within 2 s, one more for each second beyond.
  EXPECT_LE(lines, 8U + static_cast<std::size_t>(std::max<std::int64_t>(0, took.count() - 1))) << took.count() << " s";
}

}  // namespace
}  // namespace meter::protocol
