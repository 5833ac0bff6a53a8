// meter-controller convert-log: a recorded CAN log in any format this build reads, written as
// candump -L, Vector ASC or Vector BLF, so a drive can be handed to other tools.
#pragma once

#include <iosfwd>
#include <string>

namespace meter::controller {

struct ConvertLogOptions {
  std::string in;      // FILE or FILE#N (channel N only)
  std::string out;     // the file written
  std::string format;  // candump | asc | blf; empty: by the extension of `out` (.log, .asc, .blf)
  bool progress = false;  // a progress line on err while writing (meter-controller: when err is a terminal)
};

// Reads `in` (bad records reported as decode reports them; no usable frame is an error), writes
// its frames to `out` in the chosen format and prints one summary line on `out_text`. Returns 0,
// or 1 with the reason on err (unreadable input, unknown output format, `out` the input itself, a
// write error).
int convert_log_command(const ConvertLogOptions& options, std::ostream& out_text, std::ostream& err);

}  // namespace meter::controller
