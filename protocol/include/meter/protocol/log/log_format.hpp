// The record's forms, pure: the plain-text line on stderr (today's wording), one JSON object per
// line (--log json, read by meter-fleet), the journal's fields (--log journal) and DLT's ids.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "meter/protocol/log/log_record.hpp"

namespace meter::protocol {

// prefix + message, exactly the line the programs wrote before records existed (no newline).
std::string format_text(const LogRecord& r);

// {"time":"2026-12-06T09:50:01.123456Z","level":"warning","program":"meter-controller",
//  "component":"health","message":"...", then each field by its key}; no newline. Invalid UTF-8
// in any text is replaced (U+FFFD), never dropped.
std::string format_json(const LogRecord& r, std::string_view program);

// syslog priorities the journal files a record under: error 3, warning 4, info 6, debug 7.
int journal_priority(LogLevel level);
// "MESSAGE=...", "PRIORITY=n", "SYSLOG_IDENTIFIER=program", "CODE_FILE=", "CODE_LINE=" (when the
// record has a source position), "METER_COMPONENT=", then "METER_<KEY>=value" per field.
std::vector<std::string> journal_fields(const LogRecord& r, std::string_view program);

// DLT application id of a program (MCTL meter-controller, MVEW meter-view, MTOL the tools) and
// context id of a component (docs/logging.md has the table); ids are at most 4 characters.
std::string dlt_app_id(std::string_view program);
std::string dlt_context_id(std::string_view component);

}  // namespace meter::protocol
