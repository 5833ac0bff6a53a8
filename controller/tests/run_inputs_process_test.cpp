// Process level, several inputs: one meter-controller reads a CAN log and a Modbus TCP peer
// (python3-pymodbus) at once, and what it publishes carries values from both, on one clock.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "meter/controller/input/candump_line.hpp"
#include "meter/protocol/link.hpp"
#include "model_fixture.hpp"
#include "process_util.hpp"
#include "pymodbus_peer.hpp"

using namespace meter;
using namespace meter::controller::testing;
namespace sig = meter::protocol::sig;

TEST(ProcessInputs, CanLogAndModbusPeerInOneController) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-proc-inputs-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  PymodbusPeer peer;
  ASSERT_TRUE(peer.started());

  // 3 s of Speed frames every 20 ms, WheelA raw 4660 = 46.60 m/s = 167.76 km/h. Stamped in 2033
  // (2e9 s): far from CLOCK_MONOTONIC (the Modbus client's clock, seconds since boot), so a
  // register value left on its own clock would be 63 years old on the log's and time out at once.
  {
    std::ofstream log(dir / "body.log");
    for (int k = 0; k < 150; ++k)
      log << controller::format_candump_line(frame(256, 2000000000LL * 1000 * ms + k * 20 * ms, {0x34, 0x12, 0, 0, 0, 0, 0, 0}), "can0")
          << "\n";
  }
  std::ofstream(dir / "body.dbc") << kDbc;
  // pymodbus_server.py serves holding register 0 = int16 -5 and 1 = uint16 1234.
  std::ofstream(dir / "v.map") << "[modbus]\npoll = 50ms\ntimeout = 200ms\n"
                                  "[modbus.register coolant]\naddress = 0\ntype = int16\n"
                                  "[modbus.register rpm]\naddress = 1\ntype = uint16\n"
                                  "[Vehicle.Speed]\nsource = body.Speed.WheelA\nconvert = m/s->km/h\n"
                                  "[Vehicle.Powertrain.CombustionEngine.Speed]\nsource = modbus.rpm\n"
                                  "[Vehicle.Powertrain.CombustionEngine.ECT]\nsource = modbus.coolant\n";
  const std::string sock = (dir / "link.sock").string();
  pid_t pid = spawn({std::string(METER_BINARY_DIR) + "/bin/meter-controller", "run", "-v", "--input",
                     "body=log:" + (dir / "body.log").string(), "--input", "pump=modbus-tcp:127.0.0.1:" + std::to_string(peer.port()),
                     "--dbc", "body=" + (dir / "body.dbc").string(), "--map", (dir / "v.map").string(), "--link",
                     "unix:" + sock, "--exit-at-end", "--linger", "1"},
                    (dir / "stderr.txt").string());
  ASSERT_GT(pid, 0);
  protocol::Subscriber sub(protocol::Endpoint::parse("unix:" + sock));
  bool all_three = false;
  int status = -1;
  const bool exited = watch_until_exit(pid, std::chrono::seconds(20), [&] {
    sub.poll(std::chrono::milliseconds(20));
    if (!sub.link_up()) return;
    const auto speed = sub.get(sig::kSpeed), rpm = sub.get(sig::kEngineSpeed), ect = sub.get(sig::kCoolantTemp);
    // All three valid in one state: the bus value and both register values fresh at one time
    // (1e-6: the same arithmetic as the controller's, any rounding on the way stays far below).
    all_three |= speed.status == protocol::SignalStatus::Valid && std::abs(speed.value - 4660 * 0.01 * 3.6) < 1e-6 &&
                 rpm.status == protocol::SignalStatus::Valid && rpm.value == 1234 &&
                 ect.status == protocol::SignalStatus::Valid && ect.value == -5;
  }, status);
  const std::string err = slurp((dir / "stderr.txt").string());
  ASSERT_TRUE(exited) << err;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << err;
  EXPECT_TRUE(all_three) << "the link never carried the CAN speed and both Modbus values valid together\n" << err;
  EXPECT_NE(err.find("body: candump log (streamed, replay realtime)"), std::string::npos) << err;
  EXPECT_NE(err.find("pump: Modbus tcp:127.0.0.1:"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}
