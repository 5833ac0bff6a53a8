// SIGKILL endurance for the odometer store (the suite does 220 kills; this does thousands):
// a child integrates 100 km/h in 1 ms steps and persists every persistence interval; the parent
// kills it at random instants and checks the stored record each time. Prints the counts and the
// distribution of the distance lost per kill, in persistence intervals.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <vector>

#include "meter/controller/persistence/odometer_store.hpp"
#include "odometer_writer.hpp"

using namespace meter::controller;

int main(int argc, char** argv) {
  const int kills = argc > 1 ? std::atoi(argv[1]) : 2000;
  const int every = 3;                 // steps per persistence interval
  const std::int64_t step_um = 27777;  // 100 km/h for 1 ms (rounded down per step)
  auto dir = std::filesystem::temp_directory_path() / ("meter-kill-bench-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::mt19937 rng(1);
  std::int64_t floor = 0;
  int corrupt = 0, ahead = 0, too_far_behind = 0, backwards = 0;
  std::vector<double> lost_intervals;
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
    ::waitpid(pid, nullptr, 0);
    std::int64_t truth = floor, v;
    while (::read(fds[0], &v, sizeof v) == sizeof v) truth = v;
    ::close(fds[0]);
    std::int64_t stored = 0;
    try {
      auto r = OdometerStore(dir.string()).load();
      stored = r ? r->odo_um : 0;
    } catch (...) {
      ++corrupt;
      continue;
    }
    ahead += stored > truth;
    too_far_behind += truth - stored > every * (step_um + 1);
    backwards += stored < floor;
    lost_intervals.push_back(static_cast<double>(truth - stored) / static_cast<double>(every * step_um));
    floor = stored;
  }
  std::sort(lost_intervals.begin(), lost_intervals.end());
  auto pct = [&](double q) { return lost_intervals.empty() ? 0.0 : lost_intervals[static_cast<std::size_t>(q * static_cast<double>(lost_intervals.size() - 1))]; };
  std::printf("odometer SIGKILL endurance: %d kills\n", kills);
  std::printf("  corrupt records        %d\n", corrupt);
  std::printf("  ahead of the truth     %d\n", ahead);
  std::printf("  behind > 1 interval    %d\n", too_far_behind);
  std::printf("  went backwards         %d\n", backwards);
  std::printf("  distance lost per kill (persistence intervals): p50 %.2f  p99 %.2f  max %.2f\n", pct(0.5), pct(0.99), pct(1.0));
  std::printf("  final odometer         %.3f m\n", static_cast<double>(floor) / 1e6);
  std::filesystem::remove_all(dir);
  return corrupt + ahead + too_far_behind + backwards == 0 ? 0 : 1;
}
