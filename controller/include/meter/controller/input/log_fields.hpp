// The small pieces the text log formats (ASC, TRC) are made of: whitespace-separated fields,
// decimal times to nanoseconds, hex or decimal numbers; and the local wall time of a calendar date,
// which Vector's ASC and BLF files use for their start.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace meter::controller {

// The fields of a line (split at spaces and tabs) into `out`.
void split_log_fields(std::string_view line, std::vector<std::string_view>& out);

// "12.345678" in units of unit_ns nanoseconds (a power of ten: 1e9 seconds, 1e6 milliseconds) -> nanoseconds,
// digits only, at most 9 fraction digits and 12 integer digits; nullopt otherwise.
std::optional<std::int64_t> parse_log_time(std::string_view text, std::int64_t unit_ns);

// The value of a hex digit (0..15), else 16 and more.
inline constexpr std::array<std::uint8_t, 256> kLogDigitValue = [] {
  std::array<std::uint8_t, 256> v{};
  v.fill(99);
  for (int c = 0; c < 10; ++c) v[static_cast<std::size_t>('0' + c)] = static_cast<std::uint8_t>(c);
  for (int c = 0; c < 6; ++c) v[static_cast<std::size_t>('A' + c)] = v[static_cast<std::size_t>('a' + c)] = static_cast<std::uint8_t>(10 + c);
  return v;
}();

// An unsigned number in base 16 or 10, at most `max`; nullopt when not all digits or too large.
inline std::optional<std::uint32_t> parse_log_number(std::string_view text, int base, std::uint32_t max) {
  if (text.empty() || text.size() > 10) return std::nullopt;
  std::uint64_t v = 0;
  for (char c : text) {
    const unsigned d = kLogDigitValue[static_cast<unsigned char>(c)];
    if (d >= static_cast<unsigned>(base)) return std::nullopt;
    v = v * static_cast<std::uint64_t>(base) + d;
  }
  if (v > max) return std::nullopt;
  return static_cast<std::uint32_t>(v);
}

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
