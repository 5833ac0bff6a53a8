#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "meter/controller/persistence/odometer_store.hpp"
#include "odometer_writer.hpp"

using namespace meter::controller;

namespace {

std::filesystem::path fresh_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return dir;
}
std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
void write_text(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary | std::ios::trunc) << text; }

// The newest copy's path after an even/odd number of saves from a fresh store (copy a first).
std::string newest_copy(const OdometerStore& s, int saves) { return s.copy_path((saves - 1) % 2); }

}  // namespace

TEST(OdometerStore, RoundTripTwoCopiesWrittenAlternately) {
  auto dir = fresh_dir("odo-rt");
  OdometerStore s(dir.string());
  EXPECT_EQ(s.load().state, OdometerState::Fresh);
  EXPECT_EQ(s.save(1000, 10), 1u);
  EXPECT_TRUE(std::filesystem::exists(s.copy_path(0)));
  EXPECT_FALSE(std::filesystem::exists(s.copy_path(1)));
  EXPECT_EQ(s.save(2000, 20), 2u);
  EXPECT_EQ(s.save(3000, 30), 3u);  // back to copy a: b (2000) is untouched while a is written
  EXPECT_NE(read_text(s.copy_path(0)).find("odo_um 3000"), std::string::npos);
  EXPECT_NE(read_text(s.copy_path(1)).find("odo_um 2000"), std::string::npos);
  OdometerStore again(dir.string());
  const OdometerLoad l = again.load();
  ASSERT_EQ(l.state, OdometerState::Restored);
  EXPECT_EQ(l.record->odo_um, 3000);
  EXPECT_EQ(l.record->trip_um, 30);
  EXPECT_TRUE(l.faults.empty());
  EXPECT_EQ(again.save(4000, 40), 4u);  // continues the sequence, into copy b
  EXPECT_NE(read_text(again.copy_path(1)).find("odo_um 4000"), std::string::npos);
  std::filesystem::remove_all(dir);
}

// Truncation at every length, a flipped bit in every byte, a zero-length file and garbage, in
// either copy: the store restores the other copy, names the damaged file, and goes on saving. A
// damaged older copy loses nothing; a damaged newest copy falls back to the one saved before it.
TEST(OdometerStore, OneDamagedCopyRestoresTheOther) {
  auto dir = fresh_dir("odo-damage");
  const std::string good = OdometerStore::format({5000, 50, 5, 4});
  std::vector<std::string> damages{"", "garbage", std::string(5000, 'x')};
  for (std::size_t n = 0; n < good.size() - 1; ++n) damages.push_back(good.substr(0, n));
  for (std::size_t i = 0; i < good.size(); ++i) {  // one bit in every byte, each bit position in turn
    std::string flipped = good;
    flipped[i] = static_cast<char>(flipped[i] ^ (1 << (i % 8)));
    damages.push_back(flipped);
  }
  // The two copies after 5 saves: a holds the newest (seq 5), b the one before.
  std::string intact[2];
  {
    OdometerStore s(dir.string());
    s.load();
    for (int k = 1; k <= 5; ++k) s.save(k * 1000, k * 10);
    ASSERT_EQ(newest_copy(s, 5), s.copy_path(0));
    intact[0] = read_text(s.copy_path(0));
    intact[1] = read_text(s.copy_path(1));
  }
  int cases = 0;
  for (const std::string& damaged : damages)
    for (int which : {0, 1}) {
      OdometerStore s(dir.string());
      write_text(s.copy_path(which), damaged);
      write_text(s.copy_path(1 - which), intact[1 - which]);
      const OdometerLoad l = s.load();
      std::string why;
      if (OdometerStore::parse(damaged, &why)) continue;  // a flip that still parses would be caught by the CRC: never
      ++cases;
      ASSERT_EQ(l.state, OdometerState::Restored) << which << ": " << why;
      ASSERT_EQ(l.record->odo_um, which == 0 ? 4000 : 5000) << why;
      ASSERT_EQ(l.faults.size(), 1u);
      EXPECT_NE(l.faults[0].find(s.copy_path(which)), std::string::npos) << l.faults[0];
      s.save(6000, 60);  // overwrites the damaged copy first; the intact one stays
      const OdometerLoad after = OdometerStore(dir.string()).load();
      ASSERT_EQ(after.state, OdometerState::Restored);
      EXPECT_EQ(after.record->odo_um, 6000);
      EXPECT_TRUE(after.faults.empty());
    }
  EXPECT_EQ(cases, static_cast<int>(damages.size()) * 2);
  std::filesystem::remove_all(dir);
}

TEST(OdometerStore, BothDamagedIsRefusedUntilReset) {
  auto dir = fresh_dir("odo-both");
  OdometerStore s(dir.string());
  s.load();
  s.save(1000, 1);
  s.save(2000, 2);
  write_text(s.copy_path(0), "");
  write_text(s.copy_path(1), "meter-odometer 2\nodo_um 2000\n");
  const OdometerLoad l = s.load();
  EXPECT_EQ(l.state, OdometerState::Refused);
  EXPECT_FALSE(l.record);
  ASSERT_EQ(l.faults.size(), 3u);  // each copy, then the refusal with the reset command
  EXPECT_NE(l.faults[0].find("zero length"), std::string::npos) << l.faults[0];
  EXPECT_NE(l.faults[1].find("truncated"), std::string::npos) << l.faults[1];
  EXPECT_NE(l.faults[2].find("odometer-reset"), std::string::npos) << l.faults[2];
  EXPECT_THROW(s.save(3000, 3), std::runtime_error);  // the damaged files stay for inspection
  EXPECT_EQ(read_text(s.copy_path(0)), "");
  EXPECT_FALSE(s.best_valid());
  s.reset(123000, 0);
  const OdometerLoad r = OdometerStore(dir.string()).load();
  ASSERT_EQ(r.state, OdometerState::Restored);
  EXPECT_EQ(r.record->odo_um, 123000);
  std::filesystem::remove_all(dir);
}

// A copy put back from an older state (a restored backup, a swapped storage chip) while the other
// copy remembers a newer sequence: refused, not restored, until the explicit reset, which restores
// the largest distance on disk so the odometer never goes backwards.
TEST(OdometerStore, CopyRestoredFromAnOlderStateIsRefused) {
  for (int stale : {0, 1}) {
    auto dir = fresh_dir("odo-rollback");
    OdometerStore s(dir.string());
    s.load();
    std::string old_copy;
    for (int k = 1; k <= 10; ++k) {
      s.save(k * 1000, k);
      if (k == 3 + stale) old_copy = read_text(s.copy_path(stale));  // copy 'stale' at save 3 or 4
    }
    write_text(s.copy_path(stale), old_copy);  // put back behind the store's back
    OdometerStore again(dir.string());
    const OdometerLoad l = again.load();
    ASSERT_EQ(l.state, OdometerState::Refused) << stale;
    EXPECT_NE(l.faults.back().find("older state"), std::string::npos) << l.faults.back();
    EXPECT_THROW(again.save(11000, 11), std::runtime_error);
    ASSERT_TRUE(again.best_valid());
    EXPECT_EQ(again.best_valid()->odo_um, stale == 0 ? 10000 : 9000);  // the newest surviving copy
    again.reset(again.best_valid()->odo_um, again.best_valid()->trip_um);
    const OdometerLoad r = OdometerStore(dir.string()).load();
    ASSERT_EQ(r.state, OdometerState::Restored);
    EXPECT_EQ(r.record->odo_um, stale == 0 ? 10000 : 9000);
    std::filesystem::remove_all(dir);
  }
}

// The single file of earlier versions still loads; it goes once both copies hold records.
// A copy whose sequence is the largest there is (only a damaged or hand-made file holds one) is
// not taken: the save after it would wrap to 0 and a restart would then refuse the distance it saved.
TEST(OdometerStore, FuzzCopyAtTheLastSequenceIsDamagedAndTheOtherRestored) {
  auto dir = fresh_dir("odo-lastseq");
  {
    OdometerStore s(dir.string());
    ASSERT_EQ(s.load().state, OdometerState::Fresh);
    s.save(1000, 10);  // copy a, sequence 1
  }
  OdometerRecord last{5000, 0, UINT64_MAX, 1};
  write_text((dir / "odometer.b").string(), OdometerStore::format(last));
  std::string why;
  EXPECT_FALSE(OdometerStore::parse(OdometerStore::format(last), &why));
  EXPECT_NE(why.find("largest"), std::string::npos) << why;
  OdometerStore s(dir.string());
  const auto loaded = s.load();
  ASSERT_EQ(loaded.state, OdometerState::Restored);
  EXPECT_EQ(loaded.record->odo_um, 1000);
  s.save(1001, 10);
  OdometerStore again(dir.string());
  const auto after = again.load();
  ASSERT_EQ(after.state, OdometerState::Restored);
  EXPECT_EQ(after.record->odo_um, 1001);  // nothing persisted is lost
  std::filesystem::remove_all(dir);
}

TEST(OdometerStore, OldSingleFileMigrates) {
  auto dir = fresh_dir("odo-legacy");
  std::filesystem::create_directories(dir);
  OdometerStore s(dir.string());
  // Written by the single-file store (format 1, CRC-32 of the body).
  write_text(s.legacy_path(), "meter-odometer 1\nodo_um 123456789\ntrip_um 4242\nseq 7\ncrc a1f96c82\n");
  const OdometerLoad l = s.load();
  ASSERT_EQ(l.state, OdometerState::Restored);
  EXPECT_EQ(l.record->odo_um, 123456789);
  EXPECT_EQ(l.record->trip_um, 4242);
  EXPECT_EQ(s.save(123456790, 4243), 8u);
  EXPECT_TRUE(std::filesystem::exists(s.legacy_path()));  // until the second copy exists
  EXPECT_EQ(s.save(123456791, 4244), 9u);
  EXPECT_FALSE(std::filesystem::exists(s.legacy_path()));
  EXPECT_EQ(OdometerStore(dir.string()).load().record->odo_um, 123456791);
  // A damaged single file with no copies: refused, like two damaged copies.
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_text(s.legacy_path(), "meter-odometer 1\nodo_um 123456789\ntrip_um 4242\nseq 7\ncrc a1f96c83\n");
  const OdometerLoad bad = OdometerStore(dir.string()).load();
  EXPECT_EQ(bad.state, OdometerState::Refused);
  EXPECT_NE(bad.faults[0].find("CRC mismatch"), std::string::npos);
  std::filesystem::remove_all(dir);
}

// SIGKILL at random instants while a child persists its odometer: the stored record must always
// parse (never corrupt), never be ahead of the true distance, and never be behind by more than one
// persistence interval. 220 kills keep this well under a few seconds. Every tenth kill waits until
// the child has announced the step after a completed save before its random delay starts, so the
// distance grows however slow the machine is: under ASan beside a CI's builds a save's fsync can
// outlast every random delay, and all 220 children once died before their first save.
TEST(OdometerStore, SurvivesSigkillAtRandomInstants) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-kill-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::mt19937 rng(2026);
  constexpr int kKills = 220;
  constexpr std::int64_t kStepUm = 27778;  // 100 km/h for 1 ms
  constexpr int kPersistEvery = 3;         // steps per persistence interval
  std::int64_t expected_floor = 0;
  int killed_mid_run = 0;
  for (int k = 0; k < kKills; ++k) {
    int pipefd[2];
    ASSERT_EQ(::pipe(pipefd), 0);
    pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      ::close(pipefd[0]);
      meter::controller::testing::run_odometer_writer(dir.string(), pipefd[1], kPersistEvery);
    }
    ::close(pipefd[1]);
    std::int64_t truth = expected_floor, v;
    if (k % 10 == 9) {
      // The child resumes from the stored distance; it announces a step before saving it, so an
      // announcement one step past the first save means that save is complete.
      const std::int64_t after_a_save = expected_floor + kPersistEvery * kStepUm + kStepUm / 2;
      while (truth < after_a_save && ::read(pipefd[0], &v, sizeof v) == sizeof v) truth = v;
    }
    std::uniform_int_distribution<int> delay_us(200, 4000);
    ::usleep(static_cast<useconds_t>(delay_us(rng)));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "child exited on its own with " << WEXITSTATUS(status);
    ++killed_mid_run;
    while (::read(pipefd[0], &v, sizeof v) == sizeof v) truth = v;
    ::close(pipefd[0]);
    OdometerStore store(dir.string());
    const OdometerLoad l = store.load();
    ASSERT_NE(l.state, OdometerState::Refused) << "kill " << k << " left no valid copy";
    ASSERT_TRUE(l.faults.empty()) << "kill " << k << ": " << l.faults[0];
    std::int64_t stored = l.record ? l.record->odo_um : 0;
    ASSERT_LE(stored, truth) << "kill " << k;
    ASSERT_LE(truth - stored, kPersistEvery * kStepUm) << "kill " << k << ": lost more than one interval";
    ASSERT_GE(stored, expected_floor) << "kill " << k << ": went backwards";
    expected_floor = stored;
  }
  EXPECT_EQ(killed_mid_run, kKills);
  // At least one persistence interval per waited kill (22 of them).
  EXPECT_GE(expected_floor, (kKills / 10) * kPersistEvery * (kStepUm - 1));
  std::filesystem::remove_all(dir);
}
