// meter-controller's memory budget (goal: peak RSS <= 16 MB), measured on the real binary:
//  (a) a live CAN input: `run --input can:vcan0` inside vcan/with-vcan (the host's vcan0, or the
//      qemu VM when this kernel has no SocketCAN) while cangen floods the bus, its peak RSS read
//      from /proc/PID/status (VmHWM) there; skipped (said so) when no VM or vcan can be had;
//  (b) replaying a long log: the ft86 drive repeated with shifted times (each repeat starts after
//      the previous one ends) written at bench time to /tmp as candump and as BLF (a few hundred MB
//      of candump), replayed by `run --replay fast --exit-at-end`, decoded by `decode` and converted
//      by `convert-log`; each process's peak RSS (wait4's ru_maxrss) next to the same commands on
//      the short drive, so that growth with the log's length shows. The files are deleted after.
//   controller_memory_bench [REPEATS [BINARY]]   (default 80 repeats, this build's meter-controller)
#include <sys/resource.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "meter/controller/input/blf_log_writer.hpp"
#include "meter/controller/input/candump_log.hpp"
#include "meter/controller/input/log_source.hpp"

using namespace meter::controller;

namespace {

const std::string kShared = METER_SHARED_DIR;
const std::string kDbc = kShared + "/data/can/ft86_motec/sample_can_spec.dbc";
const std::string kLog = kShared + "/data/can/ft86_motec/can_sample.log";
const std::string kMap = std::string(METER_SOURCE_DIR) + "/controller/vehicles/ft86/ft86.map";
constexpr double kGoalMiB = 16.0 * 1000 * 1000 / (1024 * 1024);  // 16 MB

// The drive's frames `repeats` times, each repeat shifted to start 1 ms after the previous ends.
class RepeatedDrive : public LogSource {
 public:
  RepeatedDrive(const ParsedLog& drive, int repeats) : drive_(drive), repeats_(repeats) {
    span_ = drive.frames.back().timestamp_ns - drive.frames.front().timestamp_ns + 1000000;
  }

 private:
  const ParsedLog& drive_;
  int repeats_, repeat_ = 0;
  std::size_t next_ = 0;
  std::int64_t span_ = 0;
  bool read_more() override {
    if (next_ == drive_.frames.size()) next_ = 0, ++repeat_;
    if (repeat_ >= repeats_) return false;
    CanFrame f = drive_.frames[next_++];
    f.timestamp_ns += span_ * repeat_;
    window().frames.push_back(f);
    return true;
  }
};

// Runs argv to its end (stdout to /dev/null): its exit status and peak RSS in MiB.
std::pair<int, double> peak_rss(const std::vector<std::string>& argv) {
  std::fflush(stdout);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  rusage ru{};
  ::wait4(pid, &status, 0, &ru);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128, static_cast<double>(ru.ru_maxrss) / 1024.0};
}

double mib(std::uintmax_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

// Writes the long logs in a child process, so that this process stays small: a child's peak RSS
// (ru_maxrss) starts from its parent's at the fork.
bool write_long_logs(int repeats, const std::string& candump, const std::string& blf) {
  std::fflush(stdout);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const ParsedLog drive = load_candump_log(kLog);
    std::ofstream out(candump, std::ios::binary);
    RepeatedDrive frames(drive, repeats);
    const std::size_t n = write_candump_log(frames, out, [](std::size_t) {});
    std::ofstream bout(blf, std::ios::binary);
    RepeatedDrive again(drive, repeats);
    write_blf_log(again, bout, [](std::size_t) {});
    std::printf("(b) replaying a long log: the ft86 drive (%zu frames, %.1f MiB candump) repeated %d times = %zu frames\n",
                drive.frames.size(), mib(std::filesystem::file_size(kLog)), repeats, n);
    std::fflush(stdout);
    ::_exit(out && bout ? 0 : 1);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

int replay_long_logs(const std::string& bin, int repeats, const std::filesystem::path& dir) {
  const std::string candump = (dir / "long.log").string(), blf = (dir / "long.blf").string();
  if (!write_long_logs(repeats, candump, blf)) return std::printf("  could not write the long logs in %s\n", dir.c_str()), 1;
  rusage self{};
  ::getrusage(RUSAGE_SELF, &self);
  std::printf("  (each figure is at least this bench's own %.1f MiB at the fork)\n", static_cast<double>(self.ru_maxrss) / 1024.0);
  const std::string sock = "unix:" + (dir / "link.sock").string();
  std::printf("  %-34s %12s %12s %6s\n", "command on log", "log MiB", "peak RSS MiB", "exit");
  int failures = 0;
  for (const auto& [name, path] : {std::pair<std::string, std::string>{"ft86 candump (short)", kLog}, {"long candump", candump}, {"long BLF", blf}}) {
    const double size = mib(std::filesystem::file_size(path));
    const std::vector<std::vector<std::string>> commands{
        {bin, "run", "--dbc", kDbc, "--map", kMap, "--input", "log:" + path, "--replay", "fast", "--exit-at-end", "--link", sock},
        {bin, "decode", "--dbc", kDbc, path},
        {bin, "convert-log", path, (dir / "out.blf").string()},
    };
    for (const auto& argv : commands) {
      const auto [status, rss] = peak_rss(argv);
      failures += status != 0;
      std::printf("  %-34s %12.1f %12.1f %6d%s\n", (argv[1] + " " + name).c_str(), size, rss, status,
                  rss <= kGoalMiB ? "" : "  over the goal");
    }
    std::filesystem::remove(dir / "out.blf");
  }
  std::filesystem::remove(candump);
  std::filesystem::remove(blf);
  return failures;
}

// (a) inside vcan/with-vcan: the controller on can:vcan0 while cangen sends frames of the ft86
// DBC's ids (1 kHz for 10 s, then 5 kHz for 3 s); VmHWM read from /proc before it is stopped. The
// guest script is a file in `dir` (the VM sees the host's files read-only).
void live_can(const std::string& bin, const std::filesystem::path& dir) {
  const std::string script = (dir / "live_can.sh").string();
  std::ofstream(script) << "set -e\n"
                        << bin << " run --dbc " << kDbc << " --map " << kMap << " --input can:vcan0 --link unix:/tmp/m.sock >/tmp/m.out 2>&1 &\n"
                        << "pid=$!\nsleep 1\n"
                        << "timeout 10 cangen vcan0 -g 1 -I 0D2 -L 8 -D i >/dev/null 2>&1 || true\n"
                        << "timeout 3 cangen vcan0 -g 0.2 -I 140 -L 8 -D r >/dev/null 2>&1 || true\n"
                        << "echo \"live-can VmHWM $(sed -n 's/^VmHWM:[[:space:]]*\\([0-9]*\\) kB/\\1/p' /proc/$pid/status) kB, mode $METER_VCAN_MODE\"\n"
                        << "kill $pid; cat /tmp/m.out | tail -3\n";
  const std::string cmd = std::string(METER_SOURCE_DIR) + "/vcan/with-vcan -q --timeout 300 --boot-timeout 200 -- sh " + script + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  char line[512];
  double kb = 0;
  std::string mode = "?", said, frames_line;
  bool seen = false;
  while (p && std::fgets(line, sizeof line, p)) {
    char m[32] = "";
    if (std::sscanf(line, "live-can VmHWM %lf kB, mode %31s", &kb, m) >= 1) {
      seen = true;
      mode = m;
    } else {
      said += line;
      if (std::strncmp(line, "meter-controller: ", 18) == 0 && std::strstr(line, " frames (")) frames_line = line + 18;
    }
  }
  if (p) ::pclose(p);
  std::printf("(a) live CAN input (can:vcan0; cangen asked for 1 kHz for 10 s, then 5 kHz for 3 s):\n");
  if (!seen) {
    std::printf("  not measured: vcan/with-vcan could not run it:\n%s", said.c_str());
    return;
  }
  std::printf("  peak RSS %.1f MiB (VmHWM, vcan path: %s)%s\n", kb / 1024.0, mode.c_str(), kb / 1024.0 <= kGoalMiB ? "" : "  over the goal");
  if (!frames_line.empty()) std::printf("  the controller's stats: %.*s\n", static_cast<int>(frames_line.find(" (")), frames_line.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 80;
  const std::string bin = argc > 2 ? argv[2] : std::string(METER_BINARY_DIR) + "/bin/meter-controller";
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("meter-membench-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::printf("meter-controller peak RSS, goal <= 16 MB (%.1f MiB); binary %s\n", kGoalMiB, bin.c_str());
  if (!std::getenv("METER_MEMBENCH_NO_VCAN")) live_can(bin, dir);
  const int failures = replay_long_logs(bin, repeats, dir);
  std::filesystem::remove_all(dir);
  return failures ? 1 : 0;
}
