// The platform benchmarks' main(): one optional argument, the frames per case, then the same
// measurement on EGL and on OSMesa in turn.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <exception>

#include "meter/platform/backend.hpp"

namespace meter::bench {

template <typename RunBackend>
int run_on_both_backends(int argc, char** argv, int default_frames, const char* name, RunBackend run_backend) {
  const int frames = argc > 1 ? std::atoi(argv[1]) : default_frames;
  if (frames <= 0) {
    std::fprintf(stderr, "usage: %s [frames > 0]\n", argv[0]);
    return 2;
  }
  try {
    run_backend(platform::BackendKind::Egl, frames);
    run_backend(platform::BackendKind::OSMesa, frames);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", name, e.what());
    return 1;
  }
  return 0;
}

}  // namespace meter::bench
