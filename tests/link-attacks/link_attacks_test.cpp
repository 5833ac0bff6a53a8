// Attacks on the authenticated link through a man in the middle (link_mitm) between the real
// meter-controller and meter-view, over a Unix socket and over TCP: one MITM process per transport
// runs every attack in turn. Each is refused, counted and logged by the view; the view never
// draws a value the attacker chose; the failsafe engages when the attacker holds the link longer
// than the link timeout and the view recovers when the real controller is back; the controller's
// persisted odometer survives it all and reads back after a restart.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include "live_run.hpp"
#include "process.hpp"
#include "speed_log.hpp"

namespace fs = std::filesystem;
using meter::testing::built_executable;
using meter::testing::ChildProcess;

namespace {

const std::string kSource = METER_SOURCE_DIR;
const std::string kAttacks = "modify,replay,reorder,drop,forge,strip,version,truncate,flood,session,hello,blackhole";
constexpr int kLinkTimeoutMs = 150;

std::uint16_t free_tcp_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

// The count after `label` in a "... frames refused (mac 3, no-mac 2, ...)" line; 0 if absent.
std::uint64_t count_after(const std::string& text, const std::string& label) {
  std::smatch m;
  if (std::regex_search(text, m, std::regex("[(, ]" + label + " ([0-9]+)"))) return std::stoull(m[1]);
  return 0;
}

class LinkAttacks : public ::testing::Test {
 protected:
  static fs::path root() { return fs::path(METER_BINARY_DIR) / "link-attacks"; }
  static void SetUpTestSuite() {
    fs::create_directories(root());
    meter::testing::convert_minimal_gauge(root() / "gauge.msp");
  }

  void run(const std::string& name, bool tcp) {
    const fs::path dir = root() / name;
    fs::remove_all(dir);
    fs::create_directories(dir / "frames");
    const std::string keys = (dir / "link.keys").string();
    std::ofstream(keys) << "# the two ends' shared link key\n1 " << std::string(64, '7') << "\n";
    ::chmod(keys.c_str(), 0600);
    ASSERT_NO_THROW(meter::testing::write_demo_speed_log(dir / "speed.log", [](double t) { return t < 2 ? 40 * t : 80.0; }, 40));
    const std::string back = tcp ? "tcp:127.0.0.1:" + std::to_string(free_tcp_port()) : "unix:" + (dir / "ctl.sock").string();
    const std::string front = tcp ? "tcp:127.0.0.1:" + std::to_string(free_tcp_port()) : "unix:" + (dir / "view.sock").string();
    const std::vector<std::string> controller_args = {
        built_executable("meter-controller"), "run", "--dbc", kSource + "/controller/vehicles/demo/demo.dbc",
        "--map", kSource + "/controller/vehicles/demo/demo.map", "--key-file", keys,
        "--link-timeout", std::to_string(kLinkTimeoutMs), "--state-dir", (dir / "state").string()};
    auto first_run = controller_args;
    first_run.insert(first_run.end(), {"--input", "log:" + (dir / "speed.log").string(), "--link", back});
    ChildProcess controller(first_run, (dir / "controller.log").string());
    ChildProcess mitm({built_executable("link_mitm"), "--front", front, "--back", back, "--attacks", kAttacks,
                       "--settle-ms", "400", "--blackhole-ms", "900"},
                      (dir / "mitm.log").string());
    ChildProcess view({built_executable("meter-view"), "--scene", (root() / "gauge.msp").string(), "--backend", "egl",
                       "--link", front, "--key-file", keys, "--link-timeout", std::to_string(kLinkTimeoutMs),
                       "--fps", "10", "--dump-every", "1", "--duration", "40", "--out", (dir / "frames").string()},
                      (dir / "view.log").string());
    const auto mitm_rc = mitm.wait_for(std::chrono::seconds(45));
    ASSERT_TRUE(mitm_rc.has_value()) << "the attacks did not finish:\n" << mitm.log() << view.log();
    ASSERT_EQ(*mitm_rc, 0) << mitm.log();
    view.signal(SIGTERM);
    const auto view_rc = view.wait_for(std::chrono::seconds(20));
    controller.signal(SIGTERM);
    const auto controller_rc = controller.wait_for(std::chrono::seconds(20));
    ASSERT_EQ(view_rc.value_or(-1), 0) << view.log();
    ASSERT_EQ(controller_rc.value_or(-1), 0) << controller.log();

    const std::string attacks = mitm.log(), vlog = view.log(), clog = controller.log();
    for (const char* a : {"modify", "replay", "reorder", "drop", "forge", "strip", "version", "truncate", "flood",
                          "session", "hello", "blackhole"}) {
      EXPECT_NE(attacks.find(std::string("attack ") + a + ":"), std::string::npos) << a << " did not run:\n" << attacks;
    }
    // Refused and logged, each by what gave it away.
    const std::vector<std::pair<const char*, const char*>> logged = {
        {"modify, forge, flood, session", "MAC mismatch"},
        {"strip", "MAC missing"},
        {"replay", "was already used (replayed or reordered"},
        {"drop, reorder", "frame(s) missing before sequence"},
        {"version", "unsupported version"},
        {"truncate", tcp ? "stream framing lost" : "truncated"},
        {"hello", "authentication failed"},
        {"blackhole", "no message for"},
    };
    for (const auto& [what, line] : logged) EXPECT_NE(vlog.find(line), std::string::npos) << what << ":\n" << vlog;
    EXPECT_NE(clog.find("does not authenticate"), std::string::npos) << "hello:\n" << clog;
    // Counted: the view's exit line has every class.
    std::smatch link;
    ASSERT_TRUE(std::regex_search(vlog, link, std::regex("meter-view: link: [^\n]*"))) << vlog;
    const std::string counts = link.str();
    EXPECT_GE(count_after(counts, "mac"), 500U) << counts;
    EXPECT_GE(count_after(counts, "no-mac"), 1U) << counts;
    EXPECT_GE(count_after(counts, "version"), 1U) << counts;
    EXPECT_GE(count_after(counts, tcp ? "crc" : "truncated") + count_after(counts, "truncated"), 1U) << counts;
    EXPECT_EQ(counts.find(" 0 replays dropped"), std::string::npos) << counts;

    // The view never drew a value the attacker chose; the failsafe showed, and the link came back.
    std::set<std::string> attacker_values;
    std::smatch m;
    for (auto it = attacks.cbegin(); std::regex_search(it, attacks.cend(), m, std::regex("values ([^\n]+)")); it = m[0].second) {
      attacker_values.insert(m[1]);
    }
    ASSERT_FALSE(attacker_values.empty());
    const auto rows = meter::testing::read_csv(dir / "frames" / "frames.csv");
    ASSERT_GT(rows.size(), 20U);
    // The failsafe: frames drawn with the link lost for longer than a reconnect (3 frames at 10 fps:
    // only the 900 ms hold does that), then frames with the link up again.
    int lost_run = 0, longest_lost = 0;
    bool recovered = false;
    for (const auto& r : rows) {
      for (const auto& v : attacker_values) {
        EXPECT_NE(std::stod(r.at("Vehicle.Speed")), std::stod(v)) << "frame " << r.at("frame") << " drew the attacker's " << v;
      }
      lost_run = r.at("link_up") == "0" ? lost_run + 1 : 0;
      longest_lost = std::max(longest_lost, lost_run);
      recovered = recovered || (longest_lost >= 3 && r.at("link_up") == "1");
    }
    EXPECT_GE(longest_lost, 3) << "no frames showed the link lost while the attacker held it";
    EXPECT_TRUE(recovered) << "the view did not come back to the real controller after the hold";

    // Nothing persisted was lost: no damaged copy, no failed save, and a restart reads the
    // odometer back (a second run on the same state dir, over a log of one frame).
    std::smatch odo;
    ASSERT_TRUE(std::regex_search(clog, odo, std::regex("odometer ([0-9.]+) km, 0 damaged odometer copies, 0 odometer save errors"))) << clog;
    const double km = std::stod(odo[1]);
    EXPECT_GT(km, 0.0) << clog;
    meter::testing::write_demo_speed_log(dir / "one.log", [](double) { return 0.0; }, 0.0);
    auto again = controller_args;
    again.insert(again.end(), {"--input", "log:" + (dir / "one.log").string(), "--replay", "fast", "--exit-at-end",
                               "--link", "unix:" + (dir / "again.sock").string()});
    ChildProcess restart(again, (dir / "restart.log").string());
    ASSERT_EQ(restart.wait_for(std::chrono::seconds(20)).value_or(-1), 0) << restart.log();
    const std::string rlog = restart.log();
    std::smatch back_km;
    ASSERT_TRUE(std::regex_search(rlog, back_km, std::regex("odometer ([0-9.]+) km"))) << rlog;
    EXPECT_GE(std::stod(back_km[1]), km - 0.001) << rlog;
  }
};

TEST_F(LinkAttacks, OverAUnixSocketEveryAttackIsRefusedCountedAndLogged) { run("unix", false); }
TEST_F(LinkAttacks, OverTcpEveryAttackIsRefusedCountedAndLogged) { run("tcp", true); }

}  // namespace
