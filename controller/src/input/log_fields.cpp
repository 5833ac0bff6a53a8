// Fields, times and numbers of the text log formats; local wall times of Vector's start dates.
#include "meter/controller/input/log_fields.hpp"

#include <bit>
#include <cstdint>
#include <cstring>
#include <ctime>

namespace meter::controller {

namespace {

void split_fields(std::string_view line, std::vector<std::string_view>& out);

bool is_separator(char c) { return c == ' ' || c == '\t'; }

// Where the line's trailing run of two-character fields one separator apart starts (a log line's
// data bytes, "00 1F FF"): those fields are taken by their stride, without scanning each byte.
std::size_t pair_run_start(std::string_view line) {
  std::size_t run = line.size(), end = line.size();  // end: of the next two characters asked
  while (end >= 2 && !is_separator(line[end - 1]) && !is_separator(line[end - 2]) && (end == 2 || is_separator(line[end - 3]))) {
    run = end - 2;
    if (end < 3) break;
    end -= 3;
  }
  return run;
}

// 0x80 in each byte of `x` that is zero, nothing elsewhere (exact: no byte borrows from another).
constexpr std::uint64_t zero_bytes(std::uint64_t x) {
  constexpr std::uint64_t k7f = 0x7F7F7F7F7F7F7F7FULL;
  return ~(((x & k7f) + k7f) | x | k7f);
}

}  // namespace

// The fields before the data bytes by split_fields(), the data bytes by their stride.
void split_log_fields(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  const std::size_t run = pair_run_start(line);
  split_fields(line.substr(0, run), out);
  for (std::size_t at = run; at + 2 <= line.size(); at += 3) out.emplace_back(line.data() + at, 2);
}

namespace {

// Eight bytes at a time: the separators (spaces and tabs) of a word as a mask, the fields' starts and
// ends as that mask's edges. Fields and separators alternate, so the n-th end closes the n-th field
// still open: starts and ends are taken in two loops without a branch on which edge comes next.
// The text logs' lines are mostly short fields between runs of padding, where a byte-by-byte scan
// mispredicts at every edge.
void split_fields(std::string_view line, std::vector<std::string_view>& out) {
  const char* const base = line.data();
  const std::size_t n = line.size();
  std::size_t open = 0, i = 0;  // out[open] is the first field whose end is not known yet
  const auto close = [&](const char* end) {
    out[open] = std::string_view(out[open].data(), static_cast<std::size_t>(end - out[open].data()));
    ++open;
  };
  if constexpr (std::endian::native == std::endian::little) {
    constexpr std::uint64_t kSpaces = 0x2020202020202020ULL, kTabs = 0x0909090909090909ULL, kHigh = 0x8080808080808080ULL;
    for (; i + 8 <= n; i += 8) {
      std::uint64_t w;
      std::memcpy(&w, base + i, 8);
      const std::uint64_t sep = zero_bytes(w ^ kSpaces) | zero_bytes(w ^ kTabs);
      const std::uint64_t text = ~sep & kHigh;
      const bool in_field = out.size() > open;
      const std::uint64_t starts = text & ((sep << 8) | (in_field ? 0 : 0x80)), ends = sep & ((text << 8) | (in_field ? 0x80 : 0));
      for (std::uint64_t s = starts; s; s &= s - 1) out.emplace_back(base + i + (std::countr_zero(s) >> 3), 0);
      for (std::uint64_t e = ends; e; e &= e - 1) close(base + i + (std::countr_zero(e) >> 3));
    }
  }
  for (; i < n; ++i) {
    const bool sep = base[i] == ' ' || base[i] == '\t';
    if (!sep && out.size() == open) out.emplace_back(base + i, 0);
    if (sep && out.size() > open) close(base + i);
  }
  if (out.size() > open) close(base + n);
}

}  // namespace

std::optional<std::int64_t> parse_log_time(std::string_view text, std::int64_t unit_ns) {
  std::size_t dot = 0;  // the fields are short: a loop, not a call to memchr
  while (dot < text.size() && text[dot] != '.') ++dot;
  const std::string_view whole = text.substr(0, dot);
  const std::string_view fraction = dot == text.size() ? std::string_view() : text.substr(dot + 1);
  if (whole.empty() || whole.size() > 12 || fraction.size() > 9 || (dot != text.size() && fraction.empty()))
    return std::nullopt;
  std::int64_t value = 0;
  for (char c : whole) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + (c - '0');
  }
  // The fraction's digits as one number, scaled once; digits below a nanosecond add nothing (the
  // units are powers of ten, so one truncating division equals truncating each digit's share).
  static constexpr std::int64_t kPow10[] = {1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000, 1000000000};
  std::int64_t digits = 0;
  for (char c : fraction) {
    if (c < '0' || c > '9') return std::nullopt;
    digits = digits * 10 + (c - '0');
  }
  std::size_t unit_digits = 0;  // unit_ns = 10^unit_digits
  while (unit_digits < 9 && kPow10[unit_digits] < unit_ns) ++unit_digits;
  const std::int64_t part = fraction.size() <= unit_digits ? digits * kPow10[unit_digits - fraction.size()]  // no division
                                                           : digits * unit_ns / kPow10[fraction.size()];
  std::int64_t ns = 0;
  if (__builtin_mul_overflow(value, unit_ns, &ns) || ns > 9000000000LL * 1000000000LL) return std::nullopt;  // beyond the nanosecond clock
  return ns + part;
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
