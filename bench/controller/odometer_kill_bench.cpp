// SIGKILL endurance for the odometer store (the suite does 220 kills; this does 1,000 by default):
// a child restores the odometer, integrates 100 km/h in 1 ms steps and persists every persistence
// interval (3 steps: a save is under way most of the time); the parent kills it at random instants
// and, like the next start of the controller, loads the store each time. Prints a table: kills,
// kills that caught a write in progress, refused starts, damaged copies found, records ahead of the
// truth or going backwards, and the distance lost per kill in persistence intervals.
//   odometer_kill_bench [KILLS]
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <vector>

#include "meter/controller/persistence/odometer_store.hpp"
#include "odometer_writer.hpp"

using namespace meter::controller;

int main(int argc, char** argv) {
  const int kills = argc > 1 ? std::atoi(argv[1]) : 1000;
  if (kills <= 0) {
    std::fprintf(stderr, "odometer_kill_bench: expected a number of kills > 0, got '%s'\n", argv[1]);
    return 2;
  }
  const int every = 3;                 // steps per persistence interval
  const std::int64_t step_um = 27777;  // 100 km/h for 1 ms (rounded down per step)
  auto dir = std::filesystem::temp_directory_path() / ("meter-kill-bench-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::mt19937 rng(1);
  std::int64_t floor = 0;
  int refused = 0, child_refused = 0, damaged = 0, mid_write = 0, ahead = 0, too_far_behind = 0, backwards = 0;
  std::vector<double> lost_intervals;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < kills; ++k) {
    int fds[2];
    if (::pipe(fds) != 0) return 1;
    pid_t pid = ::fork();
    if (pid == 0) {
      ::close(fds[0]);
      meter::controller::testing::run_odometer_writer(dir.string(), fds[1], every);
    }
    ::close(fds[1]);
    ::usleep(static_cast<useconds_t>(std::uniform_int_distribution<int>(100, 5000)(rng)));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    child_refused += WIFEXITED(status) && WEXITSTATUS(status) == 4;
    std::int64_t truth = floor, v;
    while (::read(fds[0], &v, sizeof v) == sizeof v) truth = v;
    ::close(fds[0]);
    mid_write += std::filesystem::exists(dir / "odometer.a.tmp") || std::filesystem::exists(dir / "odometer.b.tmp");
    const OdometerLoad l = OdometerStore(dir.string()).load();
    damaged += static_cast<int>(l.faults.size());
    if (l.state == OdometerState::Refused) {
      ++refused;
      continue;
    }
    const std::int64_t stored = l.record ? l.record->odo_um : 0;
    ahead += stored > truth;
    too_far_behind += truth - stored > every * (step_um + 1);
    backwards += stored < floor;
    lost_intervals.push_back(static_cast<double>(truth - stored) / static_cast<double>(every * step_um));
    floor = stored;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::sort(lost_intervals.begin(), lost_intervals.end());
  auto pct = [&](double q) {
    return lost_intervals.empty() ? 0.0 : lost_intervals[static_cast<std::size_t>(q * static_cast<double>(lost_intervals.size() - 1))];
  };
  std::printf("odometer SIGKILL endurance (two alternating copies, persist every %d ms of driving)\n", every);
  std::printf("| measure | count |\n|---|---|\n");
  std::printf("| kills | %d |\n", kills);
  std::printf("| kills during a write (temp file left) | %d |\n", mid_write);
  std::printf("| refused starts | %d |\n", refused + child_refused);
  std::printf("| damaged copies found | %d |\n", damaged);
  std::printf("| stored ahead of the truth | %d |\n", ahead);
  std::printf("| behind by more than 1 interval | %d |\n", too_far_behind);
  std::printf("| went backwards | %d |\n", backwards);
  std::printf("| loss per kill, intervals: p50 / p99 / max | %.2f / %.2f / %.2f |\n", pct(0.5), pct(0.99), pct(1.0));
  std::printf("| final odometer | %.3f m |\n", static_cast<double>(floor) / 1e6);
  std::printf("| wall time | %.1f s (%.1f ms per cycle) |\n", seconds, 1000.0 * seconds / kills);
  std::filesystem::remove_all(dir);
  return refused + child_refused + damaged + ahead + too_far_behind + backwards == 0 ? 0 : 1;
}
