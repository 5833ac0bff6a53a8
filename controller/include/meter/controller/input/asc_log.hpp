// Vector ASC logs (the text format of CANoe / CANalyzer): the header (date, base hex|dec,
// timestamps absolute|relative, internal events), trigger blocks, classic CAN data and remote
// frames, CAN FD frames, error frames, on numbered channels. Events of other kinds (statistics, chip
// status, system variables, other buses) are passed over and counted; an unknown keyword is a bad
// line. Times are on the log's clock: the trigger block's (else the file's) start date, a local wall
// time, plus each event's offset.
#pragma once

#include <istream>
#include <memory>
#include <string_view>

#include "meter/controller/input/log_format.hpp"
#include "meter/controller/input/log_source.hpp"
#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

// The log a frame at a time, as run, decode and convert-log read it.
std::unique_ptr<LogSource> open_asc_log(std::istream& in);
// The whole log in memory (tests, fuzzers, benches).
ParsedLog parse_asc_log(std::string_view text);
ParsedLog read_asc_log(std::istream& in);

// True when one of the first lines of `head` is an ASC header line ("date ...", "base hex ...").
bool sniff_asc_log(std::string_view head);

// asc: recognised by its header lines, else by .asc.
const LogFormat& asc_log_format();

}  // namespace meter::controller
