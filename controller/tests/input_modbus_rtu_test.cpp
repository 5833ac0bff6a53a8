// The Modbus client over RTU, against python3-pymodbus's RTU server on a socat pseudo-terminal
// pair (one peer process for every case, pymodbus_rtu_server.py): the registers' values, a silent
// slave, frames with a bad CRC and an unreachable device, each an invalid map, a clear error, a
// health state and a bounded poll; then several Modbus inputs at once (RTU and TCP, each with its
// own register table) through the controller's run loop.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/modbus_input.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/run/run_command.hpp"
#include "model_fixture.hpp"
#include "pymodbus_peer.hpp"

using namespace meter::controller;

namespace {

// The registers pymodbus_rtu_server.py serves, at unit `unit`, polled every 20 ms. The cases that
// need an answer wait up to 1 s for it (a loaded machine may be slow to run the Python peer); the
// failure cases time out after 100 ms.
std::string rtu_registers(int unit, const char* timeout = "1s") {
  return "[modbus]\npoll = 20ms\ntimeout = " + std::string(timeout) + "\nunit = " + std::to_string(unit) +
         "\n"
         "[modbus.register a]\naddress = 0\ntype = int16\n"
         "[modbus.register b]\naddress = 1\ntype = uint16\nscale = 0.1\n"
         "[modbus.register c]\naddress = 2\ntype = int32\n"
         "[modbus.register d]\naddress = 4\ntype = float32\nword_order = low_first\n"
         "[modbus.register e]\ntable = input\naddress = 0\ntype = uint32\n";
}

// The last value and validity per key, and how long the slowest poll took.
struct LastValues : InputSink {
  std::map<std::string, std::pair<double, bool>, std::less<>> values;
  void on_frame(const CanFrame&) override {}
  void on_value(std::string_view key, double v, bool valid, std::int64_t) override { values[std::string(key)] = {v, valid}; }
  int valid_count() const {
    int n = 0;
    for (const auto& [k, v] : values) n += v.second ? 1 : 0;
    return n;
  }
};

// Polls n times; returns the longest single poll in ms.
double poll_n(ModbusInput& in, LastValues& sink, int n) {
  double longest = 0;
  for (int i = 0; i < n; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    in.poll(sink, std::chrono::milliseconds(20));
    longest = std::max(longest, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return longest;
}

class ModbusRtu : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { peer_ = new meter::controller::testing::PymodbusRtuPeer(); }
  static void TearDownTestSuite() {
    delete peer_;
    peer_ = nullptr;
  }
  static std::string target() { return "rtu:" + peer_->client_device() + ":19200"; }
  static meter::controller::testing::PymodbusRtuPeer* peer_;
};
meter::controller::testing::PymodbusRtuPeer* ModbusRtu::peer_ = nullptr;

}  // namespace

TEST_F(ModbusRtu, ValuesSilentSlaveBadCrcAndUnreachableDevice) {
  ASSERT_TRUE(peer_->started());
  {
    const Mapping m = parse_mapping(rtu_registers(1), "rtu.map");
    ModbusInput in(target(), *m.modbus);
    LastValues r;
    // The Python interpreter needs a moment to make the pair and open its end; until then the
    // device is missing (unreachable) or silent.
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (r.valid_count() < 5 && std::chrono::steady_clock::now() < give_up) in.poll(r, std::chrono::milliseconds(20));
    ASSERT_EQ(r.valid_count(), 5) << in.last_error();
    EXPECT_EQ(r.values.at("modbus.a").first, -5);
    EXPECT_NEAR(r.values.at("modbus.b").first, 123.4, 1e-9);
    EXPECT_EQ(r.values.at("modbus.c").first, -100000);
    EXPECT_EQ(r.values.at("modbus.d").first, 3.5);
    EXPECT_EQ(r.values.at("modbus.e").first, 70000);
    EXPECT_EQ(in.modbus_health().state, ModbusLinkState::Ok);
    EXPECT_EQ(in.health().polled_links, "Modbus " + target() + " ok");
  }
  {
    // Unit 5: nobody answers. Each poll ends at the response timeout (100 ms), never later.
    const Mapping m = parse_mapping(rtu_registers(5, "100ms"), "rtu.map");
    ModbusInput in(target(), *m.modbus);
    LastValues r;
    const double longest = poll_n(in, r, 3);
    EXPECT_LT(longest, 400.0) << "a silent slave must cost one response timeout per poll";
    EXPECT_EQ(r.valid_count(), 0);
    EXPECT_EQ(r.values.size(), 5u);
    const ModbusHealth& h = in.modbus_health();
    EXPECT_EQ(h.state, ModbusLinkState::NoResponse) << describe(h);
    EXPECT_GE(h.no_response, 2u) << describe(h);
    EXPECT_EQ(h.last_error, "read a@0: Connection timed out");
    EXPECT_EQ(in.health().polled_links, "Modbus " + target() + " no-response (read a@0: Connection timed out)");
  }
  {
    // Unit 9: every answer's CRC is wrong.
    const Mapping m = parse_mapping(rtu_registers(9), "rtu.map");
    ModbusInput in(target(), *m.modbus);
    LastValues r;
    EXPECT_LT(poll_n(in, r, 3), 1000.0);  // ends with the bad answer, not at the timeout
    EXPECT_EQ(r.valid_count(), 0);
    const ModbusHealth& h = in.modbus_health();
    EXPECT_EQ(h.state, ModbusLinkState::BadFrame) << describe(h);
    EXPECT_GE(h.bad_frames, 2u) << describe(h);
    EXPECT_EQ(h.last_error, "read a@0: Invalid CRC");
  }
  {
    // After the bad frames the line carries no leftovers: unit 1 reads at its first poll.
    const Mapping m = parse_mapping(rtu_registers(1), "rtu.map");
    ModbusInput in(target(), *m.modbus);
    LastValues r;
    poll_n(in, r, 1);
    EXPECT_EQ(r.valid_count(), 5) << in.last_error();
  }
  {
    const Mapping m = parse_mapping(rtu_registers(1), "rtu.map");
    ModbusInput in("rtu:/nonexistent/ttyMETER:19200", *m.modbus);
    LastValues r;
    EXPECT_LT(poll_n(in, r, 3), 100.0);
    EXPECT_EQ(r.valid_count(), 0);
    EXPECT_EQ(in.modbus_health().state, ModbusLinkState::Unreachable);
    EXPECT_GE(in.modbus_health().unreachable, 2u);
    EXPECT_EQ(in.last_error(), "connect: No such file or directory");
  }
}

// Two Modbus inputs beside a CAN log, each with its own register table: the RTU slave's register
// (unit 1, 1234) and the TCP server's (1000 x 0.05 = 50 %) both reach their catalog signals.
TEST_F(ModbusRtu, SeveralModbusInputsAtOnceInTheRunLoop) {
  ASSERT_TRUE(peer_->started());
  const auto dir = std::filesystem::path(::testing::TempDir()) / ("modbus-several-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  struct Cleanup {
    std::filesystem::path dir;
    ~Cleanup() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } cleanup{dir};
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  std::ostringstream log;
  for (int k = 0; k < 20; ++k) log << format_candump_line(meter::controller::testing::frame(0x100, k * 25 * meter::controller::testing::ms, {0xE8, 0x03, 0, 0, 0, 0, 0, 0}), "can0") << "\n";
  const std::string map = write("several.map",
                                "[modbus pump]\npoll = 20ms\ntimeout = 1s\nunit = 1\n"
                                "[modbus.register pump.rpm]\naddress = 1\ntype = uint16\n"
                                "[modbus drive]\npoll = 20ms\ntimeout = 1s\n"
                                "[modbus.register drive.level]\naddress = 0\ntype = uint16\nscale = 0.05\n"
                                "[Vehicle.Speed]\nsource = clock.Speed.WheelA\nconvert = m/s->km/h\n"
                                "[Vehicle.Powertrain.CombustionEngine.Speed]\nsource = modbus.pump.rpm\n"
                                "[Vehicle.Powertrain.FuelSystem.RelativeLevel]\nsource = modbus.drive.level\n");
  RunOptions o;
  o.inputs = {"clock=log:" + write("clock.log", log.str()), "pump=modbus-" + target(),
              "drive=modbus-tcp:127.0.0.1:" + std::to_string(peer_->tcp_port())};
  o.dbcs = {"clock=" + write("clock.dbc", meter::controller::testing::kDbc)};
  o.map = map;
  o.exit_at_end = true;
  o.verbose = true;
  o.link = "unix:" + (dir / "link.sock").string();
  // The peer may still be starting: a run whose Modbus values are not valid yet is tried again.
  std::string err_text;
  for (int attempt = 0; attempt < 5; ++attempt) {
    std::ostringstream out, err;
    ASSERT_EQ(run_command(o, out, err), 0) << err.str();
    err_text = err.str();
    if (err_text.find("final Vehicle.Powertrain.CombustionEngine.Speed = 1234 (valid)") != std::string::npos) break;
  }
  EXPECT_NE(err_text.find("final Vehicle.Powertrain.CombustionEngine.Speed = 1234 (valid)"), std::string::npos) << err_text;
  EXPECT_NE(err_text.find("final Vehicle.Powertrain.FuelSystem.RelativeLevel = 50 (valid)"), std::string::npos) << err_text;
  EXPECT_NE(err_text.find("final Vehicle.Speed = 36 (valid)"), std::string::npos) << err_text;
  EXPECT_NE(err_text.find("Modbus " + target() + " ok; Modbus tcp:127.0.0.1:" + std::to_string(peer_->tcp_port()) + " ok"),
            std::string::npos)
      << err_text;

  // Several Modbus inputs read one table each: a second one without its own is refused by name.
  o.inputs.push_back("spare=modbus-tcp:127.0.0.1:1");
  std::ostringstream out2, err2;
  EXPECT_EQ(run_command(o, out2, err2), 1);
  EXPECT_NE(err2.str().find("--input spare=modbus-tcp:127.0.0.1:1: with several Modbus inputs each reads its own registers: " + map +
                            " needs [modbus spare] and [modbus.register spare.NAME] sections"),
            std::string::npos)
      << err2.str();
}
