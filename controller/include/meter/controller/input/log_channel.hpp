// One channel of a multi-channel log as an input: "drive.blf#2" is channel 2 of drive.blf, so one
// file can feed several named inputs (--input body=log:drive.blf#1 --input chassis=log:drive.blf#2),
// each frame keeping the log's own timestamp.
#pragma once

#include <memory>
#include <string>

#include "meter/controller/input/log_source.hpp"

namespace meter::controller {

struct LogAddress {
  std::string path;
  int channel = 0;  // 0: every channel
};

// "FILE#N" (N 1..255) -> {FILE, N}; an address without a '#' and digits at its end, or one that
// names an existing file as it stands, is the whole file. Throws std::invalid_argument for "#0" or
// a channel beyond 255.
LogAddress parse_log_address(const std::string& address);

// A log:ADDRESS input: open_log_source() of the path, the frames of its channel (all of them for
// no channel). Throws std::runtime_error naming the file and the channels it holds when none is on
// the channel asked.
std::unique_ptr<LogSource> open_log_input(const std::string& address);

}  // namespace meter::controller
