// Zero false alarms: meter-controller replays the whole demo drive and the whole ft86 log into a
// live meter-view drawing the cluster, with its integrity monitor on, on both backends at every
// MSAA rung meter-view selects (--msaa 1, 2, 4; 8 is clamped to llvmpipe's 4). And the fault path
// end to end: an injected fault is logged, counted in frames.csv and reaches the controller in
// STATUS. Logs are replayed at --replay scale:N (every frame of the log, N times faster).
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <regex>
#include <string>
#include <tuple>

#include "live_run.hpp"
#include "monitor_rig.hpp"
#include "process.hpp"

namespace fs = std::filesystem;
using meter::testing::built_executable;
using meter::testing::ChildProcess;

namespace {

const std::string kSource = METER_SOURCE_DIR;
const std::string kShared = METER_SHARED_DIR;

struct Drive {
  const char* name;
  std::string dbc, map, log;
  const char* scale;  // the log's length over this is the replay's
};

Drive demo_drive() {
  return {"demo", kSource + "/controller/vehicles/demo/demo.dbc", kSource + "/controller/vehicles/demo/demo.map",
          kSource + "/vcan/logs/demo-drive.log", "scale:6"};  // 60 s -> 10 s
}
Drive ft86_drive() {
  return {"ft86", kShared + "/data/can/ft86_motec/sample_can_spec.dbc", kSource + "/controller/vehicles/ft86/ft86.map",
          kShared + "/data/can/ft86_motec/can_sample.log", "scale:9"};  // 90 s -> 10 s
}

struct RunResult {
  std::string view_log, controller_log;
  fs::path frames_csv;
};

// The view starts first and draws; the controller then replays the whole log and lingers; the
// view is stopped with SIGTERM (its summary line is printed on the way out). 15 fps and a 2 s link
// timeout: the test machine's llvmpipe, shared, must not lose the link over a slow frame.
RunResult replay(const std::string& tag, const Drive& drive, const std::string& backend, int msaa,
                 const std::vector<std::string>& view_extra = {}) {
  const fs::path dir = fs::path(METER_BINARY_DIR) / "integrity-monitor" / tag;
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  const std::string link = "unix:" + (dir / "link.sock").string();
  std::vector<std::string> argv = {built_executable("meter-view"), "--scene", meter::testing::converted_cluster().string(),
                                   "--backend", backend, "--msaa", std::to_string(msaa), "--link", link, "--link-timeout", "2000", "--fps", "15",
                                   "--dump-every", "30", "--out", (dir / "frames").string()};
  argv.insert(argv.end(), view_extra.begin(), view_extra.end());
  ChildProcess view(argv, (dir / "view.log").string());
  meter::testing::wait_for_first_dump(dir / "frames" / "frames.csv", view, std::chrono::seconds(60));
  ChildProcess controller({built_executable("meter-controller"), "run", "--dbc", drive.dbc, "--map", drive.map,
                           "--input", "log:" + drive.log, "--replay", drive.scale, "--link", link, "--link-timeout", "2000", "--state-dir",
                           (dir / "state").string(), "--exit-at-end", "--linger", "1.5"},
                          (dir / "controller.log").string());
  const auto crc = controller.wait_for(std::chrono::seconds(120));
  EXPECT_EQ(crc.value_or(-1), 0) << controller.log();
  view.signal(SIGTERM);
  const auto vrc = view.wait_for(std::chrono::seconds(30));
  EXPECT_EQ(vrc.value_or(-1), 0) << view.log();
  return {view.log(), controller.log(), dir / "frames" / "frames.csv"};
}

// "meter-view: integrity: N frames checked, M faults" of the view's summary; -1 when absent.
std::pair<long, long> summary(const std::string& log) {
  std::smatch m;
  if (!std::regex_search(log, m, std::regex("integrity: (\\d+) frames checked, (\\d+) faults"))) return {-1, -1};
  return {std::stol(m[1]), std::stol(m[2])};
}

class ZeroFalseAlarms : public ::testing::TestWithParam<std::tuple<std::string, std::string, int>> {};

TEST_P(ZeroFalseAlarms, WholeLogReplayedRaisesNoIntegrityFault) {
  const auto& [log_name, backend, msaa] = GetParam();
  const Drive drive = log_name == "demo" ? demo_drive() : ft86_drive();
  const auto r = replay("clean-" + log_name + "-" + backend + "-msaa" + std::to_string(msaa), drive, backend, msaa);
  ASSERT_NE(r.view_log.find("integrity monitor on"), std::string::npos) << r.view_log;
  const auto [checked, faults] = summary(r.view_log);
  // 10 s of replay at 15 fps draws ~150 frames; under load a third of that still covers the drive.
  EXPECT_GT(checked, 50) << r.view_log;
  EXPECT_EQ(faults, 0) << r.view_log;
  EXPECT_EQ(r.controller_log.find("view reports a fault: integrity"), std::string::npos) << r.controller_log;
  for (const auto& row : meter::testing::read_csv(r.frames_csv)) {
    ASSERT_TRUE(row.count("integrity_total")) << "frames.csv has no integrity columns";
    EXPECT_EQ(row.at("integrity_total"), "0") << "frame " << row.at("frame");
  }
}

INSTANTIATE_TEST_SUITE_P(Ladder, ZeroFalseAlarms,
                         ::testing::Combine(::testing::Values("demo", "ft86"), ::testing::Values("egl", "osmesa"),
                                            ::testing::Values(1, 2, 4)),
                         [](const auto& info) {
                           return std::get<0>(info.param) + "_" + std::get<1>(info.param) + "_msaa" +
                                  std::to_string(std::get<2>(info.param));
                         });

class FaultPath : public ::testing::TestWithParam<std::string> {};

// A stuck output from frame 45 on (the drive's needles move all the time): the view logs the
// fault, counts it in frames.csv, and the controller reads it from STATUS.
TEST_P(FaultPath, InjectedStuckFrameIsLoggedCountedAndSentInStatus) {
  const auto r = replay("stuck-" + GetParam(), demo_drive(), GetParam(), 4, {"--pipeline", "concurrent", "--inject-fault", "stuck@45"});
  ASSERT_NE(r.view_log.find("TEST FAULT INJECTION: stuck@45"), std::string::npos) << r.view_log;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.view_log, m, std::regex("integrity fault at frame (\\d+): "))) << r.view_log;
  EXPECT_GE(std::stol(m[1]), 45) << "a fault before the injection is a false alarm:\n" << r.view_log;
  EXPECT_GT(summary(r.view_log).second, 0) << r.view_log;
  EXPECT_NE(r.controller_log.find("view reports a fault: integrity"), std::string::npos) << r.controller_log;
  long counted = 0;
  for (const auto& row : meter::testing::read_csv(r.frames_csv)) counted = std::max(counted, std::stol(row.at("integrity_total")));
  EXPECT_GT(counted, 0) << "frames.csv counts no fault";
}

INSTANTIATE_TEST_SUITE_P(Both, FaultPath, ::testing::Values("egl", "osmesa"),
                         [](const auto& info) { return info.param; });

}  // namespace
