// meter-preview's reload of the cluster (scenes/cluster), the conversion part, measured side by
// side in one run: cold (a fresh program cache: every program optimized, as every reload did
// before the cache) against cached (the cache kept across reloads, as the preview keeps it: a
// config save re-optimizes nothing). Both convert the same files through preview::convert_scene
// and must give the same programs. Prints the medians of thread CPU time (the machine may be
// shared: wall time follows its load, CPU time does not) and of wall time, and their ratios.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "meter/preview/scene_reloader.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/shadergen/program_cache.hpp"
#include "bench_stats.hpp"

using meter::bench::median;

namespace {

double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) / 1e6;
}


struct Sample {
  std::vector<double> cpu_ms, wall_ms;
};

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 7;
  const std::string dir = std::string(METER_SOURCE_DIR) + "/scenes/cluster/";
  const meter::preview::SceneFiles files{dir + "cluster.glb", dir + "cluster.scene.json"};
  const auto catalog = meter::protocol::active_catalog();
  meter::shadergen::ProgramCache kept;  // the preview's, across reloads
  meter::preview::convert_scene(files, *catalog, &kept);  // the first load fills it
  Sample cold, cached;
  auto measure = [&](Sample& into, meter::shadergen::ProgramCache& cache) {
    const double c0 = thread_cpu_ms();
    const auto w0 = std::chrono::steady_clock::now();
    const auto scene = meter::preview::convert_scene(files, *catalog, &cache);
    into.wall_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count());
    into.cpu_ms.push_back(thread_cpu_ms() - c0);
    return scene->programs.size();
  };
  for (int i = 0; i < runs; ++i) {  // interleaved, so both see the same machine
    meter::shadergen::ProgramCache fresh;
    const std::size_t a = measure(cold, fresh);
    const std::size_t b = measure(cached, kept);
    if (a != b) {
      std::fprintf(stderr, "reload_bench: cold and cached conversions differ (%zu vs %zu programs)\n", a, b);
      return 1;
    }
  }
  std::printf("cluster reload, conversion (%d runs each, medians)  cold        cached      cold/cached\n", runs);
  std::printf("  CPU time (this thread)                          %7.1f ms  %7.1f ms  %6.2fx\n", median(cold.cpu_ms),
              median(cached.cpu_ms), median(cold.cpu_ms) / median(cached.cpu_ms));
  std::printf("  wall time                                       %7.1f ms  %7.1f ms  %6.2fx\n", median(cold.wall_ms),
              median(cached.wall_ms), median(cold.wall_ms) / median(cached.wall_ms));
  std::printf("  program cache: %zu programs, %zu hits, %zu misses\n", kept.size(), kept.hits(), kept.misses());
  return 0;
}
