// One meter-view process from fork to exit, as an integrator starts it: the time to the first PNG
// on disk (the frame drawn, resolved, read back and encoded), to exit, and the peak RSS.
#pragma once

#include <string>
#include <vector>

namespace meter::bench {

struct ProcessRun {
  double to_png_ms = -1, to_exit_ms = -1;
  long peak_kib = 0;  // ru_maxrss of the child
  bool ok = false;
};

// `argv[0]` is the program; `env` holds NAME=VALUE pairs set in the child (a NAME with no '='
// is unset); `png` is the file whose appearance marks the first frame (empty: none); `quiet` sends
// the child's output to /dev/null.
ProcessRun run_process(const std::vector<std::string>& argv, const std::vector<std::string>& env,
                       const std::string& png, bool quiet = false);

}  // namespace meter::bench
