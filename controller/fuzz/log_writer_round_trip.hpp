// What the ASC and BLF fuzz targets check after reading: the frames written by the format's own
// writer read back as the same frames (error frames by their channel: the formats keep no class).
#pragma once

#include <cstdlib>
#include <sstream>

#include "fixed_vehicle.hpp"
#include "meter/controller/input/log_format.hpp"

namespace meter::controller::fuzz {

inline void expect_written_log_reads_back(const ParsedLog& log, const LogFormat& format) {
  std::stringstream out;
  ParsedLogSource frames(log);
  format.write(frames, out, [](std::size_t) {});
  std::istringstream in(out.str());
  const ParsedLog back = read_whole_log(*format.open(in));
  if (!back.bad_lines.empty() || back.frames.size() != log.frames.size()) std::abort();
  for (std::size_t i = 0; i < log.frames.size(); ++i) {
    CanFrame want = log.frames[i];
    if (want.channel == 0) want.channel = 1;  // the writers put a frame without a channel on channel 1
    if (!same_logged_frame(back.frames[i], want, false)) std::abort();
  }
}

}  // namespace meter::controller::fuzz
