// bench/budget: meter-view's start-up, memory and installed size against the deployment budgets
// (docs/deploy.md, "Budgets"): process start -> first frame <= 250 ms, peak RSS <= 128 MB, the
// runtime's files against the DENSO paper's 16 MB ROM. All figures measured side by side in one
// run, with the machine's load printed, on the shipped cluster package (the build converts it).
//
//   meter-budget-bench [--runs N] [--governed]
//
//  1. whole process `meter-view --scene cluster.msp --set Vehicle.Speed=100 --out DIR`, per backend
//     and MSAA, per cache state: cold (Mesa's shader cache and the program cache empty), Mesa's
//     cache only (the view before the program cache), both warm (a restart), none;
//  2. the same start-up split into its steps in a fresh child each run (medians), with the RSS after
//     each step: where the time and the memory go;
//  3. the governed run's peak RSS (--governed: meter-calibrate's cost file and a recorded drive first);
//  4. the installed runtime's size: stripped meter-view and meter-controller, cluster.msp.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_stats.hpp"
#include "process_run.hpp"
#include "start_up_steps.hpp"

namespace fs = std::filesystem;
using namespace meter::bench;

namespace {

struct Config {
  const char* backend;
  int msaa;
};
enum class Caches { Cold, MesaOnly, BothWarm, None };
const char* caches_name(Caches c) {
  switch (c) {
    case Caches::Cold: return "cold (both caches empty)";
    case Caches::MesaOnly: return "Mesa cache warm, no program cache";
    case Caches::BothWarm: return "Mesa cache + program cache warm";
    case Caches::None: return "no caches (MESA_SHADER_CACHE_DISABLE)";
  }
  return "";
}

struct Dirs {
  fs::path root, mesa, programs;
};

// The two cache directories for a run in state `c` (emptied for a cold run; filled by a first,
// uncounted run for a warm one).
Dirs cache_dirs(const fs::path& root, const Config& cfg, Caches c, int run) {
  const std::string tag = std::string(cfg.backend) + std::to_string(cfg.msaa);
  Dirs d{root, root / ("mesa-" + tag), root / ("programs-" + tag)};
  if (c == Caches::Cold) {
    d.mesa += "-cold" + std::to_string(run), d.programs += "-cold" + std::to_string(run);
    fs::remove_all(d.mesa), fs::remove_all(d.programs);
  }
  return d;
}

std::vector<std::string> view_argv(const fs::path& pkg, const Config& cfg, Caches c, const Dirs& d, const fs::path& out) {
  std::vector<std::string> argv{METER_VIEW_EXE, "--scene", pkg.string(), "--set", "Vehicle.Speed=100", "--out",
                                out.string(), "--backend", cfg.backend, "--msaa", std::to_string(cfg.msaa)};
  argv.insert(argv.end(), {"--program-cache", (c == Caches::Cold || c == Caches::BothWarm) ? d.programs.string() : "off"});
  return argv;
}

std::vector<std::string> mesa_env(Caches c, const Dirs& d) {
  if (c == Caches::None) return {"MESA_SHADER_CACHE_DISABLE=true"};
  return {"MESA_SHADER_CACHE_DIR=" + d.mesa.string(), "MESA_SHADER_CACHE_DISABLE"};
}

void print_range(const char* what, std::vector<double> v) {
  std::sort(v.begin(), v.end());
  std::printf(" %s %5.0f (%4.0f-%4.0f)", what, median(v), v.front(), v.back());
}

// Section 1: the whole process, per configuration and cache state.
bool whole_process(const fs::path& pkg, const fs::path& root, const std::vector<Config>& configs, int runs) {
  std::printf("\n## 1. process start -> first PNG / exit, ms median (min-max) of %d, peak RSS MiB\n", runs);
  for (const Config& cfg : configs) {
    for (Caches c : {Caches::Cold, Caches::None, Caches::MesaOnly, Caches::BothWarm}) {
      std::vector<double> png, exit;
      long peak = 0;
      for (int i = -1; i < runs; ++i) {  // run -1 fills the caches of a warm state, uncounted
        if (i < 0 && c == Caches::Cold) continue;
        const Dirs d = cache_dirs(root, cfg, c, i);
        const fs::path out = root / ("out-" + std::to_string(i));
        fs::remove_all(out);
        const ProcessRun r = run_process(view_argv(pkg, cfg, c, d, out), mesa_env(c, d), (out / "frame.png").string());
        if (!r.ok) {
          std::printf("meter-view failed (%s MSAA %d, %s)\n", cfg.backend, cfg.msaa, caches_name(c));
          return false;
        }
        if (i < 0) continue;
        png.push_back(r.to_png_ms), exit.push_back(r.to_exit_ms), peak = std::max(peak, r.peak_kib);
      }
      std::printf("%-6s MSAA %d  %-40s", cfg.backend, cfg.msaa, caches_name(c));
      print_range("PNG", png);
      print_range("exit", exit);
      std::printf("  RSS %.1f\n", double(peak) / 1024.0);
    }
  }
  return true;
}

// Section 2: the steps, medians over `runs` fresh children; the RSS table of the last state.
bool split(const fs::path& pkg, const fs::path& root, const std::vector<Config>& configs, int runs) {
  std::printf("\n## 2. where the start-up goes: each step's wall ms, median of %d fresh processes\n", runs);
  std::printf("%-16s %-34s", "", "caches");
  for (int s = 0; s < StartUpSteps::kSteps; ++s) std::printf(" %9.9s", step_name(s));
  std::printf(" %9s %9s\n", "programs", "sum");
  for (const Config& cfg : configs) {
    for (Caches c : {Caches::Cold, Caches::MesaOnly, Caches::BothWarm}) {
      std::vector<std::vector<double>> ms(StartUpSteps::kSteps);
      std::vector<double> programs, sum, gl_mips, cpu_mips;
      StartUpSteps last;
      for (int i = -1; i < runs; ++i) {
        if (i < 0 && c == Caches::Cold) continue;
        const Dirs d = cache_dirs(root, cfg, c, 100 + i);
        StartUpRun run{cfg.backend, cfg.msaa, pkg.string(), (root / "split.png").string(),
                       c == Caches::MesaOnly ? std::string() : d.programs.string(), d.mesa.string()};
        last = run_start_up_steps(run);
        if (!last.ok) {
          std::printf("the start-up steps failed (%s MSAA %d, %s)\n", cfg.backend, cfg.msaa, caches_name(c));
          return false;
        }
        if (i < 0) continue;
        double total = 0;
        for (int s = 0; s < StartUpSteps::kSteps; ++s) ms[s].push_back(last.ms[s]), total += last.ms[s];
        programs.push_back(last.program_ms), sum.push_back(total);
        gl_mips.push_back(last.gl_mips_ms), cpu_mips.push_back(last.cpu_mips_ms);
      }
      std::printf("%-6s MSAA %d     %-34.34s", cfg.backend, cfg.msaa, caches_name(c));
      for (int s = 0; s < StartUpSteps::kSteps; ++s) std::printf(" %9.1f", median(ms[s]));
      std::printf(" %9.1f %9.1f   mips: glGenerateMipmap %.1f, CPU chain %.1f\n", median(programs), median(sum),
                  median(gl_mips), median(cpu_mips));
      if (cfg.msaa == 4 && std::string(cfg.backend) == "egl" && c == Caches::BothWarm) {
        std::printf("\n### where the memory goes (EGL, MSAA 4, the cluster at 1280x480, warm caches; one process)\n");
        const double mib = 1024.0 * 1024.0;
        std::printf("RSS at the first step %.1f MiB (program, libraries)\n", double(last.rss_start_kib) / 1024.0);
        long before = last.rss_start_kib;
        for (int s = 0; s < StartUpSteps::kSteps; ++s) {
          std::printf("  %-44s RSS %7.1f MiB  (%+6.1f)\n", step_name(s), double(last.rss_kib[s]) / 1024.0,
                      double(last.rss_kib[s] - before) / 1024.0);
          before = last.rss_kib[s];
        }
        std::printf("peak (VmHWM) %.1f MiB; at the end RssAnon %.1f MiB (heap: meter's and the driver's buffers), "
                    "RssFile %.1f MiB (mapped libraries: LLVM, Mesa, ...)\n", double(last.peak_kib) / 1024.0,
                    double(last.anon_kib) / 1024.0, double(last.file_kib) / 1024.0);
        std::printf("known sizes: render target (MSAA samples + depth + resolved) %.1f MiB, the static layer "
                    "another target like it when built; textures %.1f MiB (uploaded, and the same RGBA still held "
                    "by the scene); package file %.1f MiB; %d programs (%d from kept binaries)\n",
                    last.target_bytes / mib, last.texture_bytes / mib, last.package_file_bytes / mib,
                    last.programs, last.programs_loaded);
      }
    }
  }
  return true;
}

int run_tool(const std::vector<std::string>& argv) {
  const ProcessRun r = run_process(argv, {}, "", true);
  return r.ok ? 0 : 1;
}

// Section 3: peak RSS of a recorded drive played at 1280x480 MSAA 4, ungoverned and governed.
bool governed(const fs::path& pkg, const fs::path& root) {
  std::printf("\n## 3. peak RSS playing the demo drive (20 s of it at 30 fps, EGL, MSAA 4), ungoverned and governed\n");
  const fs::path msp = root / "governed.msp", rec = root / "drive.rec";
  fs::copy_file(pkg, msp, fs::copy_options::overwrite_existing);
  if (run_tool({METER_CALIBRATE_EXE, msp.string(), "--backend", "egl", "-o", msp.string() + ".costs.json"}) != 0 ||
      run_tool({METER_CONTROLLER_EXE, "run", "--dbc", METER_SOURCE_DIR "/controller/vehicles/demo/demo.dbc", "--map",
                METER_SOURCE_DIR "/controller/vehicles/demo/demo.map", "--input",
                "log:" METER_SOURCE_DIR "/vcan/logs/demo-drive.log", "--replay", "fast", "--exit-at-end", "--record",
                rec.string(), "--link", "unix:" + (root / "rec.sock").string(), "--state-dir", (root / "state").string()}) != 0) {
    std::printf("governed: meter-calibrate or the recording failed\n");
    return false;
  }
  for (const bool gov : {false, true}) {
    std::vector<std::string> argv{METER_VIEW_EXE, "--scene", msp.string(), "--play", rec.string(), "--fps", "30",
                                  "--duration", "20", "--out", (root / "play").string()};
    if (gov) argv.insert(argv.end(), {"--target-ms", "33"});
    const ProcessRun r = run_process(argv, {}, "", true);
    std::printf("%-11s %s peak RSS %.1f MiB (goal <= 122 MiB = 128 MB), %.1f s\n", gov ? "governed" : "ungoverned",
                r.ok ? "" : "FAILED", double(r.peak_kib) / 1024.0, r.to_exit_ms / 1000.0);
  }
  return true;
}

// Section 4: the runtime's files as installed (stripped programs, the shipped package).
void sizes(const fs::path& pkg, const fs::path& root) {
  std::printf("\n## 4. installed runtime (stripped, not Mesa or system libraries) vs the DENSO paper's 16 MB ROM\n");
  double total = 0;
  for (const char* exe : {METER_VIEW_EXE, METER_CONTROLLER_EXE}) {
    const fs::path stripped = root / (fs::path(exe).filename().string() + ".stripped");
    if (run_tool({"/usr/bin/strip", "-o", stripped.string(), exe}) != 0) {
      std::printf("strip %s failed\n", exe);
      continue;
    }
    const double mb = double(fs::file_size(stripped)) / 1e6;
    std::printf("  %-24s %6.2f MB\n", stripped.filename().c_str(), mb);
    total += mb;
  }
  const double pkg_mb = double(fs::file_size(pkg)) / 1e6;
  std::printf("  %-24s %6.2f MB\n  total %.2f MB = %.0f %% of 16 MB\n", "cluster.msp", pkg_mb, total + pkg_mb,
              100.0 * (total + pkg_mb) / 16.0);
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 3;
  bool with_governed = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--governed") with_governed = true;
    else {
      std::fprintf(stderr, "usage: %s [--runs N] [--governed]\n", argv[0]);
      return 2;
    }
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each line as it is measured, also into a file
  const fs::path pkg = METER_BINARY_DIR "/deploy/scenes/cluster.msp";
  if (!fs::exists(pkg)) {
    std::fprintf(stderr, "%s missing: build the target meter_shipped_scene\n", pkg.c_str());
    return 1;
  }
  const fs::path root = fs::temp_directory_path() / ("meter_budget_bench_" + std::to_string(getpid()));
  fs::create_directories(root);
  double load[1] = {0};
  getloadavg(load, 1);
  std::printf("bench/budget: %ld cores, load average %.2f, %s, runs in %s\n", sysconf(_SC_NPROCESSORS_ONLN), load[0],
              pkg.c_str(), root.c_str());
  const std::vector<Config> configs{{"egl", 4}, {"egl", 1}, {"osmesa", 4}};
  bool ok = whole_process(pkg, root, configs, runs) && split(pkg, root, configs, runs);
  if (ok && with_governed) ok = governed(pkg, root);
  sizes(pkg, root);
  getloadavg(load, 1);
  std::printf("load average at the end %.2f\n", load[0]);
  fs::remove_all(root);
  return ok ? 0 : 1;
}
