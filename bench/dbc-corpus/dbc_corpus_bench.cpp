// DBC corpus parse, meter vs python3-canmatrix, measured side by side in one run: every file of
// ../shared/data/can/opendbc/ parsed and kept in memory by a fresh process of each, alternating
// which goes first, ROUNDS times. Prints the median parse CPU time of each (the process's own CPU
// clock around reading and parsing the files: a shared machine's waits do not count), their ratio, and each
// process's peak RSS (wait4 ru_maxrss) with and without parsing (the difference is what the
// parsed corpus costs).
//
// usage: dbc_corpus_bench [ROUNDS=7]        (internal: dbc_corpus_bench --meter-child DIR [--none])
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "meter/controller/dbc/database.hpp"
#include "bench_stats.hpp"

using meter::bench::median;

using namespace meter::controller;

namespace {

const std::string kCorpus = std::string(METER_SHARED_DIR) + "/data/can/opendbc";
const std::string kCanmatrix = std::string(METER_SOURCE_DIR) + "/bench/dbc-corpus/canmatrix_corpus_parse.py";

std::vector<std::string> corpus_files(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".dbc") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

// The meter child: the same work as the canmatrix script (read and parse every file, keep all).
int meter_child(const std::string& dir, bool none) {
  std::vector<std::string> files = none ? std::vector<std::string>{} : corpus_files(dir);
  timespec t0{}, t1{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t0);
  std::vector<Database> dbs;
  std::size_t messages = 0;
  for (const auto& f : files) {
    dbs.push_back(load_dbc(f));
    messages += dbs.back().messages.size();
  }
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t1);
  const double s = static_cast<double>(t1.tv_sec - t0.tv_sec) + static_cast<double>(t1.tv_nsec - t0.tv_nsec) * 1e-9;
  std::printf("%zu %zu %.6f\n", dbs.size(), messages, s);
  return 0;
}

struct Run {
  std::size_t files = 0, messages = 0;
  double seconds = 0;
  long max_rss_kb = 0;
};

// Runs argv with stdout to a pipe; parses "files messages seconds"; peak RSS from wait4.
Run run_child(const std::vector<std::string>& argv) {
  int fds[2];
  if (::pipe(fds) != 0) std::exit(2);
  pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(fds[1], 1);
    ::close(fds[0]);
    std::vector<char*> a;
    for (const auto& s : argv) a.push_back(const_cast<char*>(s.c_str()));
    a.push_back(nullptr);
    ::execv(a[0], a.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  std::string out;
  char buf[256];
  ssize_t n;
  while ((n = ::read(fds[0], buf, sizeof buf)) > 0) out.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  int status = 0;
  rusage ru{};
  ::wait4(pid, &status, 0, &ru);
  Run r;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 ||
      std::sscanf(out.c_str(), "%zu %zu %lf", &r.files, &r.messages, &r.seconds) != 3) {
    std::fprintf(stderr, "%s failed (status %d): %s\n", argv[0].c_str(), status, out.c_str());
    std::exit(1);
  }
  r.max_rss_kb = ru.ru_maxrss;
  return r;
}


}  // namespace

int main(int argc, char** argv) {
  if (argc >= 3 && std::strcmp(argv[1], "--meter-child") == 0) return meter_child(argv[2], argc > 3);
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 7;
  const std::string self = std::filesystem::canonical("/proc/self/exe").string();
  const std::vector<std::string> meter = {self, "--meter-child", kCorpus};
  const std::vector<std::string> cm = {"/usr/bin/python3", kCanmatrix, kCorpus};
  std::vector<double> t_meter, t_cm;
  long rss_meter = 0, rss_cm = 0;
  Run last_meter, last_cm;
  for (int r = 0; r < rounds; ++r) {
    // Alternate which goes first, so neither always meets a warm or a cold page cache.
    for (int k = 0; k < 2; ++k) {
      if ((k == 0) == (r % 2 == 0)) {
        last_meter = run_child(meter);
        t_meter.push_back(last_meter.seconds);
        rss_meter = std::max(rss_meter, last_meter.max_rss_kb);
      } else {
        last_cm = run_child(cm);
        t_cm.push_back(last_cm.seconds);
        rss_cm = std::max(rss_cm, last_cm.max_rss_kb);
      }
    }
  }
  std::vector<std::string> meter_none = meter, cm_none = cm;
  meter_none.push_back("--none");
  cm_none.push_back("--none");
  const long base_meter = run_child(meter_none).max_rss_kb, base_cm = run_child(cm_none).max_rss_kb;
  const double mm = median(t_meter), mc = median(t_cm);
  std::printf("DBC corpus parse: %zu files of %s, all kept in memory; median of %d alternating rounds\n",
              last_meter.files, kCorpus.c_str(), rounds);
  std::printf("  %-18s %8s %10s %14s %16s %14s\n", "", "files", "messages", "parse CPU (ms)", "peak RSS (MiB)", "of it corpus");
  std::printf("  %-18s %8zu %10zu %14.1f %16.1f %14.1f\n", "meter", last_meter.files, last_meter.messages, mm * 1e3,
              static_cast<double>(rss_meter) / 1024, static_cast<double>(rss_meter - base_meter) / 1024);
  std::printf("  %-18s %8zu %10zu %14.1f %16.1f %14.1f\n", "python3-canmatrix", last_cm.files, last_cm.messages, mc * 1e3,
              static_cast<double>(rss_cm) / 1024, static_cast<double>(rss_cm - base_cm) / 1024);
  std::printf("  ratio (canmatrix / meter): parse time %.1fx, corpus memory %.1fx\n", mc / mm,
              static_cast<double>(rss_cm - base_cm) / static_cast<double>(std::max(1L, rss_meter - base_meter)));
  return 0;
}
