// meter-view's offline start-up, step by step, in a fresh child process: what
// `meter-view --scene S --set Vehicle.Speed=100 --out DIR` does between main() and exit, each step
// timed and followed by the process's resident memory, so the whole-process figure can be split.
#pragma once

#include <string>

namespace meter::bench {

struct StartUpRun {
  std::string backend = "egl";  // egl | osmesa
  int msaa = 4;
  std::string package;          // cluster.msp
  std::string png;              // where the frame goes
  std::string program_cache;    // empty: off
  // Mesa's shader cache: a directory (MESA_SHADER_CACHE_DIR), or empty for MESA_SHADER_CACHE_DISABLE
  std::string mesa_cache;
};

// Wall milliseconds of each step and VmRSS (KiB) after it; VmHWM at the end.
struct StartUpSteps {
  enum Step { Backend, Package, Renderer, FirstFrame, Resolve, Readback, Png, kSteps };
  double ms[kSteps] = {};
  long rss_kib[kSteps] = {};
  long rss_start_kib = 0, peak_kib = 0;
  long anon_kib = 0, file_kib = 0;  // RssAnon (heap, driver buffers) and RssFile (mapped libraries) at the end
  double program_ms = 0;     // part of Renderer: the programs' compiles and links
  // After the PNG, the scene's first mipmapped texture once more: glGenerateMipmap's first call in
  // the process (what the renderer paid before the CPU chain) and the CPU chain (what it pays now).
  double gl_mips_ms = -1, cpu_mips_ms = -1;
  int programs = 0, programs_loaded = 0;
  // What the code knows it allocates (bytes): render targets (multisampled + resolved), the
  // scene's textures as uploaded, the same images still held by the CPU-side scene, the package file.
  double target_bytes = 0, texture_bytes = 0, package_file_bytes = 0;
  bool ok = false;
};

inline const char* step_name(int s) {
  static const char* names[] = {"EGL/OSMesa start", "package read", "renderer (targets, programs, uploads, text)",
                                "first frame drawn", "resolve", "readback", "PNG encode+write"};
  return names[s];
}

// Forks; the child sets the Mesa cache variables, runs the steps and reports through a pipe.
StartUpSteps run_start_up_steps(const StartUpRun& run);

}  // namespace meter::bench
