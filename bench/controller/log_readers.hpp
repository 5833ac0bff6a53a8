// The log readers' speed, measured side by side in one run: meter's candump, ASC, BLF and TRC
// readers and python-can's on the same files (the ft86 drive written by python-can's writers).
#pragma once

#include <string>

// Prints frames/s of each reader, the ratio to python-can (goal >= 20x) and BLF's to candump's
// (goal within 3x). Returns non-zero when python-can could not be run.
int bench_log_readers(const std::string& candump_log);
