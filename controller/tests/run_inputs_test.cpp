// Several inputs in one controller: pairing --input with --dbc, candump logs merged onto one
// timeline, the input set's one clock, and the run loop fed by two logs with a DBC each.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "meter/controller/input/blf_log_writer.hpp"
#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/candump_log.hpp"
#include "meter/controller/input/clocks.hpp"
#include "meter/controller/input/log_replay.hpp"
#include "meter/controller/input/merge_logs.hpp"
#include "meter/controller/run/input_schemes.hpp"
#include "meter/controller/run/input_set.hpp"
#include "meter/controller/run/input_specs.hpp"
#include "meter/controller/run/decode_command.hpp"
#include "meter/controller/run/run_command.hpp"
#include "model_fixture.hpp"

using namespace meter::controller;
using namespace meter::controller::testing;

namespace {

std::string error_of(const std::vector<std::string>& inputs, const std::vector<std::string>& dbcs) {
  try {
    parse_input_specs(inputs, dbcs);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// A candump -L log: one frame on id every step_ms from t0_s, payload = the frame's index as a
// little-endian 16-bit count.
std::string make_log(std::uint32_t id, double t0_s, int step_ms, int n) {
  std::ostringstream s;
  for (int k = 0; k < n; ++k) {
    CanFrame f = frame(id, static_cast<std::int64_t>(std::llround(t0_s * 1e3)) * ms + k * step_ms * ms,
                       {static_cast<std::uint8_t>(k & 0xFF), static_cast<std::uint8_t>(k >> 8), 0, 0, 0, 0, 0, 0});
    s << format_candump_line(f, "can0") << "\n";
  }
  return s.str();
}

struct Received : InputSink {
  std::vector<CanFrame> frames;
  void on_frame(const CanFrame& f) override { frames.push_back(f); }
  void on_value(std::string_view, double, bool, std::int64_t) override {}
};

// A live input without a bus: a frame waits whenever its pipe holds a byte, and the pipe is what
// it says to wait on (as SocketCAN's receive queues are).
class PipeInput : public Input {
 public:
  PipeInput() { EXPECT_EQ(::pipe2(fds_, O_CLOEXEC | O_NONBLOCK), 0); }
  ~PipeInput() override {
    ::close(fds_[0]);
    ::close(fds_[1]);
  }
  void send() { EXPECT_EQ(::write(fds_[1], "x", 1), 1); }
  std::optional<int> wait_fd() const override { return fds_[0]; }
  bool poll(InputSink& sink, std::chrono::milliseconds) override {
    char byte;
    while (::read(fds_[0], &byte, 1) == 1) sink.on_frame(CanFrame{});
    return true;
  }
  std::int64_t now_ns() const override { return monotonic_ns(); }
  std::string describe() const override { return "pipe"; }

 private:
  int fds_[2] = {-1, -1};
};

}  // namespace

TEST(RunInputs, TheInputSetWaitsOnWhatEachInputSaysToWaitOn) {
  // A log (nothing to wait on) first, the pipe second: the set sleeps until the pipe has a frame,
  // not to the end of its timeout.
  std::vector<InputSet::Member> members;
  members.push_back({std::make_unique<LogReplay>(parse_candump_log(make_log(0x100, 1000.0, 20, 4)), ReplayOptions{}), "log", -1});
  auto pipe = std::make_unique<PipeInput>();
  PipeInput* live = pipe.get();
  members.push_back({std::move(pipe), "pipe", 1});
  InputSet set(std::move(members));
  EXPECT_EQ(set.wait_fd(), std::nullopt);  // the set paces itself: it waits inside poll()
  Received rx;
  set.poll(rx, std::chrono::milliseconds(0));  // starts the replay; the first log frame is due now
  rx.frames.clear();
  live->send();
  const auto begin = std::chrono::steady_clock::now();
  set.poll(rx, std::chrono::milliseconds(5000));
  EXPECT_LT(std::chrono::steady_clock::now() - begin, std::chrono::milliseconds(2500));
  // The pipe's frame, tagged with its input index (a slow machine may see a log frame fall due too).
  EXPECT_EQ(std::count_if(rx.frames.begin(), rx.frames.end(), [](const CanFrame& f) { return f.input == 1; }), 1);
}

TEST(RunInputs, SingleInputFormsAreUnchanged) {
  auto one = parse_input_specs({"log:drive.log"}, {"v.dbc"});
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].name, "");
  EXPECT_EQ(one[0].target, "log:drive.log");
  EXPECT_EQ(one[0].dbc, "v.dbc");
  EXPECT_EQ(one[0].kind(), InputKind::Log);
  EXPECT_TRUE(parse_input_specs({"modbus-tcp:127.0.0.1:1502"}, {})[0].dbc.empty());
  // '=' inside a target is part of it, not a name.
  EXPECT_EQ(parse_input_specs({"log:/tmp/a=b.log"}, {})[0].target, "log:/tmp/a=b.log");
  auto named = parse_input_specs({"body=can:vcan0"}, {"v.dbc"});
  EXPECT_EQ(named[0].name, "body");
  EXPECT_EQ(named[0].dbc, "v.dbc");
  EXPECT_EQ(named[0].kind(), InputKind::CanBus);
}

TEST(RunInputs, TheSchemeIsParsedOnceAndAnUnknownOneListsEveryKnownForm) {
  auto specs = parse_input_specs({"a=log:/x/drive.log", "b=modbus-tcp:h:1502", "c=can:vcan1"}, {"a=v.dbc", "c=w.dbc"});
  EXPECT_EQ(specs[0].scheme->scheme, "log");
  EXPECT_EQ(specs[0].address, "/x/drive.log");
  EXPECT_EQ(specs[1].scheme->scheme, "modbus-tcp");
  EXPECT_EQ(specs[1].address, "h:1502");
  EXPECT_EQ(specs[2].address, "vcan1");
  const std::string unknown = error_of({"serial:/dev/ttyS0"}, {});
  EXPECT_TRUE(contains(unknown, "unknown scheme 'serial'")) << unknown;
  for (const InputScheme& s : input_schemes()) EXPECT_TRUE(contains(unknown, std::string(s.form))) << s.form;
  EXPECT_TRUE(contains(error_of({"vcan0"}, {}), "(no scheme before a ':')"));
  EXPECT_TRUE(contains(error_of({"can:"}, {}), "--input can:: expected can:IFACE, with something after 'can:'"));
  EXPECT_TRUE(contains(error_of({"modbus-tcp:"}, {}), "expected modbus-tcp:HOST:PORT"));
  // A log is loaded (and merged with the other logs); every other kind is opened live.
  for (const InputScheme& s : input_schemes()) {
    EXPECT_EQ(s.load != nullptr, s.kind == InputKind::Log) << s.scheme;
    EXPECT_EQ(s.open != nullptr, s.kind != InputKind::Log) << s.scheme;
  }
}

TEST(RunInputs, SeveralInputsPairWithTheirDbcs) {
  auto specs = parse_input_specs({"body=can:vcan0", "chassis=log:c.log", "pump=modbus-tcp:h:1502"},
                                 {"chassis=c.dbc", "body=b.dbc"});
  ASSERT_EQ(specs.size(), 3u);
  EXPECT_EQ(specs[0].dbc, "b.dbc");
  EXPECT_EQ(specs[1].dbc, "c.dbc");
  EXPECT_EQ(specs[2].kind(), InputKind::Modbus);
  EXPECT_TRUE(specs[2].dbc.empty());

  EXPECT_TRUE(contains(error_of({"body=can:vcan0", "can:vcan1"}, {}), "--input can:vcan1: with several inputs each one needs a name"));
  EXPECT_TRUE(contains(error_of({"a=can:vcan0", "a=can:vcan1"}, {"a=x.dbc"}), "a second input named 'a'"));
  EXPECT_TRUE(contains(error_of({"modbus=can:vcan0"}, {}), "'modbus' is reserved"));
  EXPECT_TRUE(contains(error_of({"a=can:vcan0", "b=can:vcan1"}, {"a=x.dbc", "x.dbc"}), "--dbc x.dbc: with several inputs each DBC names its input"));
  EXPECT_TRUE(contains(error_of({"a=can:vcan0", "b=can:vcan1"}, {"a=x.dbc", "c=y.dbc"}), "--dbc c=y.dbc: no input named 'c' (inputs: a, b)"));
  EXPECT_TRUE(contains(error_of({"a=can:vcan0", "b=can:vcan1"}, {"a=x.dbc", "a=y.dbc"}), "input 'a' already has the DBC x.dbc"));
  EXPECT_TRUE(contains(error_of({"a=can:vcan0", "b=can:vcan1"}, {"a=x.dbc"}), "--input b=can:vcan1: a CAN input needs its DBC: --dbc b=FILE"));
  EXPECT_TRUE(contains(error_of({"a=can:vcan0", "m=modbus-tcp:h:1"}, {"a=x.dbc", "m=y.dbc"}), "a Modbus input reads the mapping's [modbus] registers"));
  // Several Modbus inputs parse; check_modbus_tables pairs them with their register tables.
  EXPECT_EQ(parse_input_specs({"a=modbus-tcp:h:1", "b=modbus-rtu:/dev/x:9600"}, {}).size(), 2u);
  EXPECT_TRUE(contains(error_of({"a=serial:x"}, {}), "expected [NAME=]log:FILE, can:IFACE"));
  EXPECT_TRUE(contains(error_of({"log:x"}, {"other=x.dbc"}), "no input named 'other'"));
}

// Modbus inputs and the mapping's register tables: one input may read [modbus]; several read one
// [modbus NAME] table each, and a named table needs its input.
TEST(RunInputs, ModbusInputsPairWithTheirRegisterTables) {
  const Mapping one = parse_mapping("[modbus.register a]\naddress = 0\n", "one.map");
  const Mapping two = parse_mapping("[modbus.register pump.a]\naddress = 0\n[modbus.register drive.a]\naddress = 0\n", "two.map");
  auto error = [](const std::vector<std::string>& inputs, const Mapping& map) {
    try {
      check_modbus_tables(parse_input_specs(inputs, {}), map);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error({"modbus-tcp:h:1"}, one), "");
  EXPECT_EQ(error({"pump=modbus-tcp:h:1"}, one), "");  // one named Modbus input: [modbus]
  EXPECT_EQ(error({"pump=modbus-tcp:h:1", "drive=modbus-rtu:/dev/x:9600"}, two), "");
  EXPECT_EQ(error({"pump=modbus-tcp:h:1", "drive=modbus-rtu:/dev/x:9600"}, one),
            "--input pump=modbus-tcp:h:1: with several Modbus inputs each reads its own registers: one.map needs "
            "[modbus pump] and [modbus.register pump.NAME] sections");
  EXPECT_EQ(error({"pump=modbus-tcp:h:1"}, two),
            "two.map: [modbus drive]: no Modbus input is named 'drive' (Modbus inputs: pump); expected --input "
            "drive=modbus-tcp:HOST:PORT or modbus-rtu:DEV:BAUD");
  EXPECT_EQ(error({"log:x.log"}, two), "");  // no Modbus input: the tables are not read
}

// Two logs merged as the replay pulls them (inputs 0 and 1), read whole.
ParsedLog merged_in_memory(ParsedLog first, ParsedLog second) {
  std::vector<std::pair<int, std::unique_ptr<LogSource>>> logs;
  logs.emplace_back(0, std::make_unique<ParsedLogSource>(std::move(first)));
  logs.emplace_back(1, std::make_unique<ParsedLogSource>(std::move(second)));
  MergedLogSource merged(std::move(logs));
  return read_whole_log(merged);
}

TEST(RunInputs, MergedLogsKeepTheirRelativeTimingAndEachFilesOrder) {
  // Body frames every 20 ms from t = 100.000 s, chassis every 30 ms from t = 100.010 s, recorded on
  // one clock: merged, they interleave by timestamp.
  const ParsedLog merged = merged_in_memory(parse_candump_log(make_log(0x100, 100.000, 20, 5)), parse_candump_log(make_log(0x300, 100.010, 30, 4)));
  ASSERT_EQ(merged.frames.size(), 9u);
  std::vector<std::pair<int, std::int64_t>> got;
  for (const CanFrame& f : merged.frames) got.emplace_back(f.input, (f.timestamp_ns - 100000 * ms) / ms);
  const std::vector<std::pair<int, std::int64_t>> want{{0, 0},  {1, 10}, {0, 20}, {0, 40}, {1, 40},
                                                       {0, 60}, {1, 70}, {0, 80}, {1, 100}};
  EXPECT_EQ(got, want);

  // Replayed on the simulated clock, the frames come out in that order.
  LogReplay replay(merged, ReplayOptions{ReplayMode::Fast, 1.0, std::chrono::milliseconds(10)});
  Received rx;
  while (replay.poll(rx, std::chrono::milliseconds(0))) {
  }
  ASSERT_EQ(rx.frames.size(), 9u);
  for (std::size_t i = 0; i < 9; ++i) EXPECT_EQ(rx.frames[i].input, want[i].first) << i;

  // A file whose timestamps step back keeps its own order.
  const ParsedLog m2 = merged_in_memory(parse_candump_log("(5.000) can0 100#01\n(4.000) can0 100#02\n"), parse_candump_log("(4.500) can0 300#03\n"));
  ASSERT_EQ(m2.frames.size(), 3u);
  EXPECT_EQ(m2.frames[0].data[0], 3);  // 4.5 < 5.0
  EXPECT_EQ(m2.frames[1].data[0], 1);
  EXPECT_EQ(m2.frames[2].data[0], 2);
}

TEST(RunInputs, InputSetPutsEveryInputOnTheFirstOnesClock) {
  // Two inputs on clocks 4000 s apart, both replayed in real time: the second one's frames arrive
  // tagged with its index and stamped on the first one's clock. The second is one frame shorter,
  // so it has ended before the first (the time base) ends the set.
  std::vector<InputSet::Member> members;
  members.push_back({std::make_unique<LogReplay>(parse_candump_log(make_log(0x100, 1000.0, 20, 4)), ReplayOptions{}), "a", -1});
  members.push_back({std::make_unique<LogReplay>(parse_candump_log(make_log(0x300, 5000.0, 20, 3)), ReplayOptions{}), "b", 1});
  InputSet set(std::move(members));
  EXPECT_EQ(set.describe().rfind("a: candump log (streamed, replay realtime) + b: candump log (streamed", 0), 0u) << set.describe();
  // Each poll's wall time and how many frames had arrived when it returned: the second input's
  // clock is read a moment after the first's, so its frames can be off by the time spent inside the
  // poll that started both replays and the poll that delivered them, and by nothing else, however
  // long a loaded machine keeps the test from running between polls.
  Received rx;
  std::vector<double> poll_ns;
  std::vector<std::size_t> arrived;
  int polls = 0;
  for (bool more = true; more && polls < 400; ++polls) {
    const auto t0 = std::chrono::steady_clock::now();
    more = set.poll(rx, std::chrono::milliseconds(5));
    poll_ns.push_back(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count());
    arrived.push_back(rx.frames.size());
  }
  EXPECT_LT(polls, 400) << "the set never ended";
  ASSERT_EQ(rx.frames.size(), 7u);
  const auto delivering_poll = [&](std::size_t frame) {
    return static_cast<std::size_t>(std::upper_bound(arrived.begin(), arrived.end(), frame) - arrived.begin());
  };
  int a = 0, b = 0;
  for (std::size_t i = 0; i < rx.frames.size(); ++i) {
    const CanFrame& f = rx.frames[i];
    const int k = f.data[0];
    const std::int64_t base = 1000000 * ms + k * 20 * ms;
    if (f.input == 0) {  // the time base: its own log's times
      EXPECT_EQ(f.timestamp_ns, base) << "input 0 frame " << k;
    } else {
      const double bound = poll_ns.front() + poll_ns.at(delivering_poll(i));
      EXPECT_NEAR(static_cast<double>(f.timestamp_ns - base), 0.0, bound)
          << "input " << int(f.input) << " frame " << k << " (bound: the two polls' " << bound / ms << " ms)";
    }
    (f.input == 0 ? a : b) += 1;
    EXPECT_EQ(f.id, f.input == 0 ? 0x100u : 0x300u);
  }
  EXPECT_EQ(a, 4);
  EXPECT_EQ(b, 3);
}

namespace {

const char* kChassisDbc =
    "BO_ 768 Engine: 8 ECU\n"
    " SG_ Rpm : 0|16@1+ (1,0) [0|8000] \"rpm\" ICL\n"
    "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\n"
    "BA_ \"GenMsgCycleTime\" BO_ 768 30;\n";

struct TempDir {
  std::filesystem::path path = std::filesystem::temp_directory_path() / ("meter-inputs-" + std::to_string(::getpid()));
  TempDir() { std::filesystem::create_directories(path); }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return (path / name).string();
  }
};

// The two logs of the test below as the two channels of one BLF file: its frames in time order,
// the body's (can0, first to appear) channel 1, the chassis' (can1) channel 2.
std::string two_channel_blf(const TempDir& dir, const std::string& body, std::string chassis) {
  for (std::size_t at = chassis.find(" can0 "); at != std::string::npos; at = chassis.find(" can0 ", at)) chassis.replace(at, 6, " can1 ");
  std::istringstream lines(body + chassis);
  std::vector<std::string> sorted;
  for (std::string line; std::getline(lines, line);) sorted.push_back(line + "\n");
  std::sort(sorted.begin(), sorted.end());  // fixed-width times: time order
  std::string text;
  for (const std::string& l : sorted) text += l;
  const std::string path = (dir.path / "drive.blf").string();
  std::ofstream file(path, std::ios::binary);
  ParsedLogSource frames(parse_candump_log(text));
  write_blf_log(frames, file, [](std::size_t) {});
  return path;
}

}  // namespace

TEST(RunInputs, TheRunLoopReadsTwoLogsEachWithItsDbc) {
  TempDir dir;
  const std::string body_dbc = dir.write("body.dbc", kDbc), chassis_dbc = dir.write("chassis.dbc", kChassisDbc);
  // Body: Speed.WheelA counts 0..49 at 0.01 m/s (last 0.49 m/s = 1.764 km/h); chassis: Engine.Rpm
  // counts 0..29 (last 29 rpm). Both end at about 101 s.
  const std::string body_log = dir.write("body.log", make_log(256, 100.0, 20, 50));
  const std::string chassis_log = dir.write("chassis.log", make_log(768, 100.11, 30, 30));
  const std::string map = dir.write("v.map",
                                    "[Vehicle.Speed]\nsource = body.Speed.WheelA\nconvert = m/s->km/h\n"
                                    "[Vehicle.Powertrain.CombustionEngine.Speed]\nsource = Engine.Rpm\n");
  RunOptions o;
  o.inputs = {"body=log:" + body_log, "chassis=log:" + chassis_log};
  o.dbcs = {"body=" + body_dbc, "chassis=" + chassis_dbc};
  o.map = map;
  o.replay = "fast";
  o.exit_at_end = true;
  o.verbose = true;
  o.link = "unix:" + (dir.path / "link.sock").string();
  const auto runs_both = [&] {
    std::ostringstream out, err;
    ASSERT_EQ(run_command(o, out, err), 0) << err.str();
    EXPECT_TRUE(contains(out.str(), " 80 frames (80 mapped, 0 unknown id")) << out.str();
    EXPECT_TRUE(contains(err.str(), "final Vehicle.Powertrain.CombustionEngine.Speed = 29 (valid)")) << err.str();
    // No needle damping or speedometer rule in this map: the shown speed is the last frame's.
    EXPECT_TRUE(contains(err.str(), "final Vehicle.Speed = 1.764 (valid)")) << err.str();
  };
  runs_both();
  // The same two buses as the two channels of one BLF file, each a named input (log:FILE#N): the
  // same frames reach the same values, on the file's one clock.
  const std::string blf = two_channel_blf(dir, make_log(256, 100.0, 20, 50), make_log(768, 100.11, 30, 30));
  o.inputs = {"body=log:" + blf + "#1", "chassis=log:" + blf + "#2"};
  runs_both();
  o.inputs = {"body=log:" + body_log, "chassis=log:" + chassis_log};

  // The same map with the two inputs' names swapped finds no Speed message on 'body'.
  o.dbcs = {"body=" + chassis_dbc, "chassis=" + body_dbc};
  std::ostringstream out2, err2;
  EXPECT_EQ(run_command(o, out2, err2), 1);
  EXPECT_TRUE(contains(err2.str(), map + ":1: source body.Speed.WheelA: the DBC " + chassis_dbc + " has no message 'Speed'")) << err2.str();

  // A log cannot run fast next to a live bus: there would be two clocks.
  o.dbcs = {"body=" + body_dbc, "chassis=" + chassis_dbc};
  o.inputs = {"body=log:" + body_log, "chassis=can:vcan9"};
  std::ostringstream out3, err3;
  EXPECT_EQ(run_command(o, out3, err3), 1);
  EXPECT_TRUE(contains(err3.str(), "--replay fast: with a live input (can:, modbus-) the logs replay in realtime only")) << err3.str();
}

// A log in which no line gives a frame (here candump's output without -L) is an error in
// every command that reads logs, naming its first bad lines; decode once printed only its header.
TEST(RunInputs, EveryCommandRefusesALogWithoutAUsableFrame) {
  TempDir dir;
  const std::string dbc = dir.write("body.dbc", kDbc);
  const std::string log = dir.write("drive.log", "\n  can0  100   [2]  01 02\n");
  std::ostringstream dout, derr;
  EXPECT_EQ(decode_command(dbc, log, "", dout, derr), 1);
  EXPECT_TRUE(contains(derr.str(), log + ": no usable CAN frame")) << derr.str();
  EXPECT_TRUE(contains(derr.str(), log + ":2: timestamp: expected")) << derr.str();
  EXPECT_EQ(dout.str(), "");  // not even the CSV header

  RunOptions o;
  o.inputs = {"log:" + log};
  o.dbcs = {dbc};
  o.map = dir.write("v.map", "[Vehicle.Speed]\nsource = Speed.WheelA\n");
  o.replay = "fast";
  o.exit_at_end = true;
  o.link = "unix:" + (dir.path / "link.sock").string();
  std::ostringstream rout, rerr;
  EXPECT_EQ(run_command(o, rout, rerr), 1);
  EXPECT_TRUE(contains(rerr.str(), log + ":2: timestamp: expected")) << rerr.str();
}

