// --trace-json on meter-controller and meter-view: both files are valid Chrome trace-event JSON
// with every stage of the way from a CAN frame to its PNG, on one clock (check_trace.py says what
// is checked). The checker is shown to refuse a broken file, so the test can fail.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "live_run.hpp"
#include "process.hpp"
#include "speed_log.hpp"

namespace fs = std::filesystem;
using meter::testing::built_executable;
using meter::testing::ChildProcess;

namespace {

const std::string kSource = METER_SOURCE_DIR;

int check(const fs::path& dir, const fs::path& controller_json, const fs::path& view_json, const std::string& name,
          std::string& output) {
  ChildProcess checker({METER_PYTHON, kSource + "/tests/trace/check_trace.py", controller_json.string(), view_json.string()},
                       (dir / (name + ".log")).string());
  const auto rc = checker.wait_for(std::chrono::seconds(30));
  output = checker.log();
  return rc.value_or(-1);
}

}  // namespace

TEST(TraceJson, BothProcessesWriteTraceEventsOnOneClock) {
  const fs::path dir = fs::path(METER_BINARY_DIR) / "trace" / "json";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_NO_THROW(meter::testing::write_demo_speed_log(
      dir / "ramp.log", [](double t) { return t < 0.5 ? 0.0 : std::min(120.0, 60.0 * (t - 0.5)); }, 3.0));
  ASSERT_NO_THROW(meter::testing::convert_minimal_gauge(dir / "gauge.msp"));
  const std::string link = "unix:" + (dir / "link.sock").string();
  ChildProcess view({built_executable("meter-view"), "--scene", (dir / "gauge.msp").string(), "--backend", "egl",
                     "--link", link, "--fps", "10", "--dump-every", "2", "--duration", "7", "--out",
                     (dir / "frames").string(), "--trace-json", (dir / "view.json").string()},
                    (dir / "view.log").string());
  ASSERT_NO_THROW(meter::testing::wait_for_first_dump(dir / "frames" / "frames.csv", view));
  ChildProcess controller({built_executable("meter-controller"), "run", "--dbc",
                           kSource + "/controller/vehicles/demo/demo.dbc", "--map",
                           kSource + "/controller/vehicles/demo/demo.map", "--input", "log:" + (dir / "ramp.log").string(),
                           "--replay", "realtime", "--link", link, "--state-dir", (dir / "state").string(),
                           "--exit-at-end", "--linger", "1", "--trace-json", (dir / "controller.json").string()},
                          (dir / "controller.log").string());
  const auto crc = controller.wait_for(std::chrono::seconds(40));
  ASSERT_TRUE(crc.has_value()) << controller.log();
  ASSERT_EQ(*crc, 0) << controller.log();
  const auto vrc = view.wait_for(std::chrono::seconds(40));
  ASSERT_TRUE(vrc.has_value()) << view.log();
  ASSERT_EQ(*vrc, 0) << view.log();

  std::string output;
  EXPECT_EQ(check(dir, dir / "controller.json", dir / "view.json", "check", output), 0) << output;

  // A file cut short (a process killed mid-write) is not valid JSON and is refused.
  std::ifstream in(dir / "view.json");
  std::stringstream text;
  text << in.rdbuf();
  std::ofstream(dir / "cut.json") << text.str().substr(0, text.str().size() / 2);
  EXPECT_NE(check(dir, dir / "controller.json", dir / "cut.json", "check-cut", output), 0) << output;
  EXPECT_NE(output.find("not valid JSON"), std::string::npos) << output;
  // A view file on another clock (every slice 10 s earlier, as if its time base were not the
  // controller's) is refused: its intakes would end before their messages were sent.
  const std::string original = text.str();
  const std::regex ts("\"ts\":([0-9]+)\\.");
  std::string shifted;
  auto last = original.cbegin();
  for (std::sregex_iterator it(original.begin(), original.end(), ts), end; it != end; ++it) {
    shifted.append(last, (*it)[0].first);
    shifted += "\"ts\":" + std::to_string(std::stoll((*it)[1].str()) - 10'000'000) + ".";
    last = (*it)[0].second;
  }
  shifted.append(last, original.cend());
  std::ofstream(dir / "shifted.json") << shifted;
  EXPECT_NE(check(dir, dir / "controller.json", dir / "shifted.json", "check-shifted", output), 0) << output;
  EXPECT_NE(output.find("not on one clock"), std::string::npos) << output;
}

// --trace-on-overrun: a view whose first frame overruns writes the ring as one trace-event file,
// named in its log; one file per 5 s at most, so a 3-s run writes one. A threshold no frame reaches
// writes none. The overrun is made by the test build's cost injection (1 us of busy time per drawn
// pixel, some 100 ms over the gauge's first, full frame), not left to start-up work: programs are
// compiled before the first frame, and Mesa's shader cache makes a warm start fast.
TEST(TraceJson, AnOverrunningFrameWritesTheLastSecondsOfTrace) {
  const fs::path dir = fs::path(METER_BINARY_DIR) / "trace" / "overrun";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_NO_THROW(meter::testing::convert_minimal_gauge(dir / "gauge.msp"));
  auto run = [&](const std::string& tag, const std::string& threshold_ms, bool slow_first_frame) {
    std::vector<std::string> args = {built_executable("meter-view"), "--scene", (dir / "gauge.msp").string(), "--backend",
                                     "egl", "--link", "unix:" + (dir / "nobody.sock").string(), "--catalog-wait", "0",
                                     "--fps", "10", "--duration", "3", "--out", (dir / tag).string(),
                                     "--trace-on-overrun", threshold_ms};
    if (slow_first_frame) args.insert(args.end(), {"--inject-cost", "1000@0-3"});
    ChildProcess view(args, (dir / (tag + ".log")).string());
    const auto rc = view.wait_for(std::chrono::seconds(40));
    EXPECT_EQ(rc.value_or(-1), 0) << view.log();
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir / tag))
      if (e.path().filename().string().rfind("overrun_", 0) == 0) files.push_back(e.path());
    return std::make_pair(files, view.log());
  };
  const auto [files, log] = run("slow", "50", true);
  ASSERT_EQ(files.size(), 1U) << log;
  EXPECT_NE(log.find(files[0].string()), std::string::npos) << "the log names the file: " << log;
  ChildProcess checker({METER_PYTHON, kSource + "/tests/trace/check_trace.py", "--overrun", files[0].string()},
                       (dir / "check.log").string());
  EXPECT_EQ(checker.wait_for(std::chrono::seconds(30)).value_or(-1), 0) << checker.log();
  const auto [none, quiet_log] = run("fast", "100000", false);
  EXPECT_TRUE(none.empty()) << quiet_log;
}
