// Writes frames as a Vector BLF log, the form CANoe and python-can read.
#pragma once

#include <ostream>

#include "meter/controller/input/log_format.hpp"
#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

// The 144-byte file header (start and stop as local wall times to the millisecond, sizes and the
// object count, written last: `out` must be seekable), then zlib log containers of about 128 KiB of
// objects each: CAN_MESSAGE for classic data and remote frames, CAN_FD_MESSAGE for CAN FD,
// CAN_ERROR_EXT for error frames; object times in nanoseconds from the first frame's millisecond.
// A frame without a channel goes on channel 1.
// Returns the frames written.
std::size_t write_blf_log(LogSource& frames, std::ostream& out, const LogProgress& progress);

}  // namespace meter::controller
