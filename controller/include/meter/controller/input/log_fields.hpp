// The small pieces the text log formats (ASC, TRC) are made of: whitespace-separated fields,
// decimal times to nanoseconds, hex or decimal numbers; and the local wall time of a calendar date,
// which Vector's ASC and BLF files use for their start.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace meter::controller {

// The fields of a line (split at spaces and tabs) into `out`.
void split_log_fields(std::string_view line, std::vector<std::string_view>& out);

// "12.345678" in units of unit_ns nanoseconds (1e9: seconds, 1e6: milliseconds) -> nanoseconds,
// digits only, at most 9 fraction digits and 12 integer digits; nullopt otherwise.
std::optional<std::int64_t> parse_log_time(std::string_view text, std::int64_t unit_ns);

// An unsigned number in base 16 or 10, at most `max`; nullopt when not all digits or too large.
std::optional<std::uint32_t> parse_log_number(std::string_view text, int base, std::uint32_t max);

// Nanoseconds since the epoch of a local wall time (the machine's time zone, as Vector's tools
// write it), nullopt when the date does not exist.
std::optional<std::int64_t> local_time_ns(int year, int month, int day, int hour, int minute, int second,
                                          std::int64_t fraction_ns);

// The calendar fields of a local wall time, for writing: year, month 1..12, day, weekday 0..6
// (Sunday 0), hour, minute, second.
struct LocalTime {
  int year, month, day, weekday, hour, minute, second;
};
LocalTime local_time_of(std::int64_t seconds_since_epoch);

}  // namespace meter::controller
