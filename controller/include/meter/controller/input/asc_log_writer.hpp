// Writes frames as a Vector ASC log, the form CANoe and python-can read.
#pragma once

#include <ostream>

#include "meter/controller/input/log_format.hpp"
#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

// "base hex timestamps absolute", one trigger block dated at the first frame's millisecond (local
// wall time, 12-hour clock as CANoe writes it), every frame's time in microseconds from there;
// classic frames as "<ch> <id>[x] Rx d <dlc> <bytes>", remote "r <dlc>", CAN FD as CANFD lines with
// their BRS/ESI bits and flags, error frames as "<ch> ErrorFrame". A frame without a channel goes
// on channel 1.
// Returns the frames written.
std::size_t write_asc_log(LogSource& frames, std::ostream& out, const LogProgress& progress);

}  // namespace meter::controller
