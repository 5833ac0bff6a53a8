// Controller benchmarks, measured side by side in one run:
//  1. DBC decode throughput on the ft86 log held in memory vs python3-canmatrix on the same frames
//     (ratio printed; goal >= 100x),
//  1b. decode plus the E2E checks (checksum and counter) of the same log's frames under opendbc's
//     Subaru pre-global DBC (the Toyota 86 is built on that platform; its conventions protect the
//     log's Steering checksum and six counters) vs python3-canmatrix's decode alone of the same
//     frames with the same DBC (ratio printed; goal >= 50x),
//  2. each log reader (candump, ASC, BLF, TRC) vs python3-can reading the same file (goal >= 20x),
//     BLF vs the candump reader (goal within 3x): log_readers.cpp,
//  3. meter-controller CPU share and peak RSS while replaying the ft86 log in real time
//     (goal < 1 % of a core at the real bus rate).
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <string>
#include <vector>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"
#include "log_readers.hpp"
#include "meter/controller/e2e/e2e_guard.hpp"
#include "meter/controller/mapping/sources.hpp"
#include "meter/controller/input/candump_log.hpp"

using namespace meter::controller;

namespace {
const std::string kShared = METER_SHARED_DIR;
const std::string kDbc = kShared + "/data/can/ft86_motec/sample_can_spec.dbc";
const std::string kLog = kShared + "/data/can/ft86_motec/can_sample.log";

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
// utime + stime of a process, from /proc/PID/stat (fields 14 and 15, in clock ticks).
double proc_cpu_seconds(pid_t pid) {
  FILE* f = std::fopen(("/proc/" + std::to_string(pid) + "/stat").c_str(), "r");
  if (!f) return 0;
  char buf[1024];
  std::size_t n = std::fread(buf, 1, sizeof buf - 1, f);
  std::fclose(f);
  buf[n] = 0;
  const char* p = std::strrchr(buf, ')');  // the command name may contain spaces
  if (!p) return 0;
  unsigned long ut = 0, st = 0;
  // After ") ": state(3) ppid pgrp session tty tpgid flags minflt cminflt majflt cmajflt utime(14) stime(15)
  if (std::sscanf(p + 2, "%*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %lu %lu", &ut, &st) != 2) return 0;
  return static_cast<double>(ut + st) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}
// Frames/s over the frames db knows: lookup, then the E2E checks of guard (when given; a refused
// frame is not decoded, as in the model), then decode (when asked).
double frame_rate(const Database& db, const std::vector<const CanFrame*>& frames, E2eGuard* guard, bool decode_too,
                  double& sink) {
  std::vector<DecodedSignal> out;
  std::size_t n = 0;
  auto t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < 40; ++r)
    for (const CanFrame* f : frames) {
      const DbcMessage* m = db.find(f->id, f->extended);
      const std::span<const std::uint8_t> payload(f->data.data(), f->len);
      ++n;
      if (guard && !guard->accept(m, f->id, payload)) continue;
      if (!decode_too) continue;
      decode(*m, payload, out);
      sink += out.empty() ? 0 : out[0].physical;
    }
  return static_cast<double>(n) / seconds_since(t0);
}

// 1b: the same log under opendbc's Subaru pre-global DBC (the Toyota 86 is built on that
// platform), decoded alone and with the E2E checks its conventions identify.
double bench_e2e() {
  const std::string dbc = kShared + "/data/can/opendbc/subaru_outback_2015_generated.dbc";
  const Database db = load_dbc(dbc);
  const ParsedLog log = load_candump_log(kLog);
  std::vector<const CanFrame*> frames;  // as canmatrix takes them: the DBC's length only
  for (const auto& f : log.frames)
    if (const DbcMessage* m = db.find(f.id, f.extended); m && f.len == m->size) frames.push_back(&f);
  const std::string cmd = "/usr/bin/python3 " + std::string(METER_SOURCE_DIR) + "/controller/tests/canmatrix_decode.py " + dbc +
                          " " + kLog + " --bench --dbc-length-only 2>/dev/null";
  FILE* p = ::popen(cmd.c_str(), "r");
  double py_frames = 0, py_s = 0;
  if (!p || std::fscanf(p, "%lf %lf", &py_frames, &py_s) != 2 || py_s <= 0) {
    std::fprintf(stderr, "python3-canmatrix benchmark (Subaru DBC) failed\n");
    std::exit(1);
  }
  ::pclose(p);
  const double canmatrix_fps = py_frames / py_s;
  E2eSettings settings;
  settings.detect = true;
  const InputDbc inputs[] = {{"", &db}};
  E2eGuard guard = build_e2e_guard(inputs, settings, "bench");
  double sink = 0;
  std::uint64_t protected_frames = 0;
  for (const CanFrame* f : frames) protected_frames += guard.find(db.find(f->id, f->extended)) >= 0;
  const double plain = frame_rate(db, frames, nullptr, true, sink);
  const double checked = frame_rate(db, frames, &guard, true, sink);
  E2eGuard fresh = build_e2e_guard(inputs, settings, "bench");
  const double lookup = frame_rate(db, frames, nullptr, false, sink), checks = frame_rate(db, frames, &fresh, false, sink);
  std::uint64_t refused = 0;
  for (const auto& e : guard.entries()) refused += e.stats.refused();
  std::printf("decode + E2E checks, ft86 under subaru_outback_2015_generated.dbc (%zu frames, %llu of them protected):\n",
              frames.size(), static_cast<unsigned long long>(protected_frames));
  std::printf("  python3-canmatrix  %12.0f frames/s  (decode alone, %.0f frames)\n", canmatrix_fps, py_frames);
  std::printf("  decode alone       %12.0f frames/s\n", plain);
  std::printf("  decode + checks    %12.0f frames/s  (%llu refused: the 40 replays' seams)\n", checked,
              static_cast<unsigned long long>(refused));
  std::printf("  the checks alone   %12.1f ns per frame  (lookup + checks minus lookup, every frame of the log)\n",
              1e9 / checks - 1e9 / lookup);
  std::printf("  ratio to canmatrix %12.1fx  (decode + checks vs python3-canmatrix's decode alone; goal >= 50x)\n",
              checked / canmatrix_fps);
  return sink;
}

}  // namespace

int main(int argc, char** argv) {
  double cpu_seconds = argc > 1 ? std::atof(argv[1]) : 20.0;
  Database db = load_dbc(kDbc);
  ParsedLog log = load_candump_log(kLog);
  std::vector<const CanFrame*> known;
  std::vector<const DbcMessage*> msgs;
  for (const auto& f : log.frames)
    if (db.find(f.id, f.extended)) known.push_back(&f);

  // 1. Decode throughput (frame lookup + every signal, as the decode subcommand does).
  std::vector<DecodedSignal> out;
  out.reserve(16);
  double sink = 0;
  std::size_t decoded = 0;
  const int kRounds = 40;
  auto t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < kRounds; ++r) {
    for (const CanFrame* f : known) {
      const DbcMessage* m = db.find(f->id, f->extended);
      decode(*m, std::span<const std::uint8_t>(f->data.data(), f->len), out);
      sink += out.empty() ? 0 : out[0].physical;
      ++decoded;
    }
  }
  const double ours_s = seconds_since(t0);
  const double ours_fps = static_cast<double>(decoded) / ours_s;

  std::string cmd = "/usr/bin/python3 " + std::string(METER_SOURCE_DIR) + "/controller/tests/canmatrix_decode.py " + kDbc + " " +
                    kLog + " --bench 2>/dev/null";
  FILE* p = ::popen(cmd.c_str(), "r");
  double py_frames = 0, py_s = 0;
  if (!p || std::fscanf(p, "%lf %lf", &py_frames, &py_s) != 2 || py_s <= 0) {
    std::fprintf(stderr, "python3-canmatrix benchmark failed\n");
    return 1;
  }
  ::pclose(p);
  const double py_fps = py_frames / py_s;
  std::printf("decode ft86 (%zu frames in memory, one core):\n", known.size());
  std::printf("  meter decoder      %12.0f frames/s\n", ours_fps);
  std::printf("  python3-canmatrix  %12.0f frames/s\n", py_fps);
  std::printf("  ratio              %12.1fx  (goal >= 100x)\n", ours_fps / py_fps);
  sink += bench_e2e();

  // 2. The log readers.
  if (bench_log_readers(kLog) != 0) return 1;

  // 3. CPU share and RSS of meter-controller replaying the log in real time.
  const std::string bin = std::string(METER_BINARY_DIR) + "/bin/meter-controller";
  const std::string map = std::string(METER_SOURCE_DIR) + "/controller/vehicles/ft86/ft86.map";
  const std::string sock = "unix:/tmp/meter-bench-" + std::to_string(::getpid()) + ".sock";
  std::fflush(stdout);
  pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    ::execl(bin.c_str(), bin.c_str(), "run", "--dbc", kDbc.c_str(), "--map", map.c_str(), "--input", ("log:" + kLog).c_str(),
            "--replay", "realtime", "--link", sock.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  auto w0 = std::chrono::steady_clock::now();
  // Steady state excludes start-up (loading the DBC and parsing the 82k-line log): CPU ticks from
  // /proc between 2 s after start and the end of the window.
  ::usleep(2000000);
  const double cpu_a = proc_cpu_seconds(pid);
  auto s0 = std::chrono::steady_clock::now();
  ::usleep(static_cast<useconds_t>(std::max(1.0, cpu_seconds - 2.0) * 1e6));
  const double cpu_b = proc_cpu_seconds(pid);
  const double steady_wall = seconds_since(s0);
  ::kill(pid, SIGTERM);
  int status;
  rusage ru{};
  ::wait4(pid, &status, 0, &ru);
  const double wall = seconds_since(w0);
  const double cpu = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
                     static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1e6;
  const double bus_rate = static_cast<double>(log.frames.size()) /
                          (static_cast<double>(log.frames.back().timestamp_ns - log.frames.front().timestamp_ns) / 1e9);
  std::printf("meter-controller replaying ft86 in real time (%.0f frames/s on the bus) for %.1f s:\n", bus_rate, wall);
  std::printf("  CPU, whole run     %12.2f %% of one core  (includes loading the log)\n", 100.0 * cpu / wall);
  std::printf("  CPU, steady state  %12.2f %% of one core  (goal < 1 %%)\n", 100.0 * (cpu_b - cpu_a) / steady_wall);
  std::printf("  peak RSS           %12.1f MiB\n", static_cast<double>(ru.ru_maxrss) / 1024.0);
  return sink == 12345.678 ? 2 : 0;  // keeps the decode loop from being optimised away
}
