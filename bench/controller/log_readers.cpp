// Each log format read by meter (open_log_source, streamed a frame at a time as run and decode read it) and by python-can, the
// same file, one after the other in this process's run.
#include "log_readers.hpp"

#include <unistd.h>

#include <ctime>
#include <cstdio>
#include <filesystem>
#include <string>

#include "meter/controller/input/log_format.hpp"

using namespace meter::controller;

namespace {

const std::string kScript = std::string(METER_SOURCE_DIR) + "/bench/controller/python_can_logs.py";

// CPU seconds of this process: both sides are timed on their CPU time, so a machine shared with
// other work does not count against either.
double cpu_seconds() {
  timespec t{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) / 1e9;
}

// meter's frames/s on `path`: whole reads repeated for at least half a CPU second.
double meter_frames_per_second(const std::string& path, std::size_t& frames) {
  int rounds = 0;
  const double t0 = cpu_seconds();
  double s = 0;
  do {
    const auto source = open_log_source(path);
    frames = 0;
    while (source->next()) ++frames;
    ++rounds;
    s = cpu_seconds() - t0;
  } while (s < 0.5);
  return static_cast<double>(frames) * rounds / s;
}

double python_frames_per_second(const std::string& path) {
  FILE* p = ::popen(("/usr/bin/python3 " + kScript + " read " + path + " 2>/dev/null").c_str(), "r");
  double frames = 0, seconds = 0;
  const bool ok = p && std::fscanf(p, "%lf %lf", &frames, &seconds) == 2 && seconds > 0;
  if (p) ::pclose(p);
  return ok ? frames / seconds : 0;
}

}  // namespace

int bench_log_readers(const std::string& candump_log) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("meter-logbench-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string write = "/usr/bin/python3 " + kScript + " write " + dir.string() + " " + candump_log + " 2>/dev/null";
  if (std::system(write.c_str()) != 0) {
    std::fprintf(stderr, "python3-can could not write the logs\n");
    return 1;
  }
  std::printf("log readers on the ft86 drive (python-can's ASC, BLF and TRC writers; CPU time, whole files streamed):\n");
  std::printf("  %-8s %10s %14s %14s %8s\n", "format", "frames", "meter/s", "python-can/s", "ratio");
  double candump_fps = 0, blf_fps = 0;
  int status = 0;
  for (const std::string& path : {candump_log, (dir / "ft86.asc").string(), (dir / "ft86.blf").string(), (dir / "ft86.trc").string()}) {
    std::size_t frames = 0;
    const double ours = meter_frames_per_second(path, frames);
    const double theirs = python_frames_per_second(path);
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".log") candump_fps = ours;
    if (ext == ".blf") blf_fps = ours;
    if (theirs <= 0) status = 1;
    std::printf("  %-8s %10zu %14.0f %14.0f %7.1fx  (goal >= 20x)\n", ext.c_str() + 1, frames, ours, theirs, theirs > 0 ? ours / theirs : 0.0);
  }
  std::printf("  BLF / candump reader: %.2fx the candump reader's speed (goal within 3x: >= 0.33)\n", blf_fps / candump_fps);
  std::filesystem::remove_all(dir);
  return status;
}
