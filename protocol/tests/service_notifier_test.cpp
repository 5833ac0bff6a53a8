// The service notifications both processes send: what each call sends, and a refused watchdog
// value logged once as a warning of the program, with no keep-alives after it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "meter/protocol/service_notifier.hpp"

namespace meter::protocol {
namespace {

TEST(ServiceNotifier, ReadyAliveAndStoppingSendTheirStates) {
  ::unsetenv("WATCHDOG_USEC");
  std::vector<std::string> sent;
  std::ostringstream log;
  ServiceNotifier n([&](const std::string& s) { sent.push_back(s); }, log, "meter-test");
  n.ready("publishing on unix:/run/x.sock");
  n.alive();  // no watchdog asked: no keep-alive
  n.stopping();
  EXPECT_EQ(sent, (std::vector<std::string>{"READY=1\nSTATUS=publishing on unix:/run/x.sock", "STOPPING=1\nSTATUS=stopping"}));
  EXPECT_EQ(log.str(), "");
}

TEST(ServiceNotifier, ARefusedWatchdogIsLoggedAndAsksForNoKeepAlive) {
  ::setenv("WATCHDOG_USEC", "soon", 1);
  std::vector<std::string> sent;
  std::ostringstream log;
  ServiceNotifier n([&](const std::string& s) { sent.push_back(s); }, log, "meter-test");
  ::unsetenv("WATCHDOG_USEC");
  n.alive();
  EXPECT_TRUE(sent.empty());
  EXPECT_EQ(log.str().rfind("meter-test: ", 0), 0u) << log.str();
  EXPECT_NE(log.str().find("WATCHDOG_USEC"), std::string::npos) << log.str();
  EXPECT_NE(log.str().find("; no watchdog keep-alives\n"), std::string::npos) << log.str();
}

}  // namespace
}  // namespace meter::protocol
