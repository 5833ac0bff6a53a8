#include "meter/protocol/log/log_record.hpp"

#include <array>

namespace meter::protocol {

namespace {
constexpr std::array<std::string_view, 4> kLevelNames{"error", "warning", "info", "debug"};
}  // namespace

std::optional<LogLevel> parse_log_level(std::string_view text) {
  for (std::size_t i = 0; i < kLevelNames.size(); ++i)
    if (text == kLevelNames[i]) return static_cast<LogLevel>(i);
  return std::nullopt;
}

std::string_view to_string(LogLevel level) { return kLevelNames[static_cast<std::size_t>(level)]; }

LogField log_field(std::string key, std::string value) { return LogField{std::move(key), std::move(value), false}; }
LogField log_field(std::string key, std::int64_t value) { return LogField{std::move(key), std::to_string(value), true}; }

void split_prefix(std::string_view line, std::string& prefix, std::string& message) {
  // "meter-controller: ...", "meter-protocol: ...", "meter: note: ...": a program's name, a colon, a space.
  std::size_t end = 0;
  if (line.starts_with("meter-") || line.starts_with("meter:")) {
    end = 5;
    while (end < line.size() && (line[end] == '-' || (line[end] >= 'a' && line[end] <= 'z'))) ++end;
    end = line.compare(end, 2, ": ") == 0 ? end + 2 : 0;
  }
  prefix.assign(line.substr(0, end));
  message.assign(line.substr(end));
}

}  // namespace meter::protocol
