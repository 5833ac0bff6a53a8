// Fields, times and numbers of the text log formats; local wall times of Vector's start dates.
#include "meter/controller/input/log_fields.hpp"

#include <ctime>

namespace meter::controller {

void split_log_fields(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  const char* p = line.data();
  const char* const end = p + line.size();
  for (;;) {
    while (p != end && (*p == ' ' || *p == '\t')) ++p;
    if (p == end) return;
    const char* start = p;
    while (p != end && *p != ' ' && *p != '\t') ++p;
    out.emplace_back(start, static_cast<std::size_t>(p - start));
  }
}

std::optional<std::int64_t> parse_log_time(std::string_view text, std::int64_t unit_ns) {
  const std::size_t dot = text.find('.');
  const std::string_view whole = text.substr(0, dot);
  const std::string_view fraction = dot == std::string_view::npos ? std::string_view() : text.substr(dot + 1);
  if (whole.empty() || whole.size() > 12 || fraction.size() > 9 || (dot != std::string_view::npos && fraction.empty()))
    return std::nullopt;
  std::int64_t value = 0;
  for (char c : whole) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + (c - '0');
  }
  std::int64_t part = 0, scale = unit_ns;
  for (char c : fraction) {
    if (c < '0' || c > '9') return std::nullopt;
    scale /= 10;  // digits below a nanosecond add nothing
    part += (c - '0') * scale;
  }
  if (value > 9000000000LL * 1000000000LL / unit_ns) return std::nullopt;  // beyond the nanosecond clock
  return value * unit_ns + part;
}

std::optional<std::int64_t> local_time_ns(int year, int month, int day, int hour, int minute, int second,
                                          std::int64_t fraction_ns) {
  if (year < 1970 || year > 2262 || month < 1 || month > 12 || day < 1 || day > 31 || hour < 0 || hour > 23 ||
      minute < 0 || minute > 59 || second < 0 || second > 60)
    return std::nullopt;
  std::tm tm{};
  tm.tm_year = year - 1900;
  tm.tm_mon = month - 1;
  tm.tm_mday = day;
  tm.tm_hour = hour;
  tm.tm_min = minute;
  tm.tm_sec = second;
  tm.tm_isdst = -1;  // as the zone says for that date
  const std::time_t t = std::mktime(&tm);
  if (t == static_cast<std::time_t>(-1) || tm.tm_mday != day) return std::nullopt;  // e.g. 31 February
  std::int64_t ns = 0;
  if (__builtin_mul_overflow(static_cast<std::int64_t>(t), 1000000000LL, &ns) || __builtin_add_overflow(ns, fraction_ns, &ns))
    return std::nullopt;  // beyond the nanosecond clock (April 2262)
  return ns;
}

LocalTime local_time_of(std::int64_t seconds_since_epoch) {
  const std::time_t t = static_cast<std::time_t>(seconds_since_epoch);
  std::tm tm{};
  ::localtime_r(&t, &tm);
  return {tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_wday, tm.tm_hour, tm.tm_min, tm.tm_sec};
}

}  // namespace meter::controller
