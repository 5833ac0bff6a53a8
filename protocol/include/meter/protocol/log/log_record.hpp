// One log record: an event of either process as plain data (time, level, component, message and
// the fields that apply: signal, file, line, input, frame ...), before any sink formats it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace meter::protocol {

// The levels, most severe first: a threshold passes its own level and every more severe one.
enum class LogLevel { Error, Warning, Info, Debug };

// "error", "warning", "info", "debug"; nothing for any other text.
std::optional<LogLevel> parse_log_level(std::string_view text);
std::string_view to_string(LogLevel level);
// Whether a record of `level` is written when the threshold is `threshold`.
constexpr bool level_passes(LogLevel level, LogLevel threshold) { return level <= threshold; }

// A field's value; numbers stay numbers in the JSON form.
struct LogField {
  std::string key;    // lower case: signal, file, line, input, frame, region, fault ...
  std::string value;
  bool number = false;
};
LogField log_field(std::string key, std::string value);
LogField log_field(std::string key, std::int64_t value);

struct LogRecord {
  std::int64_t time_ns = 0;  // CLOCK_REALTIME, nanoseconds since the epoch
  LogLevel level = LogLevel::Info;
  std::string component;     // the part of the program it comes from: run, health, link, integrity ...
  std::string prefix;        // what the plain-text line puts before the message ("meter-view: "), kept
                             // as today's wording; empty for lines that never had one
  std::string message;       // the event in words, without the prefix
  std::vector<LogField> fields;
  std::string code_file;     // the source position that wrote it (journal CODE_FILE / CODE_LINE)
  int code_line = 0;
};

// Splits a line as the programs wrote it into its "meter-...: " prefix and the message.
void split_prefix(std::string_view line, std::string& prefix, std::string& message);

}  // namespace meter::protocol
