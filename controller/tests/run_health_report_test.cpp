// Health reporting: a replay that falls behind counts its slips in health(), error frames in a log
// drive the bus state as on a live bus, and the run loop's HealthReport turns changes into log
// lines (bus state, losses at most once a second, view faults rising and clearing), trace rows
// and the stats line.
#include <gtest/gtest.h>
#include <linux/can/error.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "../src/run/health_report.hpp"
#include "meter/controller/input/log_replay.hpp"
#include "meter/protocol/wire.hpp"

namespace meter::controller {
namespace {

struct NullSink : InputSink {
  void on_frame(const CanFrame&) override { ++frames; }
  void on_value(std::string_view, double, bool, std::int64_t) override {}
  int frames = 0;
};

TEST(HealthReport, AReplayThatFallsBehindCountsItsSlips) {
  ParsedLog log;
  for (int i = 0; i < 100; ++i) {  // a frame every 10 ms
    CanFrame f;
    f.timestamp_ns = 1'000'000'000LL + i * 10'000'000LL;
    f.id = 0x123;
    f.len = 1;
    log.frames.push_back(f);
  }
  CanFrame err;
  err.timestamp_ns = 1'000'000'000LL;
  err.error = true;
  err.id = CAN_ERR_BUSOFF;
  err.len = 8;
  log.frames.insert(log.frames.begin() + 1, err);
  LogReplay replay(std::move(log), ReplayOptions{ReplayMode::Realtime, 1.0, {}});
  NullSink sink;
  replay.poll(sink, std::chrono::milliseconds(0));
  EXPECT_EQ(replay.health().replay_slips, 0U);
  EXPECT_EQ(replay.health().state, BusState::BusOff) << "the log's error frame";
  // 150 ms without a poll: far beyond the 20 ms lag bound, so the replay clock slips.
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  replay.poll(sink, std::chrono::milliseconds(0));
  EXPECT_EQ(replay.health().replay_slips, 1U);
  EXPECT_EQ(replay.health().replay_slips, replay.slips());
}

// A HealthReport's stderr and its trace file (removed after the test).
class HealthReportRun : public ::testing::Test {
 protected:
  void TearDown() override { std::filesystem::remove(trace_path); }
  std::string trace_text() const {
    std::ifstream in(trace_path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  const std::filesystem::path trace_path =
      std::filesystem::temp_directory_path() /
      (std::string("meter_health_report_") + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".csv");
  std::ostringstream err;
};

TEST_F(HealthReportRun, ChangesBecomeLogLinesTraceRowsAndTheStatsLine) {
  {
    Trace trace(trace_path.string());
    HealthReport r("SocketCAN vcan0");
    BusHealth b;
    r.update(b, 0, 1'000'000'000, err, trace);
    EXPECT_EQ(err.str(), "") << "a healthy start says nothing";
    b.state = BusState::ErrorPassive;
    b.error_frames = 1;
    b.kernel_drops = 10;
    r.update(b, 0, 1'100'000'000, err, trace);
    b.kernel_drops = 25;
    b.replay_slips = 0;
    r.update(b, 0, 1'500'000'000, err, trace);  // within the second: no new loss line
    EXPECT_EQ(r.controller_faults(), protocol::kControllerFaultBusPassive | protocol::kControllerFaultFramesLost);
    b.kernel_drops = 30;
    r.update(b, protocol::kViewFaultDumpFailed, 2'200'000'000, err, trace);
    r.update(b, 0, 2'300'000'000, err, trace);
    r.update(b, protocol::kViewFaultDumpFailed | protocol::kViewFaultFrameDeadline, 2'400'000'000, err, trace);
    EXPECT_EQ(r.controller_faults(), protocol::kControllerFaultBusPassive | protocol::kControllerFaultFramesLost)
        << "0.2 s after the last drop";
    b.state = BusState::BusOff;
    b.replay_slips = 1;
    r.update(b, 0, 3'300'000'000, err, trace);
    EXPECT_EQ(r.controller_faults(), protocol::kControllerFaultBusOff | protocol::kControllerFaultReplaySlip)
        << "1.1 s after the last drop the frames-lost flag is down; the slip raises its own";
    EXPECT_EQ(r.view_fault_count(protocol::kViewFaultDumpFailed), 2U);
    EXPECT_EQ(r.view_fault_count(protocol::kViewFaultFrameDeadline), 1U);
    const std::string stats = r.stats_text();
    EXPECT_NE(stats.find("bus bus-off, 1 error frames"), std::string::npos) << stats;
    EXPECT_NE(stats.find("30 kernel drops"), std::string::npos) << stats;
    EXPECT_NE(stats.find("view faults: frame-deadline 1, dump-failed 2"), std::string::npos) << stats;
  }
  const std::string log = err.str();
  EXPECT_NE(log.find("SocketCAN vcan0: bus error-passive"), std::string::npos) << log;
  EXPECT_NE(log.find("SocketCAN vcan0: bus bus-off"), std::string::npos) << log;
  EXPECT_NE(log.find("0 dropped by the kernel (receive queue full), 0 by the interface (input backlog full), 1 "
                     "replay slips; totals 30 drops, 0 interface drops, 1 slips"),
            std::string::npos) << log;
  EXPECT_NE(log.find("frames lost: 10 dropped by the kernel"), std::string::npos) << log;
  EXPECT_NE(log.find("frames lost: 20 dropped by the kernel (receive queue full), 0 by the interface (input backlog "
                     "full), 0 replay slips; totals 30 drops"),
            std::string::npos)
      << "the lines are at most one a second, and none of the drops is left out:\n" << log;
  EXPECT_NE(log.find("view reports a fault: dump-failed (STATUS fault flags 0x2)"), std::string::npos) << log;
  EXPECT_NE(log.find("view fault cleared: dump-failed"), std::string::npos) << log;
  EXPECT_NE(log.find("view reports a fault: frame-deadline, dump-failed (STATUS fault flags 0x3)"), std::string::npos) << log;
  const std::string text = trace_text();
  EXPECT_NE(text.find(",kernel_drops,30\n"), std::string::npos) << text;
  EXPECT_NE(text.find(",bus_state,2\n"), std::string::npos) << text;
  EXPECT_NE(text.find(",view_faults,3\n"), std::string::npos) << text;
}

TEST_F(HealthReportRun, InterfaceDropsAreLossesLikeKernelDrops) {
  {
    Trace trace(trace_path.string());
    HealthReport r("SocketCAN vcan0");
    BusHealth b;
    r.update(b, 0, 1'000'000'000, err, trace);
    b.interface_drops = 12;
    r.update(b, 0, 1'100'000'000, err, trace);
    EXPECT_EQ(r.controller_faults(), protocol::kControllerFaultFramesLost) << "a frame lost before any socket is lost";
    r.update(b, 0, 2'200'000'000, err, trace);
    EXPECT_EQ(r.controller_faults(), 0U) << "held 1 s after the last drop, then down";
    EXPECT_NE(r.stats_text().find("0 kernel drops, 12 interface drops"), std::string::npos) << r.stats_text();
  }
  EXPECT_NE(err.str().find("frames lost: 0 dropped by the kernel (receive queue full), 12 by the interface (input "
                           "backlog full), 0 replay slips; totals 0 drops, 12 interface drops, 0 slips"),
            std::string::npos)
      << err.str();
  EXPECT_NE(trace_text().find(",interface_drops,12\n"), std::string::npos) << trace_text();
}

}  // namespace
}  // namespace meter::controller
