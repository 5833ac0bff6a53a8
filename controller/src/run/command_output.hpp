// Text the subcommands write: numbers at full precision, CSV fields, the report of skipped log lines.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/log_source.hpp"

namespace meter::controller {

std::string fmt_double(double v);  // %.15g
std::string hex(std::uint32_t v);  // 0x1A4: a CAN id, STATUS flags
std::string csv_field(std::string_view s);  // quoted when it holds ',', '"' or a newline
// A log's bad lines on err as the reading meets them (a streamed log's are not all known before it
// is replayed): "<path>: bad line(s) skipped:" once, then the first ten with their line number and
// reason ("  <path>:L: why"), those read before its first frame at once; the rest are counted.
// `err` must outlive the source.
void report_bad_lines(LogSource& log, const std::string& path, std::ostream& err);
// "<path>: skipped N bad line(s)" for a log read to its end, if it had any.
void report_bad_line_count(const LogSource& log, const std::string& path, std::ostream& err);
// One line on err when the lenient DBC parse gave warnings: how many, the first, and the command
// that lists them all (check-dbc). Nothing for a clean file.
void report_dbc_warnings(const Database& db, std::ostream& err);
// load_dbc, or the DbcError printed to err and false (the commands then exit 1).
bool load_dbc_reporting(const std::string& path, Database& db, std::ostream& err);

}  // namespace meter::controller
