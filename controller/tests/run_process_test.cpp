// Process level: replay the ft86 log from file into a running meter-controller and check what it
// publishes over the protocol link, with a protocol Subscriber.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <set>
#include <sstream>

#include "meter/controller/input/socketcan.hpp"
#include "meter/controller/persistence/odometer_store.hpp"
#include "meter/protocol/link.hpp"
#include "process_util.hpp"

using namespace meter;
using meter::controller::OdometerLoad;
using meter::controller::OdometerState;
using meter::controller::OdometerStore;
namespace sig = meter::protocol::sig;

using meter::controller::testing::slurp;
using meter::controller::testing::spawn;
using meter::controller::testing::watch_until_exit;

namespace {
const std::string kBin = std::string(METER_BINARY_DIR) + "/bin/meter-controller";
const std::string kSharedData = METER_SHARED_DIR;
const std::string kSrc = METER_SOURCE_DIR;

// Polls the subscriber (calling on_link_up while the link is up) until the controller exits or
// 'limit' passes; a controller still running then is killed. Returns whether it exited by itself.
template <class OnLinkUp>
bool watch_until_exit(pid_t pid, protocol::Subscriber& sub, std::chrono::seconds limit, OnLinkUp on_link_up,
                      int& status) {
  return meter::controller::testing::watch_until_exit(pid, limit, [&] {
    sub.poll(std::chrono::milliseconds(20));
    if (sub.link_up()) on_link_up();
  }, status);
}
}  // namespace

TEST(Process, Ft86ReplayPublishesTheLogValues) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-proc-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string sock = (dir / "link.sock").string();
  pid_t pid = spawn({kBin, "run", "--dbc", kSharedData + "/data/can/ft86_motec/sample_can_spec.dbc", "--map",
                     kSrc + "/controller/vehicles/ft86/ft86.map", "--input", "log:" + kSharedData + "/data/can/ft86_motec/can_sample.log",
                     "--replay", "scale:30", "--link", "unix:" + sock, "--state-dir", (dir / "state").string(),
                     "--exit-at-end", "--linger", "1.5"},
                    (dir / "stderr.txt").string());
  ASSERT_GT(pid, 0);
  protocol::Subscriber sub(protocol::Endpoint::parse("unix:" + sock));
  std::set<int> gears;
  double max_rpm = 0, max_speed = 0;
  bool saw_bulb = false;
  int status = -1;
  protocol::SignalState rpm, speed, gear, coolant, fuel, odo;
  const bool exited = watch_until_exit(pid, sub, std::chrono::seconds(20), [&] {
    rpm = sub.get(sig::kEngineSpeed);
    speed = sub.get(sig::kSpeed);
    gear = sub.get(sig::kCurrentGear);
    coolant = sub.get(sig::kCoolantTemp);
    fuel = sub.get(sig::kFuelLevel);
    odo = sub.get(sig::kOdometer);
    if (gear.status == protocol::SignalStatus::Valid) gears.insert(static_cast<int>(gear.value));
    if (rpm.status == protocol::SignalStatus::Valid) max_rpm = std::max(max_rpm, rpm.value);
    if (speed.status == protocol::SignalStatus::Valid) max_speed = std::max(max_speed, speed.value);
    saw_bulb |= sub.get(sig::kParkingBrake).value == 1.0 && sub.get(sig::kFuelLow).value == 1.0;
  }, status);
  const std::string err = slurp((dir / "stderr.txt").string());
  ASSERT_TRUE(exited) << "controller did not finish the log in time; stderr:\n" << err;
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << err;
  // Final state (held during --linger) against the log's last frames (expected_canmatrix_stats.csv):
  EXPECT_EQ(rpm.status, protocol::SignalStatus::Valid);
  EXPECT_EQ(rpm.value, 3160.0);               // ID_140.RPM last
  EXPECT_EQ(gear.value, 6.0);                 // ID_141.GEAR last
  EXPECT_EQ(coolant.value, 90.0);             // ID_360.COOLANT_TEMP last
  EXPECT_EQ(fuel.value, 100.0);               // 62.345 l clamped to the DBC's 61 l = full
  // Mean of the last wheel speeds (35.2699, 35.2699, 35.1768, 35.1923 m/s) in km/h; the needle has
  // settled on the steady final cruise within 1 km/h.
  EXPECT_NEAR(speed.value, (35.2699 + 35.2699 + 35.1768 + 35.1923) / 4 * 3.6, 1.0);
  EXPECT_NEAR(max_rpm, 6030.0, 400.0);        // sampled while the replay runs 30x fast
  EXPECT_GE(gears.size(), 4u);
  EXPECT_GT(max_speed, 100.0);
  // ~90 s averaging ~70 km/h: the odometer must hold the distance the log drove (0.1 km steps).
  EXPECT_GT(odo.value, 0.5);
  EXPECT_LT(odo.value, 3.0);
  EXPECT_TRUE(std::filesystem::exists(dir / "state" / "odometer.a"));  // the first of the two copies
  std::filesystem::remove_all(dir);
}

TEST(Process, SocketCanWithoutKernelSupportNamesTheVmHarness) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-proc-can-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  pid_t pid = spawn({kBin, "run", "--dbc", kSrc + "/controller/vehicles/demo/demo.dbc", "--map",
                     kSrc + "/controller/vehicles/demo/demo.map", "--input", "can:meternone0", "--link",
                     "unix:" + (dir / "l.sock").string()},
                    (dir / "stderr.txt").string());
  int status;
  ::waitpid(pid, &status, 0);
  const std::string err = slurp((dir / "stderr.txt").string());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3) << err;
  if (controller::kernel_has_can()) {
    EXPECT_NE(err.find("no such CAN interface"), std::string::npos) << err;
  } else {
    EXPECT_NE(err.find("no SocketCAN support"), std::string::npos) << err;
    EXPECT_NE(err.find("vcan/"), std::string::npos) << err;
  }
  std::filesystem::remove_all(dir);
}

TEST(Process, CliErrorsAndDecode) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-proc-cli-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  // A broken mapping: exit code 1 and file:line in the message.
  { std::FILE* f = std::fopen((dir / "bad.map").c_str(), "w"); std::fputs("[Vehicle.Speed]\nsource = X.Y\n", f); std::fclose(f); }
  pid_t pid = spawn({kBin, "run", "--dbc", kSrc + "/controller/vehicles/demo/demo.dbc", "--map", (dir / "bad.map").string(),
                     "--input", "log:" + kSrc + "/vcan/logs/demo-drive.log", "--link", "unix:" + (dir / "l.sock").string()},
                    (dir / "stderr.txt").string());
  int status;
  ::waitpid(pid, &status, 0);
  std::string err = slurp((dir / "stderr.txt").string());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_NE(err.find("bad.map:1"), std::string::npos) << err;
  EXPECT_NE(err.find("no message 'X'"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}

TEST(Process, AViewThatStopsReadingNeverStallsTheBus) {
  // A view that handshakes and then never reads again: the controller must keep replaying at
  // full pace (latest-value coalescing in the Publisher), and finish on time.
  auto dir = std::filesystem::temp_directory_path() / ("meter-proc-slow-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string sock = (dir / "link.sock").string();
  const auto t0 = std::chrono::steady_clock::now();
  pid_t pid = spawn({kBin, "run", "--dbc", kSrc + "/controller/vehicles/demo/demo.dbc", "--map",
                     kSrc + "/controller/vehicles/demo/demo.map", "--input", "log:" + kSrc + "/vcan/logs/demo-drive.log",
                     "--replay", "scale:20", "--link", "unix:" + sock, "--exit-at-end"},
                    (dir / "stderr.txt").string());
  protocol::Subscriber stuck(protocol::Endpoint::parse("unix:" + sock));
  for (int i = 0; i < 200 && !stuck.link_up(); ++i) stuck.poll(std::chrono::milliseconds(10));
  ASSERT_TRUE(stuck.link_up()) << slurp((dir / "stderr.txt").string());
  // From here on the view never polls again.
  int status = -1;
  bool exited = false;
  while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(15)) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;
      break;
    }
    ::usleep(20000);
  }
  if (!exited) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
  }
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(exited) << "the controller stalled behind a view that does not read";
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp((dir / "stderr.txt").string());
  EXPECT_LT(took, 8.0);  // 60 s of log at 20x = 3 s, plus start-up; a blocked writer would never end
  std::filesystem::remove_all(dir);
}

TEST(Process, DecodeWithMapWritesOnlyMappedSignals) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-proc-dec-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string out = (dir / "out.csv").string();
  pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen(out.c_str(), "w", stdout);
    ::execl(kBin.c_str(), kBin.c_str(), "decode", "--dbc", (kSrc + "/controller/vehicles/demo/demo.dbc").c_str(),
            (kSrc + "/vcan/logs/demo-drive.log").c_str(), "--map", (kSrc + "/controller/vehicles/demo/demo.map").c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status;
  ::waitpid(pid, &status, 0);
  ASSERT_EQ(WEXITSTATUS(status), 0);
  std::string csv = slurp(out);
  EXPECT_EQ(csv.rfind("timestamp,message,signal,raw,physical,unit,status\n", 0), 0u);
  EXPECT_NE(csv.find(",ESP_WheelSpeeds,VehicleSpeed,13000,130,km/h,valid\n"), std::string::npos);
  EXPECT_EQ(csv.find("ThrottlePos"), std::string::npos);    // not used by demo.map
  EXPECT_EQ(csv.find("WheelSpeedFL"), std::string::npos);
  EXPECT_EQ(csv.find(",not_"), std::string::npos);
  std::filesystem::remove_all(dir);
}

namespace {
// A one-second candump log of the demo vehicle: engine status every 10 ms (2000 rpm) and wheel
// speeds every 20 ms (50 km/h), so every mapped value is valid while it plays.
std::string write_short_demo_log(const std::filesystem::path& dir) {
  const std::string path = (dir / "short.log").string();
  std::FILE* f = std::fopen(path.c_str(), "w");
  for (int i = 0; i < 100; ++i) {
    std::fprintf(f, "(%d.%06d) vcan0 0C9#401F010000000000\n", 1000, i * 10000);        // 8000 x 0.25 = 2000 rpm
    if (i % 2 == 0) std::fprintf(f, "(%d.%06d) vcan0 1A0#1388000000000000\n", 1000, i * 10000 + 1);  // 50.00 km/h
  }
  std::fclose(f);
  return path;
}
void write_text(const std::filesystem::path& p, const std::string& text) {
  std::FILE* f = std::fopen(p.c_str(), "w");
  std::fputs(text.c_str(), f);
  std::fclose(f);
}
}  // namespace

// When a replayed log ends without --exit-at-end, the controller keeps running and the bus is
// silent: every value must time out as it would on a live bus whose senders stopped.
TEST(Process, EndOfLogTimesOutLikeASilentBusAndStaysUp) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-proc-eol-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string sock = (dir / "link.sock").string();
  pid_t pid = spawn({kBin, "run", "--dbc", kSrc + "/controller/vehicles/demo/demo.dbc", "--map",
                     kSrc + "/controller/vehicles/demo/demo.map", "--input", "log:" + write_short_demo_log(dir),
                     "--replay", "realtime", "--link", "unix:" + sock},
                    (dir / "stderr.txt").string());
  ASSERT_GT(pid, 0);
  protocol::Subscriber sub(protocol::Endpoint::parse("unix:" + sock));
  bool saw_valid = false, timed_out = false;
  // The log lasts 1 s; the demo speed times out 3 x 20 ms after its last frame. 4 s is ample.
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (std::chrono::steady_clock::now() < until && !timed_out) {
    sub.poll(std::chrono::milliseconds(20));
    if (!sub.link_up()) continue;
    const auto speed = sub.get(sig::kSpeed), rpm = sub.get(sig::kEngineSpeed);
    saw_valid |= speed.status == protocol::SignalStatus::Valid && rpm.status == protocol::SignalStatus::Valid;
    timed_out = saw_valid && speed.status == protocol::SignalStatus::TimedOut && rpm.status == protocol::SignalStatus::TimedOut;
  }
  const bool still_running = ::waitpid(pid, nullptr, WNOHANG) == 0;
  ::kill(pid, SIGTERM);
  int status = -1;
  ::waitpid(pid, &status, 0);
  const std::string err = slurp((dir / "stderr.txt").string());
  EXPECT_TRUE(saw_valid) << err;
  EXPECT_TRUE(timed_out) << "speed and rpm still " << protocol::to_string(sub.get(sig::kSpeed).status) << " / "
                         << protocol::to_string(sub.get(sig::kEngineSpeed).status) << " 4 s after the log ended\n" << err;
  EXPECT_TRUE(still_running) << err;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << err;
  std::filesystem::remove_all(dir);
}

// A damaged odometer state (both copies) must not keep the cluster from starting: the controller
// runs, publishes the odometer as invalid (the view's failsafe look) and reports the fault.
TEST(Process, DamagedOdometerStateKeepsTheControllerRunning) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-proc-odo-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "state");
  write_text(dir / "odo.map", "[Vehicle.Speed]\nsource = ESP_WheelSpeeds.VehicleSpeed\n[Vehicle.TraveledDistance]\naccumulate = speed\n");
  const std::string damaged = "meter-odometer 1\nodo_um 1000000000\ntrip_um 0\nseq 3\ncrc 00000000\n";
  write_text(dir / "state" / "odometer.state", damaged);
  write_text(dir / "state" / "odometer.a", damaged);
  write_text(dir / "state" / "odometer.b", damaged);
  const std::string sock = (dir / "link.sock").string();
  pid_t pid = spawn({kBin, "run", "--dbc", kSrc + "/controller/vehicles/demo/demo.dbc", "--map", (dir / "odo.map").string(),
                     "--input", "log:" + write_short_demo_log(dir), "--replay", "realtime", "--link", "unix:" + sock,
                     "--state-dir", (dir / "state").string(), "--exit-at-end", "--linger", "0.5"},
                    (dir / "stderr.txt").string());
  ASSERT_GT(pid, 0);
  protocol::Subscriber sub(protocol::Endpoint::parse("unix:" + sock));
  protocol::SignalState odo;
  bool saw_speed = false;
  int status = -1;
  const bool exited = watch_until_exit(pid, sub, std::chrono::seconds(10), [&] {
    odo = sub.get(sig::kOdometer);
    saw_speed |= sub.get(sig::kSpeed).status == protocol::SignalStatus::Valid;
  }, status);
  const std::string err = slurp((dir / "stderr.txt").string());
  ASSERT_TRUE(exited && WIFEXITED(status)) << err;
  EXPECT_EQ(WEXITSTATUS(status), 0) << err;
  EXPECT_TRUE(saw_speed) << err;
  EXPECT_EQ(odo.status, protocol::SignalStatus::Invalid) << err;
  EXPECT_NE(err.find("odometer"), std::string::npos) << err;
  EXPECT_NE(err.find("CRC"), std::string::npos) << err;
  EXPECT_NE(slurp((dir / "stderr.txt").string()).find("odometer-reset"), std::string::npos) << err;
  // The explicit reset accepts a distance again; the next start restores it.
  pid_t reset = spawn({kBin, "odometer-reset", "--state-dir", (dir / "state").string(), "--km", "1234.5"},
                      (dir / "reset.txt").string());
  ::waitpid(reset, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp((dir / "reset.txt").string());
  const OdometerLoad after = OdometerStore((dir / "state").string()).load();
  ASSERT_EQ(after.state, OdometerState::Restored);
  EXPECT_EQ(after.record->odo_um, 1234500000000LL);
  std::filesystem::remove_all(dir);
}
