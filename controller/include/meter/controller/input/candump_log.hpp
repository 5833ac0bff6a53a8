// A whole candump -L log file (can-utils): the frames it holds and the lines that break the
// grammar. The first log format of log_format.hpp. Its interfaces (can0, can1, ...) are the log's
// channels, numbered 1, 2, ... in the order they first appear.
#pragma once

#include <istream>
#include <memory>
#include <string>
#include <string_view>

#include "meter/controller/input/log_format.hpp"
#include "meter/controller/input/log_source.hpp"
#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

// The log a frame at a time, as run, decode and convert-log read it.
std::unique_ptr<LogSource> open_candump_log(std::istream& in);
// The whole log in memory (tests, fuzzers, benches).
ParsedLog parse_candump_log(std::string_view text);
ParsedLog read_candump_log(std::istream& in);
ParsedLog load_candump_log(const std::string& path);  // throws std::runtime_error if unreadable

// True when one of the first complete, non-blank lines of `head` is a candump -L line.
bool sniff_candump_log(std::string_view head);

// The frames as candump -L lines, channel N on the interface can<N-1> (no channel: can0).
std::size_t write_candump_log(LogSource& frames, std::ostream& out, const LogProgress& progress);
std::string candump_interface(const CanFrame& frame);

// candump: recognised by its lines ("(1631416514.717133) can0 0D2#0000FFFF10000000"), else by .log.
const LogFormat& candump_log_format();

}  // namespace meter::controller
