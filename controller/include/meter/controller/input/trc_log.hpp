// PEAK PCAN trace files (.trc, PCAN-View and PCAN-Basic): file versions 1.0, 1.1, 1.2, 1.3, 2.0 and
// 2.1, told by the ";$FILEVERSION=" line (none: 1.0); version 2 files by their ";$COLUMNS=" line, or
// their version's default columns. Data and remote frames (2.x: CAN FD with BRS/ESI too) and error
// frames are kept; status, error-counter and event lines are passed over and counted; a line with
// the wrong column count is a bad line. Times are the trace's own offsets (milliseconds from its
// start); the bus column (1.2 and later) is the frame's channel, else channel 1.
#pragma once

#include <istream>
#include <memory>
#include <string_view>

#include "meter/controller/input/log_format.hpp"
#include "meter/controller/input/log_source.hpp"
#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

// The trace a frame at a time, as run, decode and convert-log read it.
std::unique_ptr<LogSource> open_trc_log(std::istream& in);
// The whole trace in memory (tests, fuzzers, benches).
ParsedLog read_trc_log(std::istream& in);

// True when the head has a ";$FILEVERSION=" line, or one of its first lines is a 1.0 / 1.1
// message line ("     1)      1841  0001  8  00 ...").
bool sniff_trc_log(std::string_view head);

// trc: recognised by its lines, else by .trc.
const LogFormat& trc_log_format();

}  // namespace meter::controller
