// The service manager's watchdog as plain data: WATCHDOG_USEC / WATCHDOG_PID read as systemd sets
// them, the keep-alive pacing, the test-only stall count.
#include "meter/protocol/service_watchdog.hpp"

#include <gtest/gtest.h>

namespace meter::protocol {
namespace {

TEST(WatchdogRequest, NoneWithoutTheVariable) {
  const auto r = watchdog_request(nullptr, nullptr, 42);
  EXPECT_EQ(r.interval_ns, 0);
  EXPECT_TRUE(r.error.empty());
}

TEST(WatchdogRequest, HalfOfWatchdogSecForThisProcess) {
  const auto r = watchdog_request("3000000", "42", 42);  // WatchdogSec=3
  EXPECT_EQ(r.timeout_ns, 3'000'000'000);
  EXPECT_EQ(r.interval_ns, 1'500'000'000);
  EXPECT_TRUE(r.error.empty());
  EXPECT_EQ(watchdog_request("3000000", nullptr, 42).interval_ns, 1'500'000'000);  // no pid: meant for us
}

TEST(WatchdogRequest, AnotherProcessesRequestIsNotOurs) {
  const auto r = watchdog_request("3000000", "41", 42);
  EXPECT_EQ(r.interval_ns, 0);
  EXPECT_TRUE(r.error.empty());
}

TEST(WatchdogRequest, ABadValueIsRefusedByName) {
  for (const char* bad : {"", "0", "-5", "3s", "1e6", " 100", "99999999999999999999"}) {
    const auto r = watchdog_request(bad, nullptr, 42);
    EXPECT_EQ(r.interval_ns, 0) << bad;
    EXPECT_NE(r.error.find("WATCHDOG_USEC='" + std::string(bad) + "'"), std::string::npos) << r.error;
  }
  const auto r = watchdog_request("1000", "x", 42);
  EXPECT_EQ(r.interval_ns, 0);
  EXPECT_NE(r.error.find("WATCHDOG_PID='x': expected a process id"), std::string::npos) << r.error;
}

TEST(StallRequest, CountOrError) {
  EXPECT_FALSE(stall_request(nullptr).after.has_value());
  EXPECT_EQ(stall_request("3").after, 3u);
  const auto r = stall_request("three");
  EXPECT_FALSE(r.after.has_value());
  EXPECT_NE(r.error.find("METER_TEST_STALL_AFTER_KEEPALIVES='three'"), std::string::npos) << r.error;
}

TEST(KeepAlivePacer, FirstAtOnceThenOneAnInterval) {
  KeepAlivePacer p(100);
  EXPECT_TRUE(p.due(1000));
  EXPECT_FALSE(p.due(1050));
  EXPECT_FALSE(p.due(1099));
  EXPECT_TRUE(p.due(1100));
  EXPECT_TRUE(p.due(1350));  // a late turn pings at once, then paces from there
  EXPECT_FALSE(p.due(1400));
  EXPECT_TRUE(p.due(1450));
  EXPECT_EQ(p.sent(), 4u);
}

TEST(KeepAlivePacer, NothingWithoutAWatchdog) {
  KeepAlivePacer p(0);
  EXPECT_FALSE(p.due(0));
  EXPECT_FALSE(p.due(1'000'000'000));
  EXPECT_EQ(p.sent(), 0u);
}

}  // namespace
}  // namespace meter::protocol
