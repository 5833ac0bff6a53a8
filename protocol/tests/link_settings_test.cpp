// The link settings both executables derive from their command line: LinkOptions from
// --link-timeout and the Endpoint from --link.
#include <gtest/gtest.h>

#include <stdexcept>

#include "meter/protocol/endpoint.hpp"
#include "meter/protocol/link_options.hpp"

namespace meter::protocol {
namespace {

using namespace std::chrono_literals;

TEST(LinkSettings, HeartbeatEveryThirdOfTheTimeoutLostAfterThreeMissed) {
  const LinkOptions o = link_options("meter-view", 300ms);
  EXPECT_EQ(o.name, "meter-view");
  EXPECT_EQ(o.missed_heartbeats_for_loss, 3);
  EXPECT_EQ(o.heartbeat_period, 100ms);
  EXPECT_EQ(link_options("x", 1000ms).heartbeat_period, 333ms);  // whole milliseconds, rounded down
  EXPECT_EQ(link_options("x", 31ms).heartbeat_period, 10ms);
  for (auto timeout : {30ms, 100ms, 299ms, 300ms, 5000ms}) {
    const LinkOptions t = link_options("x", timeout);
    EXPECT_LE(t.heartbeat_period * t.missed_heartbeats_for_loss, timeout) << timeout.count();
  }
}

TEST(LinkSettings, HeartbeatNeverFasterThanTenMilliseconds) {
  for (auto timeout : {29ms, 10ms, 1ms, 0ms, -5ms}) {
    EXPECT_EQ(link_options("x", timeout).heartbeat_period, 10ms) << timeout.count();
  }
}

TEST(LinkSettings, EverythingElseKeepsTheLinkDefaults) {
  const LinkOptions defaults;
  const LinkOptions o = link_options("meter-controller", 300ms);
  EXPECT_EQ(o.allowed_uids, defaults.allowed_uids);
  EXPECT_EQ(o.reconnect_min, defaults.reconnect_min);
  EXPECT_EQ(o.reconnect_max, defaults.reconnect_max);
  EXPECT_EQ(o.max_peers, defaults.max_peers);
  EXPECT_EQ(o.catalog_hash_override, defaults.catalog_hash_override);
}

TEST(LinkSettings, LinkOptionNamesTheDefaultOrAnEndpoint) {
  EXPECT_EQ(endpoint_from_option("default"), default_endpoint());
  EXPECT_EQ(endpoint_from_option(""), default_endpoint());
  EXPECT_EQ(endpoint_from_option("unix:/run/meter/x.sock"), Endpoint::parse("unix:/run/meter/x.sock"));
  const Endpoint tcp = endpoint_from_option("tcp:127.0.0.1:7000");
  EXPECT_EQ(tcp.kind, Endpoint::Kind::Tcp);
  EXPECT_EQ(tcp.host, "127.0.0.1");
  EXPECT_EQ(tcp.port, 7000);
  EXPECT_THROW(endpoint_from_option("Default"), std::invalid_argument);
  EXPECT_THROW(endpoint_from_option("tcp:host"), std::invalid_argument);
}

}  // namespace
}  // namespace meter::protocol
