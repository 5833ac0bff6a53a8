// The odometer on storage that fails the way real storage does: a directory that turns read-only
// and a full disk, each on a small tmpfs the test mounts (root in the test container), and two
// damaged copies at start. The controller's model must keep running, report the fault once, and
// lose nothing that was already persisted.
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/model/model.hpp"
#include "meter/controller/persistence/odometer_store.hpp"
#include "model_fixture.hpp"

using namespace meter::controller;
using namespace meter::controller::testing;
using meter::protocol::SignalStatus;
namespace sig = meter::protocol::sig;

namespace {

// A 64 KiB tmpfs mounted for the test; unmounted (and its folder removed) at the end.
class SmallFs {
 public:
  explicit SmallFs(const std::string& name)
      : dir_(std::filesystem::temp_directory_path() / ("meter-smallfs-" + name + "-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir_);
    if (::mount("tmpfs", dir_.c_str(), "tmpfs", 0, "size=64k") != 0) error_ = std::strerror(errno);
  }
  ~SmallFs() {
    if (error_.empty()) ::umount2(dir_.c_str(), MNT_DETACH);
    std::filesystem::remove_all(dir_);
  }
  const std::string& error() const { return error_; }
  std::string path() const { return dir_.string(); }
  bool remount(bool read_only) {
    return ::mount("tmpfs", dir_.c_str(), "tmpfs", MS_REMOUNT | (read_only ? MS_RDONLY : 0), "size=64k") == 0;
  }

 private:
  std::filesystem::path dir_;
  std::string error_;
};

const char* kOdoMap = "[global]\npersist_interval = 1s\n[Vehicle.Speed]\nsource = Speed.WheelA\nconvert = m/s->km/h\n"
                      "[Vehicle.TraveledDistance]\naccumulate = speed\n";

// 90 km/h (25 m/s) from t0 for 'seconds' in 10 ms ticks.
void drive(Model& m, std::int64_t t0_ms, int seconds) {
  for (std::int64_t t = t0_ms; t <= t0_ms + seconds * 1000; t += 10) {
    m.on_frame(frame(256, t * ms, {0xC4, 0x09, 0, 0, 0, 0, 0, 0}));
    m.update(t * ms);
  }
}

std::int64_t stored_um(const std::string& dir) {
  const OdometerLoad l = OdometerStore(dir).load();
  return l.record ? l.record->odo_um : -1;
}

}  // namespace

TEST(OdometerMedium, ReadOnlyDirectoryKeepsRunningAndLosesNothingPersisted) {
  SmallFs fs("ro");
  // A real small filesystem: the test runs as root (as CI does), so a failed mount is a failure.
  ASSERT_TRUE(fs.error().empty()) << "cannot mount a 64 KiB tmpfs (" << fs.error() << "): the test needs root";
  Database db = parse_dbc(kDbc, "t.dbc");
  std::vector<std::string> reports;
  Model m(&db, parse_mapping(kOdoMap), ModelOptions{fs.path() + "/state", [&](const std::string& r) { reports.push_back(r); }});
  m.start(0);
  drive(m, 0, 5);
  const std::int64_t before = stored_um(fs.path() + "/state");
  ASSERT_GT(before, 0);
  ASSERT_TRUE(fs.remount(true)) << std::strerror(errno);
  drive(m, 5010, 5);  // 5 persistence intervals, every save refused by the file system
  EXPECT_GE(m.stats().persist_errors, 4u);
  ASSERT_EQ(reports.size(), 1u);  // reported once, not every interval
  EXPECT_NE(reports[0].find("Read-only file system"), std::string::npos) << reports[0];
  EXPECT_EQ(stored_um(fs.path() + "/state"), before);  // what was persisted is still there
  EXPECT_EQ(m.output(sig::kOdometer)->status, SignalStatus::Valid);
  ASSERT_TRUE(fs.remount(false));
  drive(m, 10010, 2);
  ASSERT_EQ(reports.size(), 2u);
  EXPECT_NE(reports[1].find("works again"), std::string::npos) << reports[1];
  EXPECT_GE(stored_um(fs.path() + "/state"), m.odometer().total_um() - 25LL * 1000000);  // within 1 s at 25 m/s
}

TEST(OdometerMedium, FullDiskKeepsRunningAndLosesNothingPersisted) {
  SmallFs fs("full");
  // A real small filesystem: the test runs as root (as CI does), so a failed mount is a failure.
  ASSERT_TRUE(fs.error().empty()) << "cannot mount a 64 KiB tmpfs (" << fs.error() << "): the test needs root";
  Database db = parse_dbc(kDbc, "t.dbc");
  std::vector<std::string> reports;
  Model m(&db, parse_mapping(kOdoMap), ModelOptions{fs.path() + "/state", [&](const std::string& r) { reports.push_back(r); }});
  m.start(0);
  drive(m, 0, 3);
  const std::int64_t before = stored_um(fs.path() + "/state");
  ASSERT_GT(before, 0);
  {  // fill the file system to the last byte
    std::ofstream filler(fs.path() + "/filler", std::ios::binary);
    const std::string block(4096, 'x');
    while (filler.write(block.data(), static_cast<std::streamsize>(block.size()))) filler.flush();
  }
  {
    std::ofstream tail(fs.path() + "/filler2", std::ios::binary);
    while (tail.put('x')) tail.flush();
  }
  drive(m, 3010, 4);
  EXPECT_GE(m.stats().persist_errors, 3u);
  ASSERT_GE(reports.size(), 1u);
  EXPECT_NE(reports[0].find("No space left on device"), std::string::npos) << reports[0];
  EXPECT_EQ(stored_um(fs.path() + "/state"), before);
  EXPECT_FALSE(std::filesystem::exists(fs.path() + "/state/odometer.a.tmp"));  // no half-written leftovers
  EXPECT_FALSE(std::filesystem::exists(fs.path() + "/state/odometer.b.tmp"));
  std::filesystem::remove(fs.path() + "/filler");
  std::filesystem::remove(fs.path() + "/filler2");
  drive(m, 7010, 2);
  EXPECT_NE(reports.back().find("works again"), std::string::npos) << reports.back();
  EXPECT_GE(stored_um(fs.path() + "/state"), m.odometer().total_um() - 25LL * 1000000);
}

// Both copies damaged at start: the model runs, the odometer and trip are invalid (the cluster's
// failsafe look), the fault is reported, and the damaged copies are not overwritten.
TEST(OdometerMedium, BothCopiesDamagedShowInvalidAndAreKept) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-odo-model-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string damaged = "meter-odometer 2\nodo_um 99\ntrip_um 0\nseq 3\npeer 2\ncrc 00000000\n";
  std::ofstream(dir / "odometer.a") << damaged;
  std::ofstream(dir / "odometer.b") << "";
  Database db = parse_dbc(kDbc, "t.dbc");
  std::vector<std::string> reports;
  Model m(&db, parse_mapping(kOdoMap), ModelOptions{dir.string(), [&](const std::string& r) { reports.push_back(r); }});
  m.start(0);
  drive(m, 0, 3);
  m.persist_now();
  EXPECT_EQ(m.output(sig::kOdometer)->status, SignalStatus::Invalid);
  EXPECT_EQ(m.output(sig::kTrip)->status, SignalStatus::Invalid);
  EXPECT_EQ(m.output(sig::kSpeed)->status, SignalStatus::Valid);
  EXPECT_TRUE(m.stats().odometer_refused);
  EXPECT_EQ(m.stats().persist_faults, 3u);
  ASSERT_EQ(reports.size(), 3u);
  EXPECT_NE(reports[0].find("CRC mismatch"), std::string::npos) << reports[0];
  EXPECT_NE(reports[2].find("odometer-reset"), std::string::npos) << reports[2];
  EXPECT_EQ(m.stats().persist_saves, 0u);
  std::ifstream in(dir / "odometer.a");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), damaged);
  std::filesystem::remove_all(dir);
}
