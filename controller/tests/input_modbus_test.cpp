// The Modbus client against a loopback libmodbus server (in a thread of this test) and against
// python3-pymodbus as an independent peer.
#include <gtest/gtest.h>
#include <modbus.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <map>
#include <thread>

#include "meter/controller/input/modbus_health.hpp"
#include "meter/controller/input/modbus_input.hpp"
#include "meter/controller/input/modbus_registers.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "pymodbus_peer.hpp"

using namespace meter::controller;

namespace {

const char* kRegisters =
    "[modbus]\npoll = 20ms\ntimeout = 150ms\n"
    "[modbus.register a]\naddress = 0\ntype = int16\n"
    "[modbus.register b]\naddress = 1\ntype = uint16\nscale = 0.1\n"
    "[modbus.register c]\naddress = 2\ntype = int32\n"
    "[modbus.register d]\naddress = 4\ntype = float32\nword_order = low_first\n"
    "[modbus.register e]\ntable = input\naddress = 0\ntype = uint32\n";

struct Rec : InputSink {
  std::map<std::string, std::pair<double, bool>> last;
  int invalid_batches = 0;
  void on_frame(const CanFrame&) override {}
  void on_value(std::string_view k, double v, bool valid, std::int64_t) override {
    last[std::string(k)] = {v, valid};
  }
  bool all_valid() const {
    if (last.empty()) return false;
    for (auto& [k, v] : last)
      if (!v.second) return false;
    return true;
  }
  bool all_invalid() const {
    if (last.empty()) return false;
    for (auto& [k, v] : last)
      if (v.second) return false;
    return true;
  }
};

// Minimal libmodbus TCP server: one client at a time; can be told to go mute (timeouts).
class LoopbackServer {
 public:
  LoopbackServer() {
    ctx_ = modbus_new_tcp("127.0.0.1", 0);
    map_ = modbus_mapping_new(0, 0, 16, 4);
    const std::uint16_t hr[] = {0xFFFB, 1234, 0xFFFE, 0x7960, 0x0000, 0x4060};
    for (int i = 0; i < 6; ++i) map_->tab_registers[i] = hr[i];
    map_->tab_input_registers[0] = 0x0001;
    map_->tab_input_registers[1] = 0x1170;
    listen_ = modbus_tcp_listen(ctx_, 1);
    sockaddr_in a{};
    socklen_t len = sizeof a;
    getsockname(listen_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] { serve(); });
  }
  ~LoopbackServer() {
    stop_ = true;
    ::shutdown(listen_, SHUT_RDWR);
    if (client_ >= 0) ::shutdown(client_, SHUT_RDWR);
    thread_.join();
    ::close(listen_);
    modbus_mapping_free(map_);
    modbus_free(ctx_);
  }
  int port() const { return port_; }
  std::atomic<bool> mute{false};
  std::atomic<int> heartbeat_step{1};

 private:
  void serve() {
    std::uint8_t q[MODBUS_TCP_MAX_ADU_LENGTH];
    while (!stop_) {
      int s = listen_;
      client_ = modbus_tcp_accept(ctx_, &s);
      if (client_ < 0) return;
      for (;;) {
        int rc = modbus_receive(ctx_, q);
        if (rc <= 0) break;
        map_->tab_registers[10] = static_cast<std::uint16_t>(map_->tab_registers[10] + heartbeat_step.load());
        if (!mute) modbus_reply(ctx_, q, rc, map_);
      }
      ::close(client_);
      client_ = -1;
    }
  }
  modbus_t* ctx_;
  modbus_mapping_t* map_;
  int listen_ = -1, port_ = 0;
  std::atomic<int> client_{-1};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

void run_polls(ModbusInput& in, Rec& r, int n) {
  for (int i = 0; i < n; ++i) in.poll(r, std::chrono::milliseconds(20));
}

void expect_values(const Rec& r) {
  ASSERT_TRUE(r.all_valid());
  EXPECT_EQ(r.last.at("modbus.a").first, -5);
  EXPECT_NEAR(r.last.at("modbus.b").first, 123.4, 1e-9);
  EXPECT_EQ(r.last.at("modbus.c").first, -100000);
  EXPECT_EQ(r.last.at("modbus.d").first, 3.5);
  EXPECT_EQ(r.last.at("modbus.e").first, 70000);
}

}  // namespace

TEST(ModbusRegisters, DecodeTypesAndWordOrder) {
  ModbusRegister r;
  r.type = RegisterType::Float32;
  std::uint16_t w[2] = {0x4060, 0x0000};
  EXPECT_EQ(modbus_register_value(r, w), 3.5);
  r.word_swap = true;
  std::uint16_t s[2] = {0x0000, 0x4060};
  EXPECT_EQ(modbus_register_value(r, s), 3.5);
  r = {};
  r.type = RegisterType::Int16;
  r.scale = 0.5;
  r.offset = 10;
  std::uint16_t n[1] = {0xFFFE};
  EXPECT_EQ(modbus_register_value(r, n), 9.0);
}

// One poll's words interpreted without a connection: a NaN float register reads invalid, and an
// unchanged heartbeat invalidates the poll once it has been the same for stale_after polls.
TEST(ModbusRegisters, InterpretPollMarksNonFiniteInvalidAndStaleHeartbeat) {
  ModbusConfig cfg;
  cfg.heartbeat = "hb";
  cfg.stale_after_polls = 2;
  cfg.registers.resize(2);
  cfg.registers[0].name = "hb";
  cfg.registers[1].name = "f";
  cfg.registers[1].type = RegisterType::Float32;
  ModbusHeartbeat hb;
  std::vector<ModbusReading> out;
  std::vector<std::array<std::uint16_t, 2>> words{{1, 0}, {0x7FC0, 0x0000}};  // quiet NaN
  ASSERT_TRUE(interpret_modbus_poll(cfg, words, hb, out));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(out[0].valid);
  EXPECT_EQ(out[0].value, 1.0);
  EXPECT_FALSE(out[1].valid);
  EXPECT_TRUE(interpret_modbus_poll(cfg, words, hb, out));   // the same once
  EXPECT_FALSE(interpret_modbus_poll(cfg, words, hb, out));  // the same twice: stale
  EXPECT_TRUE(out.empty());
  words[0] = {2, 0};
  EXPECT_TRUE(interpret_modbus_poll(cfg, words, hb, out));   // changed again: fresh
}

TEST(ModbusClient, LoopbackServerValuesTimeoutExceptionAndStaleHeartbeat) {
  LoopbackServer server;
  Mapping m = parse_mapping(kRegisters, "test.map");
  {
    ModbusInput in("tcp:127.0.0.1:" + std::to_string(server.port()), *m.modbus);
    Rec r;
    run_polls(in, r, 3);
    expect_values(r);
    EXPECT_EQ(in.modbus_health().state, ModbusLinkState::Ok);
    server.mute = true;  // requests go unanswered: response timeout
    run_polls(in, r, 2);
    EXPECT_TRUE(r.all_invalid()) << in.last_error();
    EXPECT_GT(in.failures(), 0u);
    EXPECT_EQ(in.modbus_health().state, ModbusLinkState::NoResponse) << describe(in.modbus_health());
    server.mute = false;
    for (int i = 0; i < 50 && !r.all_valid(); ++i) in.poll(r, std::chrono::milliseconds(20));
    expect_values(r);  // recovers after reconnecting
  }
  {
    // A register the server does not have: exception response -> every signal invalid.
    Mapping bad = parse_mapping(std::string(kRegisters) + "[modbus.register z]\naddress = 200\n", "test.map");
    ModbusInput in("tcp:127.0.0.1:" + std::to_string(server.port()), *bad.modbus);
    Rec r;
    run_polls(in, r, 2);
    EXPECT_TRUE(r.all_invalid());
    EXPECT_NE(in.last_error().find("z@200"), std::string::npos) << in.last_error();
    EXPECT_EQ(in.modbus_health().state, ModbusLinkState::Exception);
    EXPECT_EQ(in.health().polled_links, "Modbus tcp:127.0.0.1:" + std::to_string(server.port()) + " exception (" + in.last_error() + ")");
  }
  {
    Mapping hb = parse_mapping(std::string(kRegisters) + "[modbus.register hb]\naddress = 10\n[modbus]\nheartbeat = hb\nstale_after = 3\n", "test.map");
    ModbusInput in("tcp:127.0.0.1:" + std::to_string(server.port()), *hb.modbus);
    Rec r;
    run_polls(in, r, 5);
    EXPECT_TRUE(r.all_valid());  // heartbeat advancing
    server.heartbeat_step = 0;   // the device's logic stalled, its Modbus stack still answers
    run_polls(in, r, 6);
    EXPECT_TRUE(r.all_invalid());
    EXPECT_NE(in.last_error().find("stale"), std::string::npos);
    EXPECT_EQ(in.modbus_health().state, ModbusLinkState::StaleHeartbeat);
    server.heartbeat_step = 1;
    run_polls(in, r, 3);
    EXPECT_TRUE(r.all_valid());
    EXPECT_EQ(in.modbus_health().state, ModbusLinkState::Ok);
    EXPECT_GE(in.modbus_health().stale_heartbeats, 1u);  // the counts and the last error outlive the recovery
  }
}

TEST(ModbusClient, UnreachableServerMarksEverythingInvalid) {
  Mapping m = parse_mapping(kRegisters, "test.map");
  ModbusInput in("tcp:127.0.0.1:1", *m.modbus);
  Rec r;
  run_polls(in, r, 1);
  EXPECT_TRUE(r.all_invalid());
  EXPECT_EQ(in.modbus_health().state, ModbusLinkState::Unreachable);
  EXPECT_EQ(in.last_error(), "connect: Connection refused");
  EXPECT_THROW(ModbusInput("udp:x", *m.modbus), std::invalid_argument);
  EXPECT_THROW(ModbusInput("rtu:/dev/null:0", *m.modbus), std::invalid_argument);
}

TEST(ModbusClient, AgainstPymodbusPeer) {
  meter::controller::testing::PymodbusPeer peer;
  ASSERT_TRUE(peer.started());
  Mapping m = parse_mapping(kRegisters, "test.map");
  ModbusInput in("tcp:127.0.0.1:" + std::to_string(peer.port()), *m.modbus);
  Rec r;
  // The Python interpreter needs a moment to start listening; the client reconnects each poll.
  for (int i = 0; i < 400 && !r.all_valid(); ++i) in.poll(r, std::chrono::milliseconds(25));
  expect_values(r);
}

// What each failed read means: libmodbus's errno sorted into the link's states, and the polls folded
// into counts that outlive a recovery.
TEST(ModbusHealth, ReadErrorsClassifiedAndPollsCounted) {
  EXPECT_EQ(classify_modbus_read_error(ETIMEDOUT), ModbusLinkState::NoResponse);
  for (int e : {EMBBADCRC, EMBBADDATA, EMBBADEXC, EMBMDATA, EMBBADSLAVE, EMBUNKEXC})
    EXPECT_EQ(classify_modbus_read_error(e), ModbusLinkState::BadFrame) << modbus_strerror(e);
  for (int e : {EMBXILFUN, EMBXILADD, EMBXILVAL, EMBXSFAIL, EMBXSBUSY, EMBXGPATH, EMBXGTAR})
    EXPECT_EQ(classify_modbus_read_error(e), ModbusLinkState::Exception) << modbus_strerror(e);
  for (int e : {EPIPE, ECONNRESET, EBADF, EIO}) EXPECT_EQ(classify_modbus_read_error(e), ModbusLinkState::Unreachable) << e;

  ModbusHealth h;
  EXPECT_EQ(describe(h), "not-polled: 0 of 0 polls failed (0 unreachable, 0 no response, 0 bad frames, 0 exceptions, 0 stale heartbeats)");
  note_modbus_poll(h, ModbusLinkState::Ok);
  note_modbus_poll(h, ModbusLinkState::NoResponse, "read a@0: Connection timed out");
  note_modbus_poll(h, ModbusLinkState::BadFrame, "read a@0: Invalid CRC");
  EXPECT_EQ(h.state, ModbusLinkState::BadFrame);
  note_modbus_poll(h, ModbusLinkState::Ok);
  EXPECT_EQ(h.state, ModbusLinkState::Ok);
  EXPECT_EQ(h.polls, 4u);
  EXPECT_EQ(h.failed_polls(), 2u);
  EXPECT_EQ(describe(h), "ok: 2 of 4 polls failed (0 unreachable, 1 no response, 1 bad frames, 0 exceptions, 0 stale heartbeats), "
                         "last error: read a@0: Invalid CRC");
}

// Several Modbus inputs: [modbus INPUT] and [modbus.register INPUT.NAME] make a table per input,
// its values delivered as modbus.INPUT.NAME; the one [modbus] table stays as it was.
TEST(ModbusRegisters, NamedInputTablesInTheMapping) {
  const Mapping m = parse_mapping(
      "[modbus]\npoll = 50ms\n[modbus.register a]\naddress = 3\n"
      "[modbus pump]\npoll = 20ms\nunit = 7\n[modbus.register pump.rpm]\naddress = 1\n"
      "[modbus.register drive.level]\naddress = 0\nscale = 0.05\n"
      "[Vehicle.Speed]\nsource = modbus.a\n"
      "[Vehicle.Powertrain.CombustionEngine.Speed]\nsource = modbus.pump.rpm\n"
      "[Vehicle.Powertrain.FuelSystem.RelativeLevel]\nsource = modbus.drive.level\n",
      "several.map");
  ASSERT_TRUE(m.modbus);
  ASSERT_EQ(m.modbus_inputs.size(), 2u);
  const ModbusConfig& pump = m.modbus_inputs.at("pump");
  EXPECT_EQ(pump.input, "pump");
  EXPECT_EQ(pump.unit_id, 7);
  EXPECT_EQ(pump.poll_s, 0.02);
  ASSERT_EQ(pump.registers.size(), 1u);
  EXPECT_EQ(pump.source_key(pump.registers[0]), "modbus.pump.rpm");
  EXPECT_EQ(m.modbus->source_key(m.modbus->registers[0]), "modbus.a");
  EXPECT_EQ(m.modbus_table_of("modbus.pump.rpm"), &pump);
  EXPECT_EQ(m.modbus_table_of("modbus.drive.level"), &m.modbus_inputs.at("drive"));
  EXPECT_EQ(m.modbus_table_of("modbus.a"), &*m.modbus);
  EXPECT_EQ(m.modbus_table_of("modbus.pump.a"), nullptr);
  EXPECT_EQ(m.modbus_table_of("modbus.rpm"), nullptr);

  auto error = [](const std::string& text) {
    try {
      parse_mapping(text, "bad.map");
    } catch (const MappingError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("[modbus.register pump.rpm]\naddress = 1\n[Vehicle.Speed]\nsource = modbus.drive.rpm\n")
                .find("source modbus.drive.rpm names no [modbus.register drive.rpm]"),
            std::string::npos);
  EXPECT_NE(error("[modbus.register pump.]\n").find("expected [modbus.register NAME] or [modbus.register INPUT.NAME]"), std::string::npos);
  EXPECT_NE(error("[modbus.register a.b.c]\n").find("expected [modbus.register NAME] or [modbus.register INPUT.NAME]"), std::string::npos);
  EXPECT_NE(error("[modbus a.b]\n").find("expected [modbus INPUT], INPUT an --input name"), std::string::npos);
  EXPECT_NE(error("[modbus.register pump.x]\n[modbus.register pump.x]\n").find("register 'x' defined twice"), std::string::npos);
  EXPECT_NE(error("[modbus pump]\nheartbeat = hb\n[modbus.register pump.x]\n").find("[modbus pump] heartbeat 'hb' names no register"),
            std::string::npos);
}
