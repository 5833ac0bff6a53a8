#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "meter/controller/persistence/odometer_store.hpp"
#include "odometer_writer.hpp"

using namespace meter::controller;

TEST(OdometerStore, RoundTripAndCorruptionDetected) {
  auto dir = std::filesystem::temp_directory_path() / ("meter-odo-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  OdometerStore s(dir.string());
  EXPECT_FALSE(s.load().has_value());
  s.save({123456789, 4242, 7});
  auto r = s.load();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->odo_um, 123456789);
  EXPECT_EQ(r->trip_um, 4242);
  EXPECT_EQ(r->sequence, 7u);
  std::string text = OdometerStore::format({5, 6, 1});
  std::string why;
  text[20] ^= 1;
  EXPECT_FALSE(OdometerStore::parse(text, &why));
  EXPECT_NE(why.find("CRC"), std::string::npos);
  EXPECT_FALSE(OdometerStore::parse("meter-odometer 1\nodo_um 5\n", &why));
  EXPECT_NE(why.find("truncated"), std::string::npos);
  { std::ofstream(s.path()) << "garbage"; }
  EXPECT_THROW(s.load(), std::runtime_error);
  std::filesystem::remove_all(dir);
}

// SIGKILL at random instants while a child persists its odometer: the stored record must always
// parse (never corrupt), never be ahead of the true distance, and never be behind by more than one
// persistence interval. 220 kills keep this well under a few seconds.
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
    std::uniform_int_distribution<int> delay_us(200, 4000);
    ::usleep(static_cast<useconds_t>(delay_us(rng)));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "child exited on its own with " << WEXITSTATUS(status);
    ++killed_mid_run;
    std::int64_t truth = expected_floor, v;
    while (::read(pipefd[0], &v, sizeof v) == sizeof v) truth = v;
    ::close(pipefd[0]);
    OdometerStore store(dir.string());
    std::optional<OdometerRecord> r;
    ASSERT_NO_THROW(r = store.load()) << "kill " << k << " corrupted the store";
    std::int64_t stored = r ? r->odo_um : 0;
    ASSERT_LE(stored, truth) << "kill " << k;
    ASSERT_LE(truth - stored, kPersistEvery * kStepUm) << "kill " << k << ": lost more than one interval";
    ASSERT_GE(stored, expected_floor) << "kill " << k << ": went backwards";
    expected_floor = stored;
  }
  EXPECT_EQ(killed_mid_run, kKills);
  EXPECT_GT(expected_floor, 0);
  std::filesystem::remove_all(dir);
}
