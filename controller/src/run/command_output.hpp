// Text the subcommands write: numbers at full precision, CSV fields, the report of skipped log lines.
#pragma once

#include <ostream>
#include <string>
#include <string_view>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

std::string fmt_double(double v);  // %.15g
std::string csv_field(std::string_view s);  // quoted when it holds ',', '"' or a newline
// "<path>: skipped N bad line(s)" and the first ten with their line number and reason.
void report_bad_lines(const ParsedLog& log, const std::string& path, std::ostream& err);
// One line on err when the lenient DBC parse gave warnings: how many, the first, and the command
// that lists them all (check-dbc). Nothing for a clean file.
void report_dbc_warnings(const Database& db, std::ostream& err);
// load_dbc, or the DbcError printed to err and false (the commands then exit 1).
bool load_dbc_reporting(const std::string& path, Database& db, std::ostream& err);

}  // namespace meter::controller
